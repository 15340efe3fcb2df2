#!/usr/bin/env bash
# Fuzzes the mesh readers (3MF included), the recipe reader, the field/ITDF readers, the tet-mesh
# readers, the solid spline model reader (.tsm), the point-cloud reader and the service's job
# options with libFuzzer + ASan + UBSan, one run each.
#   scripts/fuzz.sh [seconds per reader] [reader...]   (default 120 s, every reader)
# Readers: auto stl obj ply off 3mf recipe volume tet-medit tet-tetgen tet-vtk model points
# options. Naming some runs those alone (the targets are built all the same).
# Findings (crash-*, leak-*, timeout-*, oom-*) land in build-fuzz/findings/<reader>/.
set -euo pipefail
seconds="${1:-120}"
only=("${@:2}")
readers=" auto stl obj ply off 3mf recipe volume tet-medit tet-tetgen tet-vtk model points options "
for name in "${only[@]}"; do
  [[ $readers == *" $name "* ]] || { echo "fuzz: no reader '$name' (readers:$readers)" >&2; exit 2; }
done
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-fuzz"

if ! command -v clang++ >/dev/null || ! dpkg -s libclang-rt-14-dev >/dev/null 2>&1; then
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y --no-install-recommends \
    clang libclang-rt-14-dev
fi

CC=clang CXX=clang++ cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DTPMSFILL_FUZZ=ON -DTPMSFILL_BUILD_TESTS=OFF -DTPMSFILL_BUILD_EXAMPLES=OFF
cmake --build "$build" --target read_mesh_fuzz read_recipe_fuzz read_volume_fuzz read_tet_mesh_fuzz \
  read_solid_model_fuzz read_points_fuzz service_options_fuzz
fuzzer="$build/tests/fuzz/read_mesh_fuzz"

# Seed corpus: one small valid file per format, written here, plus assimp's test models when
# the package is installed.
# (one folder per run, so two runs on different readers can share the build)
seeds=$(mktemp -d "$build/seeds.XXXXXX")
trap 'rm -rf "$seeds"' EXIT
mkdir -p "$seeds"/{auto,stl,obj,ply,off,3mf}
printf 'solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n' >"$seeds/stl/ascii.stl"
python3 - "$seeds/stl/binary.stl" <<'PY'
import struct, sys
with open(sys.argv[1], "wb") as f:
    f.write(b"solid but binary".ljust(80, b" ") + struct.pack("<I", 2))
    for z in (0.0, 1.0):
        f.write(struct.pack("<12fH", 0, 0, 1, 0, 0, z, 1, 0, z, 0, 1, z, 0))
PY
printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3//1 4\nf -4 -3 -2\n' >"$seeds/obj/quad.obj"
printf 'ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n' >"$seeds/ply/ascii.ply"
python3 - "$seeds/ply" <<'PY'
import struct, sys
for order, tag in (("<", "little"), (">", "big")):
    head = ("ply\nformat binary_%s_endian 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty double z\nelement face 1\n"
            "property list uchar uint vertex_indices\nend_header\n" % tag).encode()
    body = b"".join(struct.pack(order + "ffd", *p) for p in ((0, 0, 0), (1, 0, 0), (0, 1, 0)))
    body += struct.pack(order + "B3I", 3, 0, 1, 2)
    open("%s/%s.ply" % (sys.argv[1], tag), "wb").write(head + body)
PY
printf 'COFF 4 2 0\n# c\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n1 1 0 0 0 1 1\n0 1 0 1 1 1 1\n3 0 1 2\n4 0 1 2 3 255 0 0\n' >"$seeds/off/coff.off"
models=/usr/share/assimp/models
if [ -d "$models" ]; then
  find "$models/STL" -iname '*.stl' -size -64k -exec cp {} "$seeds/stl/" \; || true
  find "$models/OBJ" -name '*.obj' -size -64k -exec cp {} "$seeds/obj/" \; || true
  find "$models/PLY" -name '*.ply' -size -64k -exec cp {} "$seeds/ply/" \; || true
  find "$models/OFF" -name '*.off' -size -64k -exec cp {} "$seeds/off/" \; || true
fi
# 3MF: a small package written by the CLI built in build/ (lib3mf's own layout), when it is there.
if [ -x "$root/build/tpmsfill" ]; then
  tmp_off=$(mktemp --suffix=.off)
  printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n' >"$tmp_off"
  "$root/build/tpmsfill" repair "$tmp_off" "$seeds/3mf/tet.3mf" --quiet >/dev/null 2>&1 || true
  rm -f "$tmp_off"
