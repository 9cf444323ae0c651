#!/usr/bin/env bash
# Fuzzes glint's input readers with libFuzzer: scripts/fuzz.sh [MINUTES] [TARGET...]
# Each target (default: all, see fuzz/README.md) runs MINUTES (default 5) in
# turn, one job at a time, from the seed corpus and the dictionary. Exits
# non-zero if any target found a crash, leak, timeout or out-of-memory; the
# input that did it is left in build-fuzz/findings/<target>/.
set -euo pipefail
cd "$(dirname "$0")/.."
MINUTES="${1:-5}"
shift || true
TARGETS=("$@")
if [ ${#TARGETS[@]} -eq 0 ]; then
  TARGETS=(fuzz_scene_loader fuzz_json fuzz_nff)
  [ -f src/glint/io/mesh_file.h ] && TARGETS+=(fuzz_mesh_obj fuzz_mesh_ply fuzz_mesh_gltf fuzz_mesh_glb)
fi
case "$MINUTES" in ''|*[!0-9.]*) echo "usage: scripts/fuzz.sh [MINUTES] [TARGET...]" >&2; exit 2;; esac

# clang and its compiler-rt (libFuzzer, ASan, UBSan), with everything else glint needs.
scripts/install-deps.sh clang libclang-rt-dev

# Asserts stay on (no NDEBUG): a broken precondition is a finding too.
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DGLINT_FUZZ=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" \
  -DGLINT_NATIVE=OFF -DGLINT_BUILD_TESTS=OFF -DGLINT_BUILD_BENCH=OFF >/dev/null
cmake --build build-fuzz --target "${TARGETS[@]}"

SECONDS_PER_TARGET=$(awk -v m="$MINUTES" 'BEGIN { s = int(m * 60); print (s < 1 ? 1 : s) }')
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
failed=()
for target in "${TARGETS[@]}"; do
  dict=fuzz/scene.dict
  case "$target" in
    fuzz_scene_loader) seeds=(fuzz/corpus/scene) ;;
    fuzz_json) seeds=(fuzz/corpus/json fuzz/corpus/scene) ;;
    fuzz_nff) seeds=(fuzz/corpus/nff); dict=fuzz/nff.dict ;;
    fuzz_mesh_obj) seeds=(fuzz/corpus/obj); dict=fuzz/mesh.dict ;;
    fuzz_mesh_ply) seeds=(fuzz/corpus/ply); dict=fuzz/mesh.dict ;;
    fuzz_mesh_gltf) seeds=(fuzz/corpus/gltf); dict=fuzz/gltf.dict ;;
    fuzz_mesh_glb) seeds=(fuzz/corpus/glb); dict=fuzz/gltf.dict ;;
    *) echo "unknown target $target" >&2; exit 2 ;;
  esac
  # New inputs go to a corpus kept in the build dir (the first directory);
  # the seeds in the repository are only read.
  corpus="build-fuzz/corpus/$target"
  findings="build-fuzz/findings/$target"
  mkdir -p "$corpus" "$findings"
  echo "== $target: ${SECONDS_PER_TARGET}s" >&2
  if ! "build-fuzz/fuzz/$target" -max_total_time="$SECONDS_PER_TARGET" -max_len=65536 \
       -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 -dict="$dict" \
       -artifact_prefix="$findings/" "$corpus" "${seeds[@]}"; then
    echo "== $target FOUND A PROBLEM: input in $findings/ (see fuzz/README.md to reproduce)" >&2
    failed+=("$target")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found problems in: ${failed[*]}" >&2
  exit 1
fi
echo "fuzzing found nothing (${TARGETS[*]}, ${MINUTES} min each)" >&2
