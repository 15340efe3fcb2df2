#!/usr/bin/env bash
# Runs one job of each command with two builds of tpmsfill and compares what they write, byte
# for byte: the meshes, layers, fields and models, and the JSON reports (keys in order) less
# what differs from run to run (times, peak memory, paths). For refactors that must not change
# behaviour.
#   bash scripts/same_outputs.sh BEFORE_BINARY AFTER_BINARY [WORK_DIR]
# Exit 0 when every output is identical; otherwise the differing files are listed and it exits 1.
set -euo pipefail
before=$(realpath "$1")
after=$(realpath "$2")
work=${3:-$(mktemp -d)}
mkdir -p "$work/in"
here=$(cd "$(dirname "$0")/.." && pwd)

tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$work/in" --strip-components=2 \
  data/meshes/femur.off data/meshes/elephant.off data/meshes/bunny00.off data/images/skull_2.9.inr
python3 - "$work/in" <<'PY'
import math, sys
d = sys.argv[1]
# A 20 x 12 x 4 mm plate whose top is a bump: a surface for conformal layers (open, one loop).
n = 24
pts = [(20 * i / n, 12 * j / n, 2 * math.exp(-((i / n - .5) ** 2 + (j / n - .5) ** 2) * 8))
       for j in range(n + 1) for i in range(n + 1)]
tris = []
for j in range(n):
    for i in range(n):
        a = j * (n + 1) + i
        tris += [(a, a + 1, a + n + 2), (a, a + n + 2, a + n + 1)]
with open(f"{d}/bump.off", "w") as f:
    f.write(f"OFF\n{len(pts)} {len(tris)} 0\n")
    f.writelines(f"{x:.6f} {y:.6f} {z:.6f}\n" for x, y, z in pts)
    f.writelines(f"3 {a} {b} {c}\n" for a, b, c in tris)
# A 20 mm cube, for the recipes of docs/recipes/ (written for parts about that size).
pts = [(x, y, z) for z in (0, 20) for y in (0, 20) for x in (0, 20)]
quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
with open(f"{d}/cube.off", "w") as f:
    f.write("OFF\n8 12 0\n" + "".join("%d %d %d\n" % p for p in pts))
    f.write("".join("3 %d %d %d\n3 %d %d %d\n" % (a, b, c, a, c, e) for a, b, c, e in quads))
PY

jobs=(
  "fill-femur|fill in/femur.off OUT/femur.stl --scale 35 --cell 2 --voxel 0.1 --report OUT/femur.json --quiet"
  "fill-diamond-skin|fill in/femur.off OUT/diamond.stl --scale 35 --lattice diamond --sheet --cell 3 --voxel 0.1 --grade thickness 0.3 0.6 --grade-along z --skin 0.4 --report OUT/diamond.json --quiet"
  "fill-iwp-windows|fill in/femur.off OUT/iwp.stl --scale 35 --lattice iwp --sheet --cell 3 --voxel 0.12 --skin 0.5 --skin-windows --measure --report OUT/iwp.json --quiet"
  "fill-neovius|fill in/femur.off OUT/neovius.ply --scale 35 --lattice neovius --cell 3 --voxel 0.12 --rotate 20 30 40 --report OUT/neovius.json --quiet"
  "fill-splitp-graded|fill in/femur.off OUT/splitp.obj --scale 35 --lattice splitp --cell 2 --voxel 0.1 --grade cell 2 4 --grade-along x --measure --report OUT/splitp.json --quiet"
  "fill-parity|fill in/elephant.off OUT/parity.stl --inside parity --cell 0.1 --voxel 0.01 --report OUT/parity.json --quiet"
  "fill-slabs|fill in/femur.off OUT/slabs.stl --scale 35 --cell 2 --voxel 0.05 --memory 200M --report OUT/slabs.json --quiet"
  "fill-3mf|fill in/femur.off OUT/femur.3mf --scale 35 --cell 2 --voxel 0.12 --porosity 0.7 --skin 0.4 --report OUT/f3mf.json --quiet"
  "recipe-gyroid-primitive|fill in/cube.off OUT/r1.stl --voxel 0.15 --recipe $here/docs/recipes/hybrid-gyroid-primitive.json --report OUT/r1.json --quiet"
  "recipe-slab-sheet|fill in/cube.off OUT/r2.stl --voxel 0.15 --recipe $here/docs/recipes/hybrid-slab-sheet.json --report OUT/r2.json --quiet"
  "recipe-sphere-beta|fill in/cube.off OUT/r3.stl --voxel 0.15 --recipe $here/docs/recipes/hybrid-sphere-beta.json --report OUT/r3.json --quiet"
  "check|check in/bunny00.off --json"
  "repair|repair in/elephant.off OUT/elephant-fixed.off --json"
  "slice-cli|slice in/femur.off OUT/femur.cli --scale 35 --cell 2 --voxel 0.1 --layer 0.2 --report OUT/slice.json --quiet"
  "slice-svg|slice in/femur.off OUT/femur.svg --scale 35 --lattice diamond --sheet --cell 3 --voxel 0.1 --layer 0.5 --quiet"
  "decimate|decimate OUT/femur.stl OUT/femur-light.stl --tolerance 0.02 --report OUT/decimate.json --quiet"
  "render|render OUT/femur.stl OUT/femur.png --size 400 --quiet"
  "field-fit|field fit in/skull_2.9.inr OUT/skull.itdf --coefficients 16 --solid 2.9 inf --quiet"
  "field-mesh|field mesh OUT/skull.itdf OUT/skull.stl --voxel 2 --porosity 0.7 --quiet"
  "conformal|conformal in/bump.off OUT/bump-layer.stl --height 3 --cell 4 --voxel 0.2 --report OUT/conformal.json --quiet"
  "material-fit|material fit in/bunny00.off OUT/femur.tsm --material point 0 0 0 --quiet"
  "material-slice|material slice OUT/femur.tsm OUT/femur-material.cli --layer 1 --quiet"
  "material-iso|material iso OUT/femur.tsm OUT/femur-iso.ply --values 0.2 0.4 --quiet"
)

