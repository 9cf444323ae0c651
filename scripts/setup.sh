#!/usr/bin/env bash
# One command from a fresh Debian machine to a rendered picture: installs the
# packages building and rendering need (scripts/install-deps.sh build), builds
# the glint program in Release, and renders scenes/showcase.json to showcase.png.
# build/ is configured exactly as scripts/test.sh configures it (warnings as
# errors included), so the tests later reuse every object built here.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh build
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLINT_WERROR=ON
cmake --build build --target glint_cli
build/glint render scenes/showcase.json -o showcase.png
echo "rendered $(pwd)/showcase.png"
