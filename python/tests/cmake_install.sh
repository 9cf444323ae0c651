#!/bin/bash
# cmake --install of the python component into a scratch prefix; then the
# installed package, not the build tree's, is imported and renders.
# Usage: cmake_install.sh CMAKE BUILD_DIR PREFIX SITE_PACKAGES_RELATIVE PYTHON SOURCE_DIR
set -euo pipefail
cmake=$1 build=$2 prefix=$3 site=$4 python=$5 src=$6
rm -rf "$prefix"
"$cmake" --install "$build" --component python --prefix "$prefix" >/dev/null
cd /
PYTHONPATH="$prefix/$site" "$python" - "$prefix" "$src/scenes/showcase.json" <<'PY'
import sys
import glint
assert glint.__file__.startswith(sys.argv[1]), glint.__file__
r = glint.render(glint.load(sys.argv[2]), width=16, height=9)
assert r.image.shape == (9, 16, 3) and r.image.max() > 0
print("cmake --install: glint", glint.__version__, "from", glint.__file__)
PY
