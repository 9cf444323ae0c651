#!/usr/bin/env bash
# Distributed efficiency on one machine: 2 ranks x 1 thread against 1 rank x
# 2 threads (and the plain single process) on a scene, best of RUNS runs of
# each, wall time from launch to exit and the render part from glint's stats
# line. Usage: scripts/mpi-efficiency.sh [RUNS] [SCENE]  (build/glint built with MPI)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5} scene=${2:-scenes/showcase.json}
glint=build/glint out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mpirun=(mpirun --oversubscribe --allow-run-as-root)

# Prints "best_wall best_render" over $runs runs of the command.
best_of() {
  local best_wall=999999 best_render=999999
  for _ in $(seq "$runs"); do
    local start end wall render
    start=$(date +%s.%N)
    "$@" 2> "$out/log"
    end=$(date +%s.%N)
    wall=$(echo "$end - $start" | bc -l)
    render=$(sed -n 's/.*render \([0-9.]*\) s.*/\1/p' "$out/log" | tail -1)
    best_wall=$(echo "if ($wall < $best_wall) $wall else $best_wall" | bc -l)
    best_render=$(echo "if ($render < $best_render) $render else $best_render" | bc -l)
  done
  printf "%.3f %.3f\n" "$best_wall" "$best_render"
}

read -r w1 r1 < <(best_of "$glint" render "$scene" -o "$out/a.exr" --threads 2)
read -r w2 r2 < <(best_of "${mpirun[@]}" -np 1 "$glint" render "$scene" -o "$out/b.exr" --threads 2)
read -r w3 r3 < <(best_of "${mpirun[@]}" -np 2 "$glint" render "$scene" -o "$out/c.exr" --threads 1)
cmp "$out/a.exr" "$out/c.exr"
grep -o "tiles by rank.*of pixels)" "$out/log"
echo "| 1 process x 2 threads (no mpirun) | $w1 s | $r1 s |"
echo "| mpirun -np 1, 2 threads | $w2 s | $r2 s |"
echo "| mpirun -np 2, 1 thread each | $w3 s | $r3 s |"
echo "2 ranks / 1 rank (wall): $(echo "scale=3; $w3 / $w2" | bc -l)"
