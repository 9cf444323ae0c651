#!/usr/bin/env bash
# How the cost of a ray grows with the mesh, through the renderer:
#   bench/render-scaling.sh [SIZES] [THREADS] [REPEAT]
# e.g. bench/render-scaling.sh 100000,1000000,10000000 1,2 3
# Renders bench/make_bench.py's terrain scene (height field + reflective plane,
# 1280x720, 1 spp: camera, shadow and mirror rays) made with each triangle
# count, and reports the render part of `glint render` (loading and building
# excluded) as Mrays/s, best of REPEAT (the sizes take turns), and the time
# per ray relative to the smallest mesh, in the same run. Scenes are generated once into
# $GLINT_SCALING_DIR (default /tmp/glint-scaling); 10M triangles is a 380 MB
# OBJ and needs ~4 GB of memory to load and build.
set -euo pipefail
cd "$(dirname "$0")/.."
SIZES="${1:-100000,1000000,10000000}"
THREADS="${2:-1,2}"
REPEAT="${3:-3}"
GLINT="${GLINT:-build/glint}"
DIR="${GLINT_SCALING_DIR:-/tmp/glint-scaling}"
MAKE_BENCH="${MAKE_BENCH:-bench/make_bench.py}"
[ -x "$GLINT" ] || { echo "error: $GLINT not built (cmake --build build)" >&2; exit 1; }

IFS=, read -r -a sizes <<<"$SIZES"
IFS=, read -r -a threads <<<"$THREADS"
for n in "${sizes[@]}"; do
  if [ ! -f "$DIR/$n/terrain.json" ]; then
    [ -f "$MAKE_BENCH" ] || { echo "error: $MAKE_BENCH not found (set MAKE_BENCH)" >&2; exit 1; }
    echo "generating the terrain with $n triangles in $DIR/$n" >&2
    python3 "$MAKE_BENCH" --terrain-tris "$n" -o "$DIR/$n" --only terrain >/dev/null
  fi
done

# Mrays/s of the render part of one run, from the stats line
# ("... render 0.52 s (total ...); rays: ...; 3.89 Mrays/s").
rate_of_run() {
  "$GLINT" render "$1" -o "$DIR/out.png" --threads "$2" 2>&1 | grep ' Mrays/s' |
    sed -E 's/.* ([0-9.]+) Mrays\/s.*/\1/'
}

# The sizes take turns within each repetition, so that a slow spell of this
# shared machine falls on all of them alike; the best of REPEAT is kept.
declare -A best
for ((r = 0; r < REPEAT; ++r)); do
  for t in "${threads[@]}"; do
    for n in "${sizes[@]}"; do
      rate=$(rate_of_run "$DIR/$n/terrain.json" "$t")
      best[$n,$t]=$(awk -v a="${best[$n,$t]:-0}" -v b="$rate" 'BEGIN { print (b > a ? b : a) }')
    done
  done
done

printf '%-12s' "triangles"
for t in "${threads[@]}"; do printf ' | %2sT Mrays/s  per ray' "$t"; done
printf '\n'
for n in "${sizes[@]}"; do
  printf '%-12s' "$n"
  for t in "${threads[@]}"; do
    printf ' | %12s  %6.2fx' "${best[$n,$t]}" "$(awk -v a="${best[${sizes[0]},$t]}" -v b="${best[$n,$t]}" 'BEGIN { print a / b }')"
  done
  printf '\n'
done
