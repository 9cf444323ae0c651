#!/usr/bin/env bash
# One command from a fresh Debian machine to a rendered picture: installs the
# packages building and rendering need (scripts/install-deps.sh build), builds
# the glint program in Release, and renders scenes/showcase.json to showcase.png.
# build/ is configured by scripts/build-release.sh, as scripts/test.sh's is
# (warnings as errors included), so the tests later reuse every object built here.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build
scripts/build-release.sh glint_cli
build/glint render scenes/showcase.json -o showcase.png
echo "rendered $(pwd)/showcase.png"