# The report's fields that change from run to run.
strip_json() {
  python3 - "$1" <<'PY'
import json, sys
VARYING = {"seconds", "wall_seconds", "peak_memory_bytes", "peak_memory_mb", "stages", "input",
           "output", "path", "threads", "created", "finished", "tool", "command_line"}
def clean(v):
    if isinstance(v, dict):
        return {k: clean(x) for k, x in v.items() if k not in VARYING and "seconds" not in k}
    if isinstance(v, list):
        return [clean(x) for x in v]
    return v
try:
    print(json.dumps(clean(json.load(open(sys.argv[1]))), indent=1))  # key order compared too
except ValueError:
    print(open(sys.argv[1], errors="replace").read())
PY
}

status=0
# SAME_OUTPUTS_COMPARE=1 compares what an earlier run left in WORK_DIR without running again.
[[ ${SAME_OUTPUTS_COMPARE:-0} == 1 ]] || for side in before after; do
  bin=${!side}
  mkdir -p "$work/$side"
  for job in "${jobs[@]}"; do
    name=${job%%|*}
    args=${job#*|}
    args=${args//OUT/$work/$side}
    (cd "$work" && $bin $args >"$side/$name.stdout" 2>"$side/$name.stderr") ||
      echo "$side: $name exited $? (see $work/$side/$name.stderr)" >>"$work/$side/exits.txt"
  done
done
for f in "$work/before"/*; do
  name=$(basename "$f")
  [[ -e "$work/after/$name" ]] || { echo "only before: $name"; status=1; continue; }
  case "$name" in
    *.json | *.stdout | *.stderr)
      if ! cmp -s <(strip_json "$f" | sed "s|$work/before|W|g") \
        <(strip_json "$work/after/$name" | sed "s|$work/after|W|g"); then
        echo "differs: $name"
        status=1
      fi
      ;;
    *.itdf | *.tsm)
      # They hold the fit's wall time: compared as `field info` reads them and through every
      # output made from them (field mesh, material slice and iso).
      if [[ $name == *.itdf ]] && ! cmp -s <("$after" field info "$f" | tail -n +2) \
        <("$after" field info "$work/after/$name" | tail -n +2); then
        echo "differs: $name"
        status=1
      fi
      ;;
    *)
      if [[ -d "$f" ]]; then
        diff -rq "$f" "$work/after/$name" >/dev/null || { echo "differs: $name/"; status=1; }
      elif ! cmp -s "$f" "$work/after/$name"; then
        echo "differs: $name"
        status=1
      fi
      ;;
  esac
done
count=$(find "$work/before" -maxdepth 1 -type f | wc -l)
((status == 0)) && echo "same outputs: ${#jobs[@]} jobs, $count files compared byte for byte ($work)"
exit $status
