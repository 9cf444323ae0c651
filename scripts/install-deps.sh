#!/usr/bin/env bash
# Installs the Debian packages glint needs to build and test, if any are missing.
# As root it runs apt-get; otherwise it prints the apt-get line to run.
# Extra package names given as arguments are checked too (scripts/fuzz.sh).
set -euo pipefail
PACKAGES=(
  cmake ninja-build g++ clang pkg-config
  nlohmann-json3-dev libstb-dev libpng-dev libtinyexr-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtinyobjloader-dev libfast-float-dev libassimp-dev libembree-dev
  assimp-testmodels
  libopenmpi-dev openmpi-bin
  python3 python3-jsonschema
  libcpp-httplib-dev chromium nodejs
  python3-pytest python3-numpy pybind11-dev python3-pybind11 python3-venv python3-setuptools python3-pip
  "$@"
)
# glint serve's browser tests need npm (Debian's npm; some nodejs builds bundle it).
command -v npm >/dev/null || PACKAGES+=(npm)
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
