#!/bin/bash
# pip install . from a clean copy of the sources into a new virtual
# environment, exactly as docs/python.md says, offline; then import glint
# from it and render. Touches nothing outside WORK (no system site-packages).
# Usage: pip_install.sh SOURCE_DIR WORK_DIR [BUILD_DIR]
set -euo pipefail
src=$1
work=$2
build=${3:-}
if ! /usr/bin/python3 -c 'import venv, ensurepip' 2>/dev/null; then
  echo "skipped: /usr/bin/python3 has no venv/ensurepip (Debian: apt-get install python3-venv)"
  exit 77
fi
rm -rf "$work"
mkdir -p "$work"
# A clean copy of the sources: the files git knows (tracked or new, not ignored).
mkdir -p "$work/src"
(cd "$src" && git ls-files -z --cached --others --exclude-standard | xargs -0 cp --parents -t "$work/src")
cd "$work"
/usr/bin/python3 -m venv --system-site-packages venv
# --no-build-isolation: Debian's setuptools from the system site-packages;
# --no-index: never ask a package index (numpy is Debian's too).
# With BUILD_DIR, setup.py packages that build's module (GLINT_BUILD_DIR)
# instead of compiling the library again: the venv, pip and the package's
# files are the same; the compile from nothing is what `glint` itself builds.
if [ -n "$build" ]; then
  GLINT_BUILD_DIR="$build" venv/bin/pip install --no-build-isolation --no-index ./src
else
  CMAKE_ARGS="${GLINT_PIP_CMAKE_ARGS:--DGLINT_LTO=OFF}" CMAKE_BUILD_PARALLEL_LEVEL=${CMAKE_BUILD_PARALLEL_LEVEL:-2} \
    venv/bin/pip install --no-build-isolation --no-index ./src
fi
cd /  # not the sources: the installed package must be the one imported
"$work/venv/bin/python" - <<'PY'
import glint, numpy as np, os, sys
assert glint.__file__.startswith(os.environ.get("VIRTUAL_ENV", sys.prefix)), glint.__file__
assert os.path.exists(os.path.join(os.path.dirname(glint.__file__), "__init__.pyi"))
scene = glint.loads('{"camera": {"position": [0, 0, 4], "look_at": [0, 0, 0]},'
                    ' "lights": [{"type": "point", "position": [2, 3, 4]}],'
                    ' "objects": [{"type": "sphere", "center": [0, 0, 0], "radius": 1}]}')
r = glint.render(scene, width=32, height=24)
assert r.image.shape == (24, 32, 3) and r.image.max() > 0
print("pip install: glint", glint.__version__, "from", glint.__file__)
PY
