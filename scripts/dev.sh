#!/usr/bin/env bash
# The developer's quick loop: rebuilds build-dev/ incrementally and runs the
# fast tests (everything but the ones labelled slow: pip, install, browser,
# MPI), or the tests whose names match a regular expression:
#   scripts/dev.sh                  # build, then the fast tests
#   scripts/dev.sh 'MeshBvh|Obj'    # build, then only those
# build-dev/ is Release without link-time optimization: a one-file change
# relinks in seconds. The first run builds it whole (a few minutes).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build-dev -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLINT_WERROR=ON -DGLINT_LTO=OFF >/dev/null
cmake --build build-dev
if [ $# -gt 0 ]; then
  ctest --test-dir build-dev --output-on-failure --no-tests=error -j "$(nproc)" -R "$1"
else
  ctest --test-dir build-dev --output-on-failure --no-tests=error -j "$(nproc)" -LE slow
fi
