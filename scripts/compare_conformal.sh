#!/usr/bin/env bash
# The conformal jobs of docs/benchmarks.md §15 with two builds, side by side: wall time, the
# layout's distortion figures, the output's triangles and validity, and how far the meshes lie
# apart (scripts/mesh_difference.py). For changes to the layout that should move the meshes
# only by rounding.
#   bash scripts/compare_conformal.sh BEFORE_BINARY AFTER_BINARY [WORK_DIR]
set -euo pipefail
before=$(realpath "$1")
after=$(realpath "$2")
work=${3:-$(mktemp -d)}
here=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$work"
python3 "$here/scripts/surfaces.py" "$work" >/dev/null
tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$work" --strip-components=2 \
  data/meshes/nefertiti.off data/meshes/blade.off data/meshes/lion-head.off data/meshes/mushroom.off
cases=(
  "dome|hemisphere.off --height 3 --lattice primitive --cell 5 --voxel 0.3"
  "wave|wave.off --height 3 --lattice gyroid --cell 5 --voxel 0.3"
  "face|nefertiti.off --scale 20 --height 3 --lattice primitive --cell 5 --voxel 0.3"
  "blade|blade.off --scale 2.5 --height 4 --recipe $here/docs/recipes/conformal/blade-rings.json --voxel 0.4"
  "dome-vertex|hemisphere.off --height 3 --lattice primitive --cell 5 --voxel 0.3 --map vertex"
  "lion-head|lion-head.off --scale 100 --height 3 --lattice primitive --cell 5 --voxel 0.3"
  "mushroom|mushroom.off --scale 60 --height 3 --lattice primitive --cell 5 --voxel 0.3"
)
for c in "${cases[@]}"; do
  name=${c%%|*}
  read -r -a args <<<"${c#*|}"
  input="$work/${args[0]}"
  args=("${args[@]:1}")
  voxel=0
  for ((i = 0; i + 1 < ${#args[@]}; ++i)); do [[ ${args[i]} == --voxel ]] && voxel=${args[i + 1]}; done
  echo "== $name: ${c#*|}"
  for build in before after; do
    bin=$before
    [[ $build == after ]] && bin=$after
    start=$(date +%s.%N)
    "$bin" conformal "$input" "$work/$name-$build.stl" --quiet --report "$work/$name-$build.json" \
      "${args[@]}"
    end=$(date +%s.%N)
    python3 - "$work/$name-$build.json" "$build" "$start" "$end" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); l = r["conformal"]["layout"]
a, g = l["area_scale"], l["angle_distortion"]
print(f"  {sys.argv[2]:6} {float(sys.argv[4]) - float(sys.argv[3]):6.2f} s  flips {l['flips']}  "
      f"area scale {a['p5']:.6g}/{a['p50']:.6g}/{a['p95']:.6g}  angle {g['p5']:.6g}/{g['p50']:.6g}/{g['p95']:.6g}  "
      f"triangles {r['output']['triangles']:,}  valid {r['valid']}")
PY
  done
  python3 "$here/scripts/mesh_difference.py" "$work/$name-before.stl" "$work/$name-after.stl" "$voxel" |
    sed 's/^/  /'
done
