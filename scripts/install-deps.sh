#!/usr/bin/env bash
# Installs the Debian packages glint needs, if any are missing:
#   scripts/install-deps.sh build [PACKAGE...]   what building and rendering need (scripts/setup.sh)
#   scripts/install-deps.sh test  [PACKAGE...]   that, the optional parts (Embree, assimp, MPI, glint
#                                                serve, Python) and what only the tests need (scripts/test.sh)
# As root it runs apt-get; otherwise it prints the apt-get line to run.
set -euo pipefail
GROUP="${1:-test}"
shift || true
# The compiler and the libraries every build of glint links.
BUILD=(
  cmake ninja-build g++ pkg-config
  nlohmann-json3-dev libstb-dev libpng-dev libtinyexr-dev libcli11-dev
  libtinyobjloader-dev libfast-float-dev
)
# The optional parts, found by CMake when present (each a plugin of the program),
# and the test tools: GoogleTest, Google Benchmark, clang with its sanitizer and
# libFuzzer runtimes (the sanitizer half and the fuzz smoke), real-world meshes,
# the Python module's build and tests, Chromium for glint serve's browser test,
# POV-Ray (an independent renderer the torus is checked against).
TEST=(
  libembree-dev libassimp-dev libopenmpi-dev openmpi-bin libcpp-httplib-dev
  pybind11-dev python3-pybind11 python3-venv python3-setuptools python3-pip
  libgtest-dev libgmock-dev libbenchmark-dev clang libclang-rt-dev
  assimp-testmodels python3 python3-jsonschema python3-pytest python3-numpy
  chromium nodejs povray
)
case "$GROUP" in
  build) PACKAGES=("${BUILD[@]}" "$@") ;;
  test)
    PACKAGES=("${BUILD[@]}" "${TEST[@]}" "$@")
    # The browser test needs npm (Debian's npm; some nodejs builds bundle it).
    command -v npm >/dev/null || PACKAGES+=(npm)
    ;;
  *) echo "usage: scripts/install-deps.sh build|test [PACKAGE...]" >&2; exit 2 ;;
esac
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
if [ "$(id -u)" -ne 0 ]; then
  echo "glint needs these Debian packages; run as root:" >&2
  echo "  apt-get update && apt-get install -y ${missing[*]}" >&2
  exit 1
fi
echo "installing: ${missing[*]}" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
