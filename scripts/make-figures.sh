#!/usr/bin/env bash
# Renders the lecture figures of scenes/figures and the showcase into docs/img/
# (small PNGs that docs/figures.md and the README show). Needs a built glint (scripts/setup.sh) and python3.
set -euo pipefail
cd "$(dirname "$0")/.."
GLINT=${GLINT:-build/glint}
OUT=docs/img
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
render() { "$GLINT" render "$@" --quiet; }

for part in ambient diffuse specular sum; do
  render scenes/figures/components-$part.json -o "$TMP/components-$part.ppm"
done
python3 scripts/montage.py "$OUT/components.png" "$TMP"/components-{ambient,diffuse,specular,sum}.ppm

for m in phong blinn-phong blinn-phong-same-exponent; do
  render scenes/figures/model-$m.json -o "$TMP/model-$m.ppm"
done
python3 scripts/montage.py "$OUT/phong-vs-blinn.png" "$TMP"/model-{phong,blinn-phong,blinn-phong-same-exponent}.ppm

# The showcase's component passes from one render (--passes), laid out like
# the components figure: ambient, diffuse, specular, reflection, transmission, and their sum.
render scenes/showcase.json --width 320 --height 180 --spp 16 \
  --passes ambient,diffuse,specular,reflection,transmission -o "$TMP/passes.ppm"
python3 scripts/montage.py "$OUT/passes.png" \
  "$TMP"/passes.{ambient,diffuse,specular,reflection,transmission}.ppm "$TMP/passes.ppm"

# Soft shadows: one square area light, 0.3, 1.5 and 4 units wide, 64 samples.
for n in small medium large; do
  render scenes/figures/soft-shadows-$n.json -o "$TMP/soft-$n.ppm"
done
python3 scripts/montage.py "$OUT/soft-shadows.png" "$TMP"/soft-{small,medium,large}.ppm

render scenes/figures/exponents.json -o "$OUT/exponents.png"
render scenes/figures/shadows.json -o "$OUT/shadows.png"

for d in 1 2 5; do
  render scenes/figures/mirrors.json --max-depth $d -o "$TMP/mirrors-$d.ppm"
done
python3 scripts/montage.py "$OUT/mirrors.png" "$TMP"/mirrors-{1,2,5}.ppm

render scenes/figures/refraction.json -o "$OUT/refraction.png"
# Cylinders (closed, open, glass), cones (pointed and a frustum), an annulus,
# a non-convex star polygon and a smooth-shaded hexagon (a polygon with normals).
render scenes/figures/quadrics.json -o "$OUT/quadrics.png"
render scenes/showcase.json -o "$OUT/showcase.png"
render scenes/meshes/bunny.json -o "$OUT/bunny.png"
render scenes/textures/textures.json -o "$OUT/textures.png"
# Beyond the seed (scenes/beyond): cameras, atmosphere, solids.
for s in fisheye panorama focus fog ambient-occlusion die torus-knot sky; do
  render scenes/beyond/$s.json -o "$TMP/beyond-$s.ppm"
done
python3 scripts/montage.py "$OUT/beyond-cameras.png" "$TMP"/beyond-{fisheye,panorama}.ppm
python3 scripts/montage.py "$OUT/beyond-atmosphere.png" "$TMP"/beyond-{focus,fog,ambient-occlusion}.ppm
python3 scripts/montage.py "$OUT/beyond-solids.png" "$TMP"/beyond-{die,torus-knot,sky}.ppm
echo "figures written to $OUT/"
