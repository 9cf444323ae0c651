#!/usr/bin/env bash
# The browser tests of glint serve (tests/browser/serve.test.cjs), as CTest
# runs them: Debian's chromium driven by playwright-core, installed with
# `npm ci` from the lock file into the build folder. Exit 77 (skipped) when
# chromium, node or glint serve is missing.
# usage: run.sh GLINT SOURCE_DIR WORK_DIR [node --test options...]
set -euo pipefail
glint=$1 source=$2 work=$3
shift 3
for tool in /usr/bin/chromium node npm; do
  command -v "$tool" >/dev/null || { echo "skipped: $tool not found (scripts/install-deps.sh)"; exit 77; }
done
"$glint" serve --help >/dev/null 2>&1 || { echo "skipped: glint built without glint serve (cpp-httplib)"; exit 77; }
mkdir -p "$work"
cp "$source/tests/browser/package.json" "$source/tests/browser/package-lock.json" "$work/"
# Never a browser download: playwright-core has no install script, and this says so twice.
export PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 PLAYWRIGHT_BROWSERS_PATH=0
if ! cmp -s "$work/package-lock.json" "$work/node_modules/.package-lock.json.installed" 2>/dev/null; then
  (cd "$work" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error)
  cp "$work/package-lock.json" "$work/node_modules/.package-lock.json.installed"
fi
export NODE_PATH="$work/node_modules" GLINT="$glint" GLINT_SOURCE_DIR="$source" GLINT_WORK_DIR="$work"
exec node --test --test-concurrency=1 "$@" "$source/tests/browser/serve.test.cjs"
