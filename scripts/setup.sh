#!/usr/bin/env bash
# One command from a fresh Debian machine to a rendered picture: installs what is
# missing, builds glint in Release, and renders the showcase scene to showcase.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
build/glint render scenes/showcase.json -o showcase.png
echo "rendered $(pwd)/showcase.png"
