#!/usr/bin/env bash
# Fuzzes glint's input readers with libFuzzer (see fuzz/README.md):
#   scripts/fuzz.sh smoke                  every target over its seeds and fuzz/regressions/,
#                                          then mutations: 12 s each, under 2 minutes in all (scripts/test.sh)
#   scripts/fuzz.sh MINUTES [TARGET...]    a campaign: each target (default: all) MINUTES
# The targets are built in build-asan/ by scripts/build-sanitized.sh, the
# configuration the sanitizer half of the tests uses (clang, ASan, UBSan,
# asserts on). Exits non-zero if any target found a crash, leak, timeout or
# out-of-memory; the input that did it is left in build-asan/fuzz-findings/<target>/.
set -euo pipefail
cd "$(dirname "$0")/.."
MODE="${1:-5}"
shift || true
TARGETS=("$@")
ALL=(fuzz_scene_loader fuzz_json fuzz_nff fuzz_mesh_obj fuzz_mesh_ply fuzz_mesh_gltf fuzz_mesh_glb
     fuzz_texture_png fuzz_texture_jpg fuzz_texture_bmp fuzz_texture_tga fuzz_texture_hdr fuzz_texture_pfm fuzz_texture_exr
     fuzz_serve_request)
if [ ${#TARGETS[@]} -eq 0 ]; then
  TARGETS=("${ALL[@]}")
  # glint serve is optional (cpp-httplib): without it, so is its target.
  if [ ! -x build-asan/fuzz/fuzz_serve_request ]; then
    TARGETS=()
    for t in "${ALL[@]}"; do [ "$t" = fuzz_serve_request ] || TARGETS+=("$t"); done
  fi
fi
if [ "$MODE" = smoke ]; then
  # 15 targets, 2 at a time on 2 cores: about 2 minutes in all; each
  # target's time includes its seeds.
  SECONDS_PER_TARGET=12
else
  case "$MODE" in ''|*[!0-9.]*) echo "usage: scripts/fuzz.sh smoke | MINUTES [TARGET...]" >&2; exit 2;; esac
  SECONDS_PER_TARGET=$(awk -v m="$MODE" 'BEGIN { s = int(m * 60); print (s < 1 ? 1 : s) }')
  # The campaign builds what it runs; the smoke runs what scripts/test.sh built.
  scripts/install-deps.sh test
  scripts/build-sanitized.sh
fi

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"

# One target's run; its output goes to build-asan/fuzz-findings/<target>/log.txt.
fuzz_one() {
  local target=$1 dict=fuzz/scene.dict regressions=fuzz/regressions seeds
  case "$target" in
    fuzz_scene_loader) seeds=(fuzz/corpus/scene) ;;
    fuzz_json) seeds=(fuzz/corpus/json fuzz/corpus/scene) ;;
    fuzz_nff) seeds=(fuzz/corpus/nff); dict=fuzz/nff.dict ;;
    fuzz_mesh_obj) seeds=(fuzz/corpus/obj); dict=fuzz/mesh.dict; regressions=fuzz/regressions/mesh ;;
    fuzz_mesh_ply) seeds=(fuzz/corpus/ply); dict=fuzz/mesh.dict; regressions=fuzz/regressions/mesh ;;
    fuzz_mesh_gltf) seeds=(fuzz/corpus/gltf); dict=fuzz/gltf.dict; regressions=fuzz/regressions/mesh ;;
    fuzz_mesh_glb) seeds=(fuzz/corpus/glb); dict=fuzz/gltf.dict; regressions=fuzz/regressions/mesh ;;
    fuzz_texture_*) seeds=(fuzz/corpus/texture-"${target#fuzz_texture_}"); dict=fuzz/texture.dict
      regressions=fuzz/regressions/texture ;;
    fuzz_serve_request) seeds=(fuzz/corpus/serve) ;;
  esac
  # New inputs go to a corpus kept in the build folder (the first directory);
  # the seeds and regressions in the repository are only read.
  local corpus="build-asan/fuzz-corpus/$target" findings="build-asan/fuzz-findings/$target"
  mkdir -p "$corpus" "$findings"
  "build-asan/fuzz/$target" -max_total_time="$SECONDS_PER_TARGET" -max_len=65536 -rss_limit_mb=2048 \
    -timeout=10 -print_final_stats=1 -dict="$dict" -artifact_prefix="$findings/" \
    "$corpus" "${seeds[@]}" "$regressions" > "$findings/log.txt" 2>&1
}

for target in "${TARGETS[@]}"; do
  case " ${ALL[*]} " in *" $target "*) ;; *) echo "unknown target $target" >&2; exit 2 ;; esac
  [ -x "build-asan/fuzz/$target" ] || { echo "error: build-asan/fuzz/$target is not built (scripts/build-sanitized.sh)" >&2; exit 1; }
done
# libFuzzer runs one input at a time: as many targets at once as there are cores.
echo "fuzzing ${TARGETS[*]}: ${SECONDS_PER_TARGET} s each, $(nproc) at a time" >&2
declare -A pids
for target in "${TARGETS[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || true; done
  fuzz_one "$target" &
  pids[$target]=$!
done
failed=()
for target in "${TARGETS[@]}"; do
  log="build-asan/fuzz-findings/$target/log.txt"
  if wait "${pids[$target]}"; then
    echo "== $target: $(grep -E '^stat::number_of_executed_units' "$log" | awk '{print $2}') runs, nothing found" >&2
  else
    tail -n 60 "$log" >&2
    echo "== $target FOUND A PROBLEM: input in build-asan/fuzz-findings/$target/ (see fuzz/README.md to reproduce)" >&2
    failed+=("$target")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found problems in: ${failed[*]}" >&2
  exit 1
fi
echo "fuzzing found nothing (${TARGETS[*]}, ${SECONDS_PER_TARGET} s each)" >&2
