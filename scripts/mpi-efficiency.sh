#!/usr/bin/env bash
# Distributed efficiency on one machine: 2 ranks x 1 thread against 1 rank x
# 2 threads on a scene, best of RUNS runs of each (interleaved, so a burst of
# load from elsewhere hits every configuration alike): wall time from launch
# to exit, the render part from glint's stats line, and the CPU time (user +
# system, of every process: the cost of the distribution).
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
declare -A wall render cpu
min() { echo "if ($1 < $2) $1 else $2" | bc -l; }
for _ in $(seq "$runs"); do
  for i in "${!configs[@]}"; do
    command=${configs[$i]#*|}
    /usr/bin/time -o "$out/time" -f "%e %U %S" $command 2> "$out/log"
    read -r w u sys < "$out/time"
    c=$(echo "$u + $sys" | bc -l)
    r=$(sed -n 's/.*render \([0-9.]*\) s.*/\1/p' "$out/log" | tail -1)
    [ -z "${wall[$i]:-}" ] || { w=$(min "$w" "${wall[$i]}"); r=$(min "$r" "${render[$i]}"); c=$(min "$c" "${cpu[$i]}"); }
    wall[$i]=$w render[$i]=$r cpu[$i]=$c
    [ "$i" -eq 2 ] && { grep -o "tiles by rank.*of pixels)" "$out/log"; grep -o "CPU in the render.*" "$out/log"; }
  done
done
cmp "$out/a.exr" "$out/c.exr" && echo "2-rank image == 1-process image"
for i in "${!configs[@]}"; do
  printf "| %s | %.3f s | %.3f s | %.2f s |\n" "${configs[$i]%%|*}" "${wall[$i]}" "${render[$i]}" "${cpu[$i]}"
done
printf "2 ranks x 1 thread / 1 rank x 2 threads (both under mpirun): wall %.3f, render part %.3f\n" \
  "$(echo "${wall[2]} / ${wall[1]}" | bc -l)" "$(echo "${render[2]} / ${render[1]}" | bc -l)"
printf "2 ranks x 1 thread / 1 process x 2 threads without mpirun: wall %.3f, render part %.3f\n" \
  "$(echo "${wall[2]} / ${wall[0]}" | bc -l)" "$(echo "${render[2]} / ${render[0]}" | bc -l)"
