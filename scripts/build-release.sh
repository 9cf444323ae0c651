#!/usr/bin/env bash
# Configures build/ (Release, warnings as errors) and builds the targets given,
# or everything: scripts/build-release.sh [TARGET...]. scripts/setup.sh and
# scripts/test.sh both build through it, so the flags are the same and the
# tests reuse every object setup built.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLINT_WERROR=ON
if [ $# -gt 0 ]; then
  cmake --build build --target "$@"
else
  cmake --build build
fi
