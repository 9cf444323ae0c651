#!/usr/bin/env bash
# One command to build glint and run every test (what CI runs: .ci/run).
# Installs what is missing (scripts/install-deps.sh test), then two halves:
#  1. Release with warnings as errors (GCC), in build/ (scripts/build-release.sh,
#     as scripts/setup.sh builds it), so whatever setup built is reused.
#  2. clang with AddressSanitizer + UndefinedBehaviorSanitizer, asserts on and
#     warnings as errors, in build-asan/ (scripts/build-sanitized.sh): the
#     suite again, then every fuzz target over its seeds and regressions and a
#     short mutation run (scripts/fuzz.sh smoke).
# docs/testing.md says what each half costs.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh test

scripts/build-release.sh
ctest --test-dir build --output-on-failure --no-tests=error -j "$(nproc)"

# InstallAndBuildExample is left to the Release half: it builds an
# unsanitized consumer against the installed (sanitized) library.
scripts/build-sanitized.sh
ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_init_order=1:check_initialization_order=1}" \
UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
  ctest --test-dir build-asan --output-on-failure --no-tests=error -j "$(nproc)" -E '^InstallAndBuildExample$'
scripts/fuzz.sh smoke
