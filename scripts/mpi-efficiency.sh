#!/usr/bin/env bash
# Distributed efficiency on one machine: 2 ranks x 1 thread against 1 rank x
# 2 threads on a scene, best of RUNS runs of each (interleaved, so a burst of
# load from elsewhere hits every configuration alike): wall time from launch
# to exit, and the render part from glint's stats line.
# Usage: scripts/mpi-efficiency.sh [RUNS] [SCENE]   (build/glint built with MPI)
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${1:-5} scene=${2:-scenes/showcase.json}
glint=build/glint out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
mpirun=(mpirun --oversubscribe --allow-run-as-root)
# Open MPI binds each rank to one core by default (np <= 2): a rank with
# 2 threads must not be bound, or its threads share one core.
configs=(
  "1 process x 2 threads (no mpirun)|$glint render $scene -o $out/a.exr --threads 2"
  "mpirun -np 1 --bind-to none, 2 threads|${mpirun[*]} -np 1 --bind-to none $glint render $scene -o $out/b.exr --threads 2"
  "mpirun -np 2, 1 thread each|${mpirun[*]} -np 2 $glint render $scene -o $out/c.exr --threads 1"
)
declare -A wall render
for _ in $(seq "$runs"); do
  for i in "${!configs[@]}"; do
    command=${configs[$i]#*|}
    start=$(date +%s.%N)
    $command 2> "$out/log"
    end=$(date +%s.%N)
    w=$(echo "$end - $start" | bc -l)
    r=$(sed -n 's/.*render \([0-9.]*\) s.*/\1/p' "$out/log" | tail -1)
    [ -z "${wall[$i]:-}" ] || w=$(echo "if ($w < ${wall[$i]}) $w else ${wall[$i]}" | bc -l)
    [ -z "${render[$i]:-}" ] || r=$(echo "if ($r < ${render[$i]}) $r else ${render[$i]}" | bc -l)
    wall[$i]=$w render[$i]=$r
    [ "$i" -eq 2 ] && grep -o "tiles by rank.*of pixels)" "$out/log"
  done
done
cmp "$out/a.exr" "$out/c.exr" && echo "2-rank image == 1-process image"
for i in "${!configs[@]}"; do
  printf "| %s | %.3f s | %.3f s |\n" "${configs[$i]%%|*}" "${wall[$i]}" "${render[$i]}"
done
printf "2 ranks x 1 thread / 1 rank x 2 threads: wall %.3f, render part %.3f\n" \
  "$(echo "${wall[2]} / ${wall[1]}" | bc -l)" "$(echo "${render[2]} / ${render[1]}" | bc -l)"
