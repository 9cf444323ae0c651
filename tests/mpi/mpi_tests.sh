#!/usr/bin/env bash
# Distributed rendering end to end: `mpirun -np 2` against a single process,
# byte for byte. Usage: mpi_tests.sh TEST GLINT MPIEXEC SOURCE_DIR WORK_DIR
# MPIEXEC empty: glint was built without MPI, and the test is skipped (77).
set -uo pipefail
test_name=$1 glint=$2 mpiexec=$3 src=$4 work=$5
if [ -z "$mpiexec" ]; then
  echo "skipped: built without MPI (configure with MPI installed, GLINT_MPI=ON)"
  exit 77
fi
# Under AddressSanitizer (scripts/test.sh): Open MPI keeps some memory until
# exit. Keep its plugins loaded so their frames have names, unwind fully
# (Open MPI has no frame pointers), and suppress Open MPI's own leaks only.
export OMPI_MCA_mca_base_component_disable_dlclose=1
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}fast_unwind_on_malloc=0"
export LSAN_OPTIONS="${LSAN_OPTIONS:+$LSAN_OPTIONS:}suppressions=$src/tests/mpi/lsan.supp"
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
mpirun=("$mpiexec" -np 2 --oversubscribe --allow-run-as-root)
showcase=$src/scenes/showcase.json anim=$src/tests/mpi/anim4.json
fail() { echo "FAIL: $*"; exit 1; }
same() { cmp -s "$1" "$2" || fail "$1 and $2 differ"; }
# Within a deadline: a hang is a failure, not a stuck CTest.
run() { timeout 120 "$@"; }

