#!/usr/bin/env bash
# Installs what tpmsfill needs to build and test, from Debian's packages (non-interactive).
# Safe to run again: installs only what is missing. Needs root (or sudo) when something is.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libcgal-dev libgmp-dev libmpfr-dev libboost-dev libtbb-dev zlib1g-dev
  libcli11-dev nlohmann-json3-dev libgtest-dev
  nettle-dev  # SHA-256 of the input in `tpmsfill fill --report`
  libeigen3-dev  # hole fairing in `tpmsfill repair` (optional at build time)
  lib3mf-dev  # 3MF in and out (the 3MF Consortium's lib3mf)
  libpolyclipping-dev  # Clipper: the region a folded solid's section covers (material slice)
  libcpp-httplib-dev  # HTTP for `tpmsfill serve` (pulls libssl-dev, zlib1g-dev, libbrotli-dev)
  libzip-dev  # `tpmsfill serve`: a slice job's folder of layers sent as one zip
  # The Python module (issue 42): pybind11 against Debian's Python, tested by pytest with numpy.
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
  libassimp-dev  # scenes as input: glTF/GLB, FBX, COLLADA, 3DS, ... (optional at build time)
  libopenvdb-dev  # .vdb grids in and out (optional at build time)
  # Real meshes for the tests and the demo: CGAL's demo data (femur.off, elephant-with-holes.off,
  # ...) and assimp's odd STL/OBJ/PLY/OFF test files.
  libcgal-demo assimp-testmodels
)
# The service's page is bundled at build time by npm (three.js, esbuild): Debian's Node.js and
# npm, unless a Node.js with npm is already installed (NodeSource's includes npm, and Debian's
# npm package would conflict with it).
command -v npm > /dev/null || packages+=(nodejs npm)
# Extra tools: `scripts/test.sh --sanitize` and `scripts/fuzz.sh` need clang's runtimes; the
# page's browser test needs Debian's chromium.
case "${TPMSFILL_SETUP_EXTRA:-}" in
  clang) packages+=(clang libclang-rt-14-dev) ;;
  chromium) packages=(chromium) ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [[ $(id -u) -eq 0 ]] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  # No recommends: libcgal-demo would otherwise pull in Qt for demos we never build.
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
