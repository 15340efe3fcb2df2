#!/usr/bin/env bash
# The main job on a real mesh: installs dependencies, builds Release, fills the femur that
# Debian's libcgal-demo ships with a gyroid lattice, checks what was written, and prints where
# the outputs are.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
bash scripts/build.sh build

out="$PWD/out/demo"
mkdir -p "$out"
tarball=/usr/share/doc/libcgal-demo/data.tar.gz
tar -xzf "$tarball" -C "$out" --strip-components=2 data/meshes/femur.off

echo
echo "== tpmsfill check femur.off"
./build/tpmsfill check "$out/femur.off" | tee "$out/femur-check.txt"

# femur.off is 1 unit long: --scale 35 makes it a 35 mm bone (the benchmark's size), filled
# with a gyroid of 2 mm cells sampled every 0.1 mm.
echo
echo "== tpmsfill fill femur.off femur-gyroid.stl --scale 35 --lattice gyroid --cell 2 --voxel 0.1"
./build/tpmsfill fill "$out/femur.off" "$out/femur-gyroid.stl" --scale 35 --lattice gyroid \
  --cell 2 --voxel 0.1 --report "$out/femur-gyroid.json" | tee "$out/femur-gyroid.txt"

echo
echo "== tpmsfill check femur-gyroid.stl (the written file, checked independently)"
./build/tpmsfill check "$out/femur-gyroid.stl" | tee "$out/femur-gyroid-check.txt"

echo
echo "input:   $out/femur.off (from $tarball)"
echo "lattice: $out/femur-gyroid.stl"
echo "report:  $out/femur-gyroid.json (summary: $out/femur-gyroid.txt)"
echo "check:   $out/femur-gyroid-check.txt"
