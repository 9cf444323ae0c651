#!/usr/bin/env bash
# Configures and builds build-asan/: the whole tree with clang, under
# AddressSanitizer and UndefinedBehaviorSanitizer, asserts on, warnings as
# errors, and the libFuzzer targets (fuzz/) in the same configuration.
# scripts/test.sh runs the suite from it, scripts/fuzz.sh its fuzz targets:
# one compile serves both, and proves clang builds glint warning-clean.
# The library is compiled -O1 (the suite runs its renders and brute-force
# checks), the rest -O0 (about twice as fast to compile; CMakeLists.txt).
# Portable code (no -march=native). The benchmarks are compiled (so a change
# that breaks them is red) but not run.
set -euo pipefail
cd "$(dirname "$0")/.."
CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DGLINT_SANITIZE=ON -DGLINT_FUZZ=ON \
  -DGLINT_NATIVE=OFF -DGLINT_WERROR=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O0 -gline-tables-only" >/dev/null
cmake --build build-asan --target all benchmarks
