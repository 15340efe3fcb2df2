#!/usr/bin/env bash
# The main job on a real mesh: installs dependencies, builds Release, then checks the femur
# that Debian's libcgal-demo ships and prints where the outputs are.
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
status=0
./build/tpmsfill check "$out/femur.off" | tee "$out/femur-check.txt" || status=$?
./build/tpmsfill check "$out/femur.off" --json >"$out/femur-check.json" || true

echo
echo "input:  $out/femur.off (from $tarball)"
echo "report: $out/femur-check.txt"
echo "json:   $out/femur-check.json"
echo "exit code of check: $status (0: a valid closed 2-manifold)"
exit "$status"