case $test_name in
  tiles)  # one image, tiles spread over 2 ranks x 2 threads
    run "${mpirun[@]}" "$glint" render "$showcase" --width 203 --height 117 --spp 2 -o mpi.exr --threads 2 2> log ||
      { cat log; fail "mpirun render failed"; }
    cat log
    grep -q "2 ranks x 2 threads" log || fail "not a distributed render"
    grep -Eq "tiles by rank [1-9][0-9]*/[1-9]" log || fail "a rank rendered no tile"
    run "$glint" render "$showcase" --width 203 --height 117 --spp 2 -o one.exr -q || fail "single render failed"
    same mpi.exr one.exr ;;
  frames)  # 4 frames > 2 ranks: whole frames per rank
    run "${mpirun[@]}" "$glint" render "$anim" -o mpi_%02d.pfm --threads 1 -q || fail "mpirun render failed"
    run "$glint" render "$anim" -o one_%02d.pfm -q || fail "single render failed"
    for f in 00 01 02 03; do same mpi_$f.pfm one_$f.pfm; done ;;
  frame-tiles)  # 2 frames, 2 ranks: each frame's tiles over both ranks
    run "${mpirun[@]}" "$glint" render "$anim" --frames 1-2 -o mpi_%d.png --threads 1 2> log || { cat log; fail "mpirun render failed"; }
    grep -q "2 ranks x 1 thread" log || fail "frames were not split in tiles"
    run "$glint" render "$anim" --frames 1-2 -o one_%d.png -q || fail "single render failed"
    same mpi_1.png one_1.png && same mpi_2.png one_2.png
    [ ! -e mpi_0.png ] && [ ! -e mpi_3.png ] || fail "frames outside --frames were written" ;;
  bad-scene)  # every rank fails to load: one error line, non-zero exit, no hang
    printf '{"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0]}, "objects": [{"type": "sphere", "radius": -1}]}\n' > bad.json
    run "${mpirun[@]}" "$glint" render bad.json -o out.png 2> log; rc=$?
    cat log
    [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "exit $rc (124: timed out)"
    [ "$(grep -c '^error: ' log)" -eq 1 ] || fail "expected one error line"
    grep -q '^error: bad.json:1:' log || fail "the error does not point into the scene"
    [ ! -e out.png ] || fail "an image was written" ;;
  jpeg-too-wide)  # a frame split in tiles whose JPEG cannot hold it: an error before the render
    # Rendered first, these 7 million pixels at 10000 spp would take hours: run's deadline fails them.
    run "${mpirun[@]}" "$glint" render "$showcase" --width 70000 --height 100 --spp 10000 -o out.jpg 2> log; rc=$?
    cat log
    [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "exit $rc (124: timed out, so it rendered)"
    [ "$(grep -c '^error: ' log)" -eq 1 ] || fail "expected one error line"
    grep -q '^error: out.jpg: cannot write: a JPEG is at most 65535 pixels wide and high, not 70000x100' log ||
      fail "the error does not name the JPEG's limit"
    [ ! -e out.jpg ] || fail "an image was written" ;;
  rank-dies)  # rank 1 dies after its first frame: the job fails fast, naming it;
              # written frames stay, --skip-existing renders only the missing ones
    # Frames slow enough (~0.2 s each) that the job ends before rank 0 renders them all;
    # a sanitized build renders them several times slower, a quarter of the pixels is enough.
    size='"width": 320, "height": 240'
    [ "${GLINT_SANITIZED:-0}" = 1 ] && size='"width": 160, "height": 120'
    sed "s/\"frames\": 4/\"frames\": 12/; s/\"width\": 96, \"height\": 64, \"samples_per_pixel\": 2/$size, \"samples_per_pixel\": 16/" \
      "$anim" > anim12.json
    start=$(date +%s)
    GLINT_TEST_DIE_RANK=1 run "${mpirun[@]}" -x GLINT_TEST_DIE_RANK "$glint" render anim12.json -o f_%02d.pfm --threads 1 -q 2> log
    rc=$?
    cat log
    [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "exit $rc (124: timed out)"
    [ $(( $(date +%s) - start )) -le 30 ] || fail "took more than 30 s to fail"
    grep -q "rank 1" log || fail "the message does not name rank 1"
    # A frame cut short by the job's end keeps a resume file: not done.
    written=0
    for f in f_*.pfm; do [ -e "$f" ] && [ ! -e "$f.glint-resume" ] && written=$((written + 1)); done
    echo "frames complete before the failure: $written"
    [ "$written" -lt 12 ] || fail "every frame was written although a rank died"
    run "${mpirun[@]}" "$glint" render anim12.json -o f_%02d.pfm --threads 1 --skip-existing --resume 2> log2 ||
      { cat log2; fail "rerun failed"; }
    skipped=$(grep -c "exists: skipped" log2)
    [ "$skipped" -eq "$written" ] || fail "skipped $skipped frames, $written were written"
    run "$glint" render anim12.json -o one_%02d.pfm -q || fail "single render failed"
    for f in $(seq -w 0 11); do same f_$f.pfm one_$f.pfm; done ;;
  rank-hangs)  # rank 1 stops (SIGSTOP) after its first tile: rank 0 names it and ends the job
    start=$(date +%s)
    GLINT_TEST_HANG_RANK=1 timeout 20 "${mpirun[@]}" -x GLINT_TEST_HANG_RANK "$glint" render "$showcase" -o hang.exr \
      --threads 1 --rank-timeout 2 2> log
    rc=$?
    cat log
    [ $rc -ne 0 ] && [ $rc -ne 124 ] || fail "exit $rc (124: timed out)"
    [ $(( $(date +%s) - start )) -le 10 ] || fail "took more than 10 s to fail"
    grep -Eq "^error: rank 1: no answer for 2 s \(holding tiles [0-9]" log || fail "the message does not name rank 1 and its tiles"
    [ ! -e hang.exr ] || fail "an image was written"
    pgrep -f "render $showcase -o hang.exr" && fail "a rank outlived the job"
    true ;;
  *) fail "unknown test $test_name" ;;
esac
echo "ok: $test_name"
