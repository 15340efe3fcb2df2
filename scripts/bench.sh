#!/usr/bin/env bash
# Benchmarks behind docs/benchmarks.md. Usage: bash scripts/bench.sh [SPHERE_LEVELS]
#  1. read/write every format and check_mesh on an icosphere (default 8 levels: 1,310,720 triangles)
#  2. `tpmsfill check` on malformed files that declare huge counts: time and peak memory
#  3. `tpmsfill check` on the real meshes in ../shared/meshes, when that folder exists
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
command -v /usr/bin/time >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq time
bash scripts/build.sh build >/dev/null

echo "## machine: $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB, $(uname -m)"
echo
echo "## 1. formats and check_mesh"
./build/tests/bench_io_check "${1:-8}"

echo
echo "## 2. malformed files (exit code, wall time, peak RSS)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0123' >"$tmp/huge-count.ply"
printf 'OFF\n2000000000 2000000000 0\n0 0 0\n' >"$tmp/huge-count.off"
{ head -c 80 /dev/zero; printf '\xff\xff\xff\x7f'; head -c 500 /dev/zero; } >"$tmp/huge-count.stl"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\n' >"$tmp/index-out-of-range.obj"
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n' >"$tmp/nan.stl"
: >"$tmp/empty.stl"
echo "| file | exit | wall s | peak RSS MB | message |"
echo "|---|---:|---:|---:|---|"
for f in "$tmp"/*; do
  set +e
  /usr/bin/time -f "%e %M" -o "$tmp/time.txt" ./build/tpmsfill check "$f" >/dev/null 2>"$tmp/err.txt"
  code=$?
  set -e
  read -r wall kb < <(tail -n 1 "$tmp/time.txt")
  printf '| %s | %s | %s | %.0f | %s |\n' "$(basename "$f")" "$code" "$wall" "$(awk -v k="$kb" 'BEGIN{print k/1024}')" \
    "$(head -1 "$tmp/err.txt" | sed "s|$tmp/||")"
done

if [[ -d ../shared/meshes ]]; then
  echo
  echo "## 3. tpmsfill check on ../shared/meshes"
  echo "| file | exit | wall s | peak RSS MB | triangles | holes | SI pairs | components |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  for f in ../shared/meshes/*.{off,stl,STL,obj,ply}; do
    [[ -f "$f" ]] || continue
    set +e
    /usr/bin/time -f "%e %M" -o "$tmp/time.txt" ./build/tpmsfill check --json "$f" >"$tmp/out.json" 2>/dev/null
    code=$?
    set -e
    read -r wall kb < <(tail -n 1 "$tmp/time.txt")
    facts=$(python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print(" | ".join(str(j[k]) for k in ("triangles","holes","self_intersecting_pairs","components")))' "$tmp/out.json" 2>/dev/null || echo "- | - | - | -")
    printf '| %s | %s | %s | %.0f | %s |\n' "$(basename "$f")" "$code" "$wall" "$(awk -v k="$kb" 'BEGIN{print k/1024}')" "$facts"
  done
fi
