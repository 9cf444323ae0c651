#!/usr/bin/env bash
# One command to build glint and run every test (installs missing packages first).
# Both builds treat warnings as errors (GLINT_WERROR).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DGLINT_WERROR=ON
cmake --build build
ctest --test-dir build --output-on-failure -j "$(nproc)"

# The same suite again under AddressSanitizer + UndefinedBehaviorSanitizer
# (portable code, no -march=native): any memory error, leak or UB fails it.
# -Og instead of RelWithDebInfo's -O2: GCC optimizing instrumented code is
# what costs (-O2 ~2.6x, -O1 ~1.6x the -Og build time on 2 cores) while the
# tests run as fast. InstallAndBuildExample is left to the Release run above:
# it builds an unsanitized consumer against the installed (sanitized) library.
cmake -S . -B build-asan -G Ninja -DGLINT_SANITIZE=ON -DGLINT_NATIVE=OFF -DGLINT_WERROR=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-Og -g -DNDEBUG" \
  -DGLINT_BUILD_BENCH=OFF
cmake --build build-asan
ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_init_order=1:check_initialization_order=1}" \
UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -E '^InstallAndBuildExample$'
