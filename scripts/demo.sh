#!/usr/bin/env bash
# The main job on a real mesh: installs dependencies, builds Release, fills the femur that
# Debian's libcgal-demo ships with a gyroid lattice, checks what was written, and prints where
# the outputs are.
#   bash scripts/demo.sh          the fill, on the command line
#   bash scripts/demo.sh serve    the second demo: the service and its web page, on this machine
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh
bash scripts/build.sh build

out="$PWD/out/demo"
mkdir -p "$out"
tarball=/usr/share/doc/libcgal-demo/data.tar.gz
tar -xzf "$tarball" -C "$out" --strip-components=2 data/meshes/femur.off

if [[ "${1:-}" == serve ]]; then
  # The page takes the token from the address once (#token=...), then keeps it for the tab.
  data="$out/service"
  mkdir -p "$data"
  [[ -s "$data/token" ]] || (umask 077 && head -c 24 /dev/urandom | od -An -tx1 | tr -d ' \n' > "$data/token")
  echo
  echo "== tpmsfill serve --data $data (Ctrl-C stops it)"
  echo "Open http://127.0.0.1:8080/#token=$(cat "$data/token") in a browser on this machine,"
  echo "drop $out/femur.off on the page, set 'scaled by' to 35 (it is 1 unit long), and press Fill."
  exec ./build/tpmsfill serve --listen 127.0.0.1:8080 --data "$data"
fi

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
echo
echo "Second demo, the service and its web page: bash scripts/demo.sh serve"