fi
cp "$seeds"/{stl,obj,ply,off,3mf}/* "$seeds/auto/" 2>/dev/null || true
gzip -c "$seeds/stl/ascii.stl" >"$seeds/auto/ascii.stl.gz"

# lib3mf's own leak (tests/lsan.supp) is not a finding.
export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp"
# fuzz NAME PROGRAM MAX_LEN: one timed run on seeds/NAME, findings in findings/NAME.
status=0
fuzz() {
  local name=$1 program=$2 max_len=$3
  if [ ${#only[@]} -gt 0 ] && [[ " ${only[*]} " != *" $name "* ]]; then return 0; fi
  local corpus="$build/corpus/$name" findings="$build/findings/$name"
  mkdir -p "$corpus" "$findings"
  echo "== $name: ${seconds}s"
  "$program" "$corpus" "$seeds/$name" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=5 \
    -max_len="$max_len" -artifact_prefix="$findings/" -print_final_stats=1 2>&1 |
    grep -E '^(#[0-9]+ +DONE|stat::number_of_executed_units|==[0-9]+==ERROR|SUMMARY|artifact_prefix)' || true
  if compgen -G "$findings/*" >/dev/null; then
    echo "!! $name: findings in $findings" >&2
    status=1
  fi
}
for reader in auto stl obj ply off 3mf; do
  TPMSFILL_FUZZ_FORMAT="$reader" fuzz "$reader" "$fuzzer" 65536
done
# Recipes, seeded with the documented ones.
mkdir -p "$seeds/recipe"
cp "$root"/docs/recipes/*.json "$root"/docs/recipes/conformal/*.json "$seeds/recipe/"
# A grading by a volume (fill --grade-by): the fuzz build refuses the file it names.
printf '{"grading": [{"what": "porosity", "ramp": "volume", "volume": "m.tsm", "start": 0.5, "end": 0.8}]}\n' \
  >"$seeds/recipe/volume-ramp.json"
fuzz recipe "$build/tests/fuzz/read_recipe_fuzz" 8192
# Field files and ITDF, seeded with small files of every form (first byte: even = a field
# file, odd = ITDF), written by the CLI built in build/ when it is there.
mkdir -p "$seeds/volume"
python3 - "$seeds/volume" <<'PY'
import struct, sys, zlib, gzip
d = sys.argv[1]
vals = struct.pack("<8f", *range(8))
def put(name, b): open(f"{d}/{name}", "wb").write(b"\x00" + b)
put("a.tdf", b"tpmsfill-field 1\nsize 1 1 1\nsign signed\n2 2 2\n0 1 2 3\n4 5 6 7\n")
put("b.tdfb", b"TDFB" + struct.pack("<HBB3I3d", 1, 0, 1, 2, 2, 2, 0, 0, 0) + vals)
put("c.nrrd", b"NRRD0004\ntype: float\ndimension: 3\nsizes: 2 2 2\nspacings: 1 1 2\nencoding: raw\n\n" + vals)
put("d.nrrd", b"NRRD0004\ntype: short\ndimension: 3\nsizes: 2 1 1\nencoding: ascii\n\n1 2\n")
put("e.mha", b"NDims = 3\nDimSize = 2 2 2\nElementType = MET_FLOAT\nCompressedData = True\nElementDataFile = LOCAL\n" + zlib.compress(vals))
h = b"#INRIMAGE-4#{\nXDIM=2\nYDIM=2\nZDIM=2\nVDIM=1\nTYPE=float\nPIXSIZE=32 bits\nCPU=decm\nVX=1\nVY=1\nVZ=1\n"
put("f.inr", h.ljust(252, b"\n") + b"##}\n" + vals)
put("g.nrrd.gz", gzip.compress(b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1 1 2\n\n\x01\x02"))
PY
if [ -x "$root/build/tpmsfill" ]; then
  tmp_itdf=$(mktemp --suffix=.itdf)
  tail -c +2 "$seeds/volume/a.tdf" >"${tmp_itdf%.itdf}.tdf"
  "$root/build/tpmsfill" field fit "${tmp_itdf%.itdf}.tdf" "$tmp_itdf" --coefficients 2 --degree 1 --quiet &&
    { printf '\x01'; cat "$tmp_itdf"; } >"$seeds/volume/h.itdf"
  rm -f "$tmp_itdf" "${tmp_itdf%.itdf}.tdf"
fi
fuzz volume "$build/tests/fuzz/read_volume_fuzz" 65536
# Tet meshes (MEDIT, TetGen, VTK), one reader at a time. An input is: a byte (the format when
# TPMSFILL_FUZZ_FORMAT is unset), the first file's length (2 bytes, little-endian), the first
# file (.mesh, .node, .vtk), the second (.sol, .ele; for VTK a non-empty rest names the array).
mkdir -p "$seeds"/tet-{medit,tetgen,vtk}
python3 - "$seeds" <<'PY'
import struct, sys
d = sys.argv[1]
def put(fmt, name, first, second=b""):
    code = {"medit": 0, "tetgen": 1, "vtk": 2}[fmt]
    open(f"{d}/tet-{fmt}/{name}", "wb").write(bytes([code]) + struct.pack("<H", len(first)) + first + second)
put("medit", "unit.mesh", b"MeshVersionFormatted 2\nDimension 3\n# c\nVertices\n5\n0 0 0 0\n1 0 0 0\n"
    b"0 1 0 0\n0 0 1 0\n1 1 1 0\nEdges 1\n1 2 0\nTriangles 1 1 2 3 0\nTetrahedra\n2\n1 2 3 4 0\n"
    b"2 3 4 5 0\nCorners 1 1\nEnd\n",
    b"MeshVersionFormatted 2\nDimension 3\nSolAtVertices\n5\n2 2 1\n0 0 0 1\n0 0 0 2\n0 0 0 3\n"
    b"0 0 0 4\n0 0 0 5\nEnd\n")
put("tetgen", "one.node", b"5 3 1 1\n1 0 0 0 0.5 0\n2 1 0 0 1.5 1\n3 0 1 0 2.5 0\n4 0 0 1 3.5 0\n"
    b"5 1 1 1 4.5 0\n", b"2 4 1\n1 1 2 3 4 7\n2 2 3 4 5 7\n")
put("tetgen", "zero10.node", b"# zero-based\r\n4 3 0 0\r\n0 0 0 0\r\n1 1 0 0\r\n2 0 1 0\r\n3 0 0 1\r\n",
    b"1 10 0\r\n0 0 1 2 3 0 1 2 3 0 1\r\n")
put("vtk", "classic.vtk", b"# vtk DataFile Version 3.0\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
    b"POINTS 5 float\n0 0 0 1 0 0 0 1 0 0 0 1 1 1 1\nCELLS 3 14\n4 0 1 2 3\n4 1 2 3 4\n3 0 1 2\n"
    b"CELL_TYPES 3\n10 10 5\nCELL_DATA 3\nSCALARS r int 1\nLOOKUP_TABLE default\n1 2 3\n"
    b"POINT_DATA 5\nVECTORS v float\n0 0 0 0 0 0 0 0 0 0 0 0 0 0 0\nSCALARS material double\n"
    b"LOOKUP_TABLE default\n1 2 3 4 5\nFIELD f 1\nm 1 5 float\n1 2 3 4 5\n", b"x")
put("vtk", "v51.vtk", b"# vtk DataFile Version 5.1\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
    b"POINTS 4 double\n0 0 0 1 0 0 0 1 0 0 0 1\nMETADATA\nINFORMATION 0\n\nCELLS 2 4\n"
    b"OFFSETS vtktypeint64\n0 4\nCONNECTIVITY vtktypeint64\n0 1 2 3\nCELL_TYPES 1\n10\n")
put("vtk", "attributes.vtk", b"# vtk DataFile Version 4.2\nt\nASCII\nDATASET UNSTRUCTURED_GRID\n"
    b"FIELD FieldData 1\nTIME 1 1 double\n0.5\nPOINTS 4 float\n0 0 0 1 0 0 0 1 0 0 0 1\n"
    b"CELLS 2 7\n4 0 1 2 3\n1 0\nCELL_TYPES 2\n10 1\nPOINT_DATA 4\nCOLOR_SCALARS c 2\n0 0 1 1 0 0 1 1\n"
    b"LOOKUP_TABLE lut 1\n0 0 0 1\nNORMALS n float\n0 0 1 0 0 1 0 0 1 0 0 1\n"
    b"TEXTURE_COORDINATES uv 1 float\n0 1 0 1\nTENSORS6 t float\n" + b"0 " * 24 +
    b"\nGLOBAL_IDS ids int\n0 1 2 3\nSCALARS e vtktypeint64 1\nLOOKUP_TABLE default\n1 2 3 4\n"
    b"METADATA\nINFORMATION 0\n\n")
put("medit", "sections.mesh", b"MeshVersionFormatted 1\nDimension\n3\nTetrahedraP2 1\n1 2 3 4 1 2 3 4 1 2 0\n"
    b"Vertices 4\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\nQuadrilaterals 1 1 2 3 4 0\nRidges 1 1\n"
    b"NormalAtVertices 1 1 1\nNormals 1 0 0 1\nIdentifier\n\"x y\"\nGeometry g.mesh\nEnd\n",
    b"MeshVersionFormatted 2\nDimension 3\nTime 0.5\nSolAtTetrahedra\n1\n1 3\n1 2 3 4 5 6\n"
    b"SolAtVertices\n4\n2 2 1\n0 0 0 1\n0 0 0 2\n0 0 0 3\n0 0 0 4\nEnd\n")
be = b"# vtk DataFile Version 3.0\nb\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 4 float\n"
be += struct.pack(">12f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
be += b"\nCELLS 1 5\n" + struct.pack(">5i", 4, 0, 1, 2, 3) + b"\nCELL_TYPES 1\n" + struct.pack(">i", 10)
be += b"\nPOINT_DATA 4\nSCALARS material double 1\nLOOKUP_TABLE default\n" + struct.pack(">4d", 1, 2, 3, 4) + b"\n"
put("vtk", "binary.vtk", be)
PY
for reader in medit tetgen vtk; do
  TPMSFILL_FUZZ_FORMAT="$reader" fuzz "tet-$reader" "$build/tests/fuzz/read_tet_mesh_fuzz" 65536
done
# Solid spline models: small ones written by the CLI built in build/ (a uniform 4³ basis, THB
# at level 2 and at level 3 on a coarse box's tets). The reader builds the THB basis from the
# octree bits, so inputs are kept to 16 KiB (a few thousand leaves).
mkdir -p "$seeds/model"
if [ -x "$root/build/tpmsfill" ] && [ -f "$root/build/examples/example_box.stl" ]; then
  tets=$(mktemp --suffix=.vtk)
  "$root/build/tpmsfill" material info "$root/build/examples/example_box.stl" --cell 8 \
    --material z 0 1 --tets "$tets" >/dev/null 2>&1 &&
    "$root/build/tpmsfill" material fit "$tets" "$seeds/model/u4.tsm" --uniform 4 --quiet &&
    "$root/build/tpmsfill" material fit "$tets" "$seeds/model/thb.tsm" --refinements 0 \
      --max-tets-per-cell 1000000 --quiet &&
    "$root/build/tpmsfill" material fit "$tets" "$seeds/model/thb3.tsm" --refinements 0 \
      --max-tets-per-cell 20 --max-level 3 --quiet || true
  rm -f "$tets"
fi
fuzz model "$build/tests/fuzz/read_solid_model_fuzz" 16384
# Point clouds: XYZ text (comments, commas, extra columns), a PLY's vertices, gzipped XYZ.
mkdir -p "$seeds/points"
printf '# x y z\n0 0 0\n1,0,0\n0 1 0 0 0 1\n0\t0\t1\n' >"$seeds/points/a.xyz"
printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 1 1\n' >"$seeds/points/b.ply"
gzip -c "$seeds/points/a.xyz" >"$seeds/points/c.xyz.gz"
fuzz points "$build/tests/fuzz/read_points_fuzz" 65536
# The service's job options: a byte for the kind (check, repair, fill, slice, material-fit,
# material-slice, material-iso), then the JSON; seeded with each kind's documented options.
mkdir -p "$seeds/options"
python3 - "$seeds/options" "$root/docs/recipes" <<'PY'
import glob, sys
d, recipes = sys.argv[1:3]
def put(name, kind, text): open(f"{d}/{name}", "wb").write(bytes([kind]) + text.encode())
put("check", 0, '{"units": "mm", "self_intersections": false}')
put("repair", 1, '{"alpha": 0.5, "tolerance": 0.01}')
put("slice", 3, '{"layer": 0.1, "format": "svg", "recipe": {"voxel": 0.2}}')
put("material-slice", 5, '{"layer": 0.5, "format": "svg"}')
put("material-iso", 6, '{"level": 0.5}')
for i, f in enumerate(sorted(glob.glob(f"{recipes}/*.json"))[:8]):
    put(f"fill{i}", 2, open(f).read())
PY
# What earlier runs found, kept as seeds so that each stays fixed.
cp "$root"/tests/fuzz/regressions/options-* "$seeds/options/" 2>/dev/null || true
fuzz options "$build/tests/fuzz/service_options_fuzz" 16384
exit $status
