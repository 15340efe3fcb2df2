#!/usr/bin/env bash
# fill and slice under mpirun -n 3 give what one process gives: the same STL bytes, the same
# layer files. Run by ctest when tpmsfill is built with -DTPMSFILL_MPI=ON.
#   bash tests/mpi_test.sh TPMSFILL [MESH]
set -euo pipefail
cli=$1
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
mesh=${2:-}
if [[ -z "$mesh" || ! -f "$mesh" ]]; then
  # A torus-like test part without any file: a 12 mm box with a 4 mm square hole through it.
  mesh="$dir/part.off"
  python3 - "$mesh" <<'PY'
import sys
# Outer box 0..12, hole 4..8 in x and y, through z: 16 vertices, 32 triangles.
v = []
for z in (0, 12):
    for (x, y) in ((0, 0), (12, 0), (12, 12), (0, 12), (4, 4), (8, 4), (8, 8), (4, 8)):
        v.append((x, y, z))
def q(a, b, c, d, f): f += [(a, b, c), (a, c, d)]
f = []
# bottom (z=0, normal -z) and top (z=12, normal +z) rings between outer and inner squares
for k in range(4):
    a, b = k, (k + 1) % 4
    q(a, 4 + a, 4 + b, b, f)                 # bottom ring
    q(8 + a, 8 + b, 12 + b, 12 + a, f)       # top ring
    q(a, b, 8 + b, 8 + a, f)                 # outer wall
    q(4 + a, 12 + a, 12 + b, 4 + b, f)       # inner wall
with open(sys.argv[1], "w") as out:
    out.write("OFF\n%d %d 0\n" % (len(v), len(f)))
    for p in v: out.write("%g %g %g\n" % p)
    for t in f: out.write("3 %d %d %d\n" % t)
PY
  scale=1
else
  scale=35
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
run3() { mpirun -n 3 --oversubscribe "$cli" "$@"; }
job=(--scale "$scale" --cell 2 --voxel 0.1 --quiet)

"$cli" check "$mesh" > /dev/null
"$cli" fill "$mesh" "$dir/one.stl" "${job[@]}" --report "$dir/one.json"
run3 fill "$mesh" "$dir/three.stl" "${job[@]}" --report "$dir/three.json"
cmp "$dir/one.stl" "$dir/three.stl"
grep -q '"ranks": 3' "$dir/three.json"

for out in layers.cli layers.svg; do
  "$cli" slice "$mesh" "$dir/one-$out" "${job[@]}" --layer 0.2
  run3 slice "$mesh" "$dir/three-$out" "${job[@]}" --layer 0.2 --report "$dir/slice.json"
  cmp "$dir/one-$out" "$dir/three-$out"
done
grep -q '"ranks": 3' "$dir/slice.json"
"$cli" slice "$mesh" "$dir/one-png" "${job[@]}" --layer 0.2 --format png --pixel 0.1
run3 slice "$mesh" "$dir/three-png" "${job[@]}" --layer 0.2 --format png --pixel 0.1
for f in "$dir"/one-png/layer_*.png; do cmp "$f" "$dir/three-png/$(basename "$f")"; done
[[ $(ls "$dir/one-png" | wc -l) == $(ls "$dir/three-png" | wc -l) ]]
echo "mpi: fill and slice under 3 ranks equal one process"
