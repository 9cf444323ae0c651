#!/usr/bin/env bash
# How the cost of a ray grows with the mesh, through the renderer:
#   bench/render-scaling.sh [SIZES] [THREADS] [REPEAT]
# e.g. bench/render-scaling.sh 100000,1000000,10000000 1,2 3
# Renders ../shared/bench's terrain scene (height field + reflective plane,
# 1280x720, 1 spp: camera, shadow and mirror rays) made with each triangle
# count, and reports the render part of `glint render` (loading and building
# excluded) as Mrays/s, best of REPEAT, and the time per ray relative to the
# smallest mesh, in the same run. Scenes are generated once into
# $GLINT_SCALING_DIR (default /tmp/glint-scaling); 10M triangles is a 380 MB
# OBJ and needs ~4 GB of memory to load and build.
set -euo pipefail
cd "$(dirname "$0")/.."
SIZES="${1:-100000,1000000,10000000}"
THREADS="${2:-1,2}"
REPEAT="${3:-3}"
GLINT="${GLINT:-build/glint}"
DIR="${GLINT_SCALING_DIR:-/tmp/glint-scaling}"
MAKE_BENCH="${MAKE_BENCH:-../shared/bench/make_bench.py}"
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

# Best Mrays/s of the render part over REPEAT runs, from the stats line
# ("... render 0.52 s (total ...); rays: ...; 3.89 Mrays/s").
best_rate() {
  local scene=$1 t=$2 best=0 line rate
  for ((i = 0; i < REPEAT; ++i)); do
    line=$("$GLINT" render "$scene" -o "$DIR/out.png" --threads "$t" 2>&1 | grep ' Mrays/s')
    rate=$(sed -E 's/.* ([0-9.]+) Mrays\/s.*/\1/' <<<"$line")
    best=$(awk -v a="$best" -v b="$rate" 'BEGIN { print (b > a ? b : a) }')
  done
  echo "$best"
}

printf '%-12s' "triangles"
for t in "${threads[@]}"; do printf ' | %2sT Mrays/s  per ray' "$t"; done
printf '\n'
declare -A first
for n in "${sizes[@]}"; do
  printf '%-12s' "$n"
  for t in "${threads[@]}"; do
    rate=$(best_rate "$DIR/$n/terrain.json" "$t")
    [ -n "${first[$t]:-}" ] || first[$t]=$rate
    printf ' | %12s  %6.2fx' "$rate" "$(awk -v a="${first[$t]}" -v b="$rate" 'BEGIN { print a / b }')"
  done
  printf '\n'
done
