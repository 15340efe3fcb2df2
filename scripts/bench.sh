#!/usr/bin/env bash
# Benchmarks behind docs/benchmarks.md. Usage: bash scripts/bench.sh [all|io|fill|inside|repair|lattice|field|conformal|any|vs-openvdb|decimate|decimate-meshes|decimate-cgal|material|material-fit|material-unfold|material-tables|material-tspline|material-audit|material-slice|material-grade|placement|memory|seed000|layout|interop] [SPHERE_LEVELS]
#  io:
#  1. read/write every format and check_mesh on an icosphere (default 8 levels: 1,310,720 triangles)
#  2. `tpmsfill check` on malformed files that declare huge counts: time and peak memory
#  3. `tpmsfill check` on the real meshes in ../shared/meshes, when that folder exists
#  layout:
# 35. seed 004's distortion: the square layout against auto (the free, as-rigid-as-possible
#     layout where it has no flips and spreads the area scale less) on the dome, the wave, the
#     face, the blade, lion-head and mushroom; flips, area scale, angle ratio, cells against the
#     size asked, time, and what a job the cells refuse says
#  seed000:
# 34. seed 000/002's Table 2 side by side: the femur and the thin-walled tube, P and G, at the
#     paper's sample counts (a = 0.1 mm; the femur scaled to 5.6e6 samples), each with the band
#     and with --full-field: boundary-voxel, distance and full-field distance times, samples,
#     band, distance queries, triangles, eq. 11's F from the geometry and from our stage times
#  fill:
#  4. `tpmsfill fill` end to end (read -> validated STL written) on the paper's two cases at our
#     scale: Debian's femur scaled to 35 mm and a 4.7-million-triangle thin-walled tube, gyroid
#     network T = 2 mm, C = 0, a = 0.1 mm; per-stage time and peak memory from --report
#  5. the femur with --full-field: the distance computations the band saves
#  6. `tpmsfill fill` on every mesh of ../shared/meshes (holes and all), checked afterwards
#  inside:
#  7. classification time, winding number vs parity, on the femur at a = 0.1 mm (bench_classify),
#     and the same femur with three holes cut into it
#  repair:
#  8. `tpmsfill repair` on every mesh of ../shared/meshes, the output checked afterwards
#  lattice:
#  9. porosity asked vs measured for all 8 types, network and sheet, in a cube of whole cells
#     at two voxel sizes
# 10. the femur filled with each lattice-design feature: wall time, compose time, porosity
#  field:
# 14. seed 003: the skull CT fitted at 16³, 32³, 48³ (direct and LSPIA), fit time 128³ → 32³ and
#     256³ → 64³, grid evaluation rate, ground-truth Hausdorff distances (bench_fit), ITDF
#     against binary STL sizes, porosity asked vs measured with `field mesh`
#  conformal:
# 15. seed 004: `tpmsfill conformal` on the dome, the wave, Debian's Nefertiti face and blade at
#     a voxel of H/10 (layout flips and distortion, cells on the surface, heights, time, memory),
#     and the layout alone on libcgal-demo's other disks
#  material:
# 20. seed 001: `tpmsfill material info` (tetrahedralize, geodesic material, cube map) on
#     libcgal-demo's genus-0 meshes at two tet sizes
# 21. seed 001: `tpmsfill material fit`, THB against the uniform baseline (control points,
#     iterations, RS of G and M, errors, time) on the same meshes at diagonal / 30
# 21c (material-unfold). seed 001: G kept fold-free (`material fit`, the default) against the
#     plain fit as it folds (--allow-folds), three rounds, on the same meshes
# 21b (material-tables). seed 001's Tables 1-2 side by side: its models' stand-ins (the genus-0
#     upper piece of libcgal-demo's femur, cut and capped by `tpmsfill repair`; assimp-testmodels'
#     Collada duck, converted by assimp-utils and repaired), THB with each model's marking and
#     the seed's uniform n³, Euler and Newton steps to one stopping rule, with the seed's
#     nc / ni / RS in the same rows; the lower piece (its handles cut, capped by repair) by
#     Euler steps only, with its cube map's folded tets by pass (about 90 min in all)
# 21d (material-tspline). seed 001's T-splines on the octrees of those six models: functions
#     against THB's, how far they are from summing to one, pairs not dual-compatible
# 22b (material-audit). issue 40's acceptance per model (the four above, the upper femur, the
#     duck, the lower femur): folds, the fold bound, the stack's volume against the surface's, turned-over
#     triangles, iso-surfaces' pieces against the tets' own (FIT_ARGS="..." adds options to
#     the fits)
# 22. seed 001: direct slicing of those THB models at three tau and the default, the sections'
#     areas against the surface's and the tets' own, and their cracks (bench_solid_slice), and
#     `material slice` of whole stacks
#  any:
# 16. any size: the femur at 35 mm and a = 0.0175 mm (1.1e9 samples) filled with the whole grid
#     and in streamed slabs within --memory 4G and 1G (time, peak RSS, same bytes); sliced at 0.05 mm layers
#     (time per layer, peak RSS, volume against fill's); under mpirun -n 1, 2, 3 (fill and slice
#     at a = 0.05 mm; times, same bytes) where Open MPI is installed
#  vs-openvdb:
# 17. vs-openvdb: issue 16's baseline, `tpmsfill fill` against the OpenVDB 10 pipeline of
#     ../shared/peers/openvdb_tpms (built into build-openvdb_tpms/; its build.sh installs Debian's
#     libopenvdb-dev when run as root) on the femur at 35 mm (a = 0.1 and 0.05 mm) and the
#     4.7-million-triangle tube (a = 0.1 mm), gyroid network T = 2 mm, 2 threads each: medians of
#     VS_RUNS (default 5) alternating runs (tpmsfill, reference --eval lut, reference --eval direct)
#     of wall time and peak RSS, both tools' per-stage medians, both outputs checked side by side,
#     and tpmsfill's stages at 1 and 2 threads on the femur at 0.05 mm. `all` runs it only where
#     the peer's folder is there and libopenvdb-dev is installed already; otherwise it says why not
#  decimate:
# 19. `tpmsfill fill --decimate voxel/4` on the femur at 35 mm, a = 0.05 mm (issue 17's target:
#     at least 4x fewer triangles, still valid) and on every mesh of ../shared/meshes: triangles
#     before and after, measured distances both ways, volume change, rounds, time, peak memory,
#     and `tpmsfill check` of the written file (each mesh stopped after 900 s by `timeout`);
#     `decimate-meshes` runs the meshes only
#  placement:
# 26. every mesh of ../shared/meshes, and every mesh of libcgal-demo and assimp-testmodels that
#     `tpmsfill check` calls valid, filled at its own position and moved by (150, 150, 0) and
#     (0, 0, -1000), to binary STL, read back and checked (bench_placement); then the preflight's
#     forecast (triangles, seconds) against what ran on the femur and the tube of section 4
#  memory:
# 27. fill's memory estimate against the measured peak (whole process, /usr/bin/time) on every
#     mesh of ../shared/meshes and three of libcgal-demo's at three voxels (cell = longest side
#     / 15; voxel = cell / 10, / 15, / 20), then the same jobs under --memory at half their
#     whole-grid estimate (slabs): the peak must stay under the budget
#  slow-clients:
# 28. `tpmsfill serve` while N clients (0, 70, 200) each trickle a header byte every 200 ms and
#     never finish: the seconds GET /v1/health takes (20 requests), and when the slow ones are
#     let go
#  decimate-cgal:
# 19. `tpmsfill decimate IN OUT --tolerance D/500` (D: the bounding box's diagonal) on every mesh
#     of libcgal-demo's data/meshes that `tpmsfill check` calls valid, each output checked
set -euo pipefail
#  interop:
# 36. scenes and OpenVDB (issue 42): `tpmsfill check` on assimp-testmodels' scenes (COLLADA,
#     zipped COLLADA, glTF with a .bin, GLB, FBX, 3DS, SMD); fill with and without
#     --field-out on the femur at 35 mm (a = 0.1 mm), the level set's size and its reading back
#     (field info), and fill --field with it; a truncated .vdb read
cd "$(dirname "$0")/.."
bash scripts/setup.sh
command -v /usr/bin/time >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq time
bash scripts/build.sh build >/dev/null
section="${1:-all}"
[[ "$section" =~ ^(all|io|fill|inside|repair|lattice|field|conformal|any|vs-openvdb|decimate|decimate-meshes|decimate-cgal|material|material-fit|material-unfold|material-tables|material-tspline|material-audit|material-slice|material-grade|placement|memory|slow-clients|seed000|layout|interop)$ ]] || { levels_arg="$section"; section=all; }
levels="${levels_arg:-${2:-8}}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# timed COMMAND...: runs it, a failure being data rather than the script's end, and sets
# code (exit status), wall (s) and kb (peak RSS). Redirections on the call apply to COMMAND.
timed() {
  set +e
  /usr/bin/time -f "%e %M" -o "$tmp/time.txt" "$@"
  code=$?
  set -e
  read -r wall kb < <(tail -n 1 "$tmp/time.txt")
}

# A service in folder $1 (made if missing; token bench-token-0123456789) on a free port, with
# the rest of the arguments as serve's flags: sets $server (its pid) and $port.
start_service() {
  local dir=$1
  shift
  mkdir -p "$dir"
  printf 'bench-token-0123456789\n' >"$dir/token"
  chmod 600 "$dir/token"
  ./build/tpmsfill serve --listen 127.0.0.1:0 --data "$dir" --token-file "$dir/token" "$@" \
    >"$dir/out.txt" 2>&1 &
  server=$!
  for _ in $(seq 100); do grep -q "listening on" "$dir/out.txt" && break; sleep 0.1; done
  port=$(sed -n 's|^listening on http://127.0.0.1:\([0-9]*\)$|\1|p' "$dir/out.txt")
}

# Sections 21 and 22: libcgal-demo's genus-0 meshes that map at diagonal / 30, into $tmp/mat.
extract_material_meshes() {
  mkdir -p "$tmp/mat"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp/mat" --strip-components=2 \
    data/meshes/bunny00.off data/meshes/bear.off data/meshes/fandisk.off data/meshes/sphere.off \
    2>/dev/null || true
}
# The seed's models' stand-ins (§21b): the femur's upper and lower ends and the duck, as
# $tmp/mat/upper-femur.off, $tmp/mat/lower-femur.off and $tmp/mat/duck.off.
extract_seed_models() {
  mkdir -p "$tmp/mat"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp/mat" --strip-components=2 \
    data/meshes/femur.off 2>/dev/null || true
  command -v assimp >/dev/null || DEBIAN_FRONTEND=noninteractive apt-get install -y -qq assimp-utils >/dev/null
  # The femur's pieces above and below 30 % of its height, each cut capped by repair. The
  # lower holds both of the mesh's handles (genus 2): narrow tunnels, between the condyles and
  # behind the medial one, each cut by taking out the triangles within 0.01 of a point on it
  # (found by a search over balls, each position's genus counted), so that repair caps those
  # holes too; both pieces genus 0, as the cube map needs.
  for piece in upper lower; do
    python3 - "$tmp/mat/femur.off" "$tmp/mat/femur-$piece.off" "$piece" <<'PY'
import math, sys
tok = open(sys.argv[1]).read().split()
nv, nf = int(tok[1]), int(tok[2]); at = 4
pts = [tuple(map(float, tok[at + 3 * i: at + 3 * i + 3])) for i in range(nv)]; at += 3 * nv
cut = min(p[2] for p in pts) + 0.3 * (max(p[2] for p in pts) - min(p[2] for p in pts))
upper = sys.argv[3] == "upper"
tunnels = [] if upper else [(-0.0995077, -0.0139117, -0.335913), (-0.00626382, -0.0674182, -0.439003)]
kept = lambda p: (p[2] >= cut if upper else p[2] <= cut) and all(math.dist(p, c) > 0.01 for c in tunnels)
faces = []
for _ in range(nf):
    n = int(tok[at]); f = list(map(int, tok[at + 1: at + 1 + n])); at += 1 + n
    if all(kept(pts[v]) for v in f): faces.append(f)
used = sorted({v for f in faces for v in f}); new = {v: i for i, v in enumerate(used)}
with open(sys.argv[2], "w") as o:
    o.write(f"OFF\n{len(used)} {len(faces)} 0\n")
    for v in used: o.write("%r %r %r\n" % pts[v])
    for f in faces: o.write(f"{len(f)} " + " ".join(str(new[v]) for v in f) + "\n")
PY
    ./build/tpmsfill repair "$tmp/mat/femur-$piece.off" "$tmp/mat/$piece-femur.off" --quiet
  done
  assimp export /usr/share/assimp/models/Collada/duck.dae "$tmp/mat/duck.obj" >/dev/null
  ./build/tpmsfill repair "$tmp/mat/duck.obj" "$tmp/mat/duck.off" --quiet
}
# The seed's material rule for a model, as the array `material`: the duck's distance to its
# box's centre (after material_sizes), the others' geodesic distance from the bottom.
seed_material() {
  if [[ $1 == duck ]]; then
    material=(--material point $(python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["bbox"]; print(*[(b["min"][i]+b["max"][i])/2 for i in range(3)])' "$tmp/c.json"))
  elif [[ $1 == lower-femur ]]; then  # its cut is at the top
    material=(--material geodesic "$depth" --up 0 0 -1)
  else
    material=(--material geodesic "$depth")
  fi
}
# A mesh's box diagonal and height, its tet size (diagonal / 30) and geodesic source depth
# (diagonal / 100), as diag, zspan, cell, depth; fails for a mesh `tpmsfill check` refuses.
material_sizes() {
  ./build/tpmsfill check --json "$1" >"$tmp/c.json" 2>/dev/null || return 1
  read -r diag zspan < <(python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["bbox"]; print(sum((b["max"][i]-b["min"][i])**2 for i in range(3))**0.5, b["max"][2]-b["min"][2])' "$tmp/c.json")
  cell=$(python3 -c "print($diag / 30)")
  depth=$(python3 -c "print($diag / 100)")
}

echo "## machine: $(nproc) cores, $(free -g | awk '/Mem:/ {print $2}') GiB, $(uname -m)"
if [[ "$section" == all || "$section" == io ]]; then
echo
echo "## 1. formats and check_mesh"
./build/tests/bench_io_check "$levels"

echo
echo "## 2. malformed files (exit code, wall time, peak RSS)"
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0123' >"$tmp/huge-count.ply"
printf 'OFF\n2000000000 2000000000 0\n0 0 0\n' >"$tmp/huge-count.off"
{ head -c 80 /dev/zero; printf '\xff\xff\xff\x7f'; head -c 500 /dev/zero; } >"$tmp/huge-count.stl"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4000000000\n' >"$tmp/index-out-of-range.obj"
printf 'solid x\nfacet normal 0 0 1\nouter loop\nvertex nan 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n' >"$tmp/nan.stl"
: >"$tmp/empty.stl"
echo "| file | exit | wall s | peak RSS MB | message |"
echo "|---|---:|---:|---:|---|"
for f in "$tmp"/*; do
  timed ./build/tpmsfill check "$f" >/dev/null 2>"$tmp/err.txt"
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
    timed ./build/tpmsfill check --json "$f" >"$tmp/out.json" 2>/dev/null
    facts=$(python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); print(" | ".join(str(j[k]) for k in ("triangles","holes","self_intersecting_pairs","components")))' "$tmp/out.json" 2>/dev/null || echo "- | - | - | -")
    printf '| %s | %s | %s | %.0f | %s |\n' "$(basename "$f")" "$code" "$wall" "$(awk -v k="$kb" 'BEGIN{print k/1024}')" "$facts"
  done
fi
fi

# One `tpmsfill fill` run: wall time and peak RSS of the whole process, then the per-stage
# table from its report.
fill_case() {
  local name=$1 in=$2
  shift 2
  timed ./build/tpmsfill fill "$in" "$tmp/$name-out.stl" --quiet --report "$tmp/$name.json" "$@"
  ((code == 0)) || exit "$code"
  python3 - "$tmp/$name.json" "$name" "$wall" "$kb" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
name, wall, kb = sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
print(f"### {name}: {wall:.2f} s wall, {kb/1024:.0f} MB peak RSS (whole process)")
print(f"grid {r['grid']['dims']} = {r['grid']['samples']:,} samples; band {r['band_nodes']:,}; "
      f"distance queries {r['distance_queries']:,}; output {r['output']['triangles']:,} triangles; "
      f"porosity {100*r['porosity']:.2f} % (unclipped {100*r['unclipped_porosity']:.2f} %); "
      f"valid {r['valid']}, self-intersecting pairs {r['validation']['self_intersecting_pairs']}")
print()
print("| stage | s | peak MB |")
print("|---|---:|---:|")
for s in r["stages"]:
    print(f"| {s['name']} | {s['seconds']:.3f} | {s['peak_memory_mb']:.0f} |")
print(f"| **sum of stages** | **{r['total_seconds']:.3f}** | |")
print()
PY
}

if [[ "$section" == all || "$section" == fill ]]; then
  echo
  echo "## 4. fill, end to end (gyroid network, T = 2 mm, C = 0, a = 0.1 mm)"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  ./build/tests/bench_fill_inputs "$tmp/femur.off" "$tmp"
  echo
  fill_case femur35 "$tmp/femur35.stl" --cell 2 --voxel 0.1
  fill_case tube "$tmp/tube.stl" --cell 2 --voxel 0.1

  echo "## 5. femur with --full-field (distance at every node, the paper's reference)"
  fill_case femur35-full-field "$tmp/femur35.stl" --cell 2 --voxel 0.1 --full-field

  if [[ -d ../shared/meshes ]]; then
    echo "## 6. fill on every mesh of ../shared/meshes (cell and voxel scaled to each mesh)"
    echo "| file | exit | wall s | peak MB | triangles out | porosity % | unclipped % | holes capped | flipped | pieces turned | overlap rows | parity would differ | rim evaluations | clean s | classify s | check of output |"
    echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
    for f in ../shared/meshes/*.{off,stl,STL,obj,ply}; do
      [[ -f "$f" ]] || continue
      ./build/tpmsfill check --no-self-intersections --json "$f" >"$tmp/c.json" 2>/dev/null || true
      # cell = longest side / 15, voxel = cell / 10.
      read -r cell voxel < <(python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); b=j["bbox"]; L=max(b["max"][i]-b["min"][i] for i in range(3)); print(L/15, L/150)' "$tmp/c.json" 2>/dev/null || echo "0 0")
      [[ "$cell" != 0 ]] || continue
      timed ./build/tpmsfill fill "$f" "$tmp/shared-out.stl" --quiet \
        --cell "$cell" --voxel "$voxel" --report "$tmp/shared.json" 2>"$tmp/err.txt"
      verdict="-"
      if [[ $code == 0 ]]; then
        ./build/tpmsfill check "$tmp/shared-out.stl" >/dev/null && verdict="valid" || verdict="NOT VALID"
        facts=$(python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); i=r["inside"]; t={s["name"]: s["seconds"] for s in r["stages"]}; print("%d | %.2f | %.2f | %d | %d | %d | %d | %d | %d | %.3f | %.3f" % (r["output"]["triangles"], 100*r["porosity"], 100*r["unclipped_porosity"], i["holes"], i["flipped_triangles"], i["reversed_pieces"], i["overlap_rows"], i["parity_disagreements"], i["cap_evaluations"], t.get("clean", 0), t["classify"]))' "$tmp/shared.json")
      else
        facts="$(head -c 80 "$tmp/err.txt") | - | - | - | - | - | - | - | - | - | -"
      fi
      printf '| %s | %s | %s | %.0f | %s | %s |\n' "$(basename "$f")" "$code" "$wall" "$(awk -v k="$kb" 'BEGIN{print k/1024}')" "$facts" "$verdict"
    done
  fi
fi

if [[ "$section" == all || "$section" == interop ]]; then
  echo
  echo "## 36. scenes through assimp, OpenVDB in and out"
  models=/usr/share/assimp/models
  echo "| file | triangles | verdict | wall s | peak MB |"
  echo "|---|---|---|---|---|"
  for f in Collada/duck.dae Collada/duck.zae glTF2/BoxTextured-glTF/BoxTextured.gltf \
    glTF2/BoxTextured-glTF-Binary/BoxTextured.glb FBX/spider.fbx 3DS/fels.3ds SMD/WusonSMD.smd; do
    timed ./build/tpmsfill check --no-self-intersections --json "$models/$f" >"$tmp/scene.json"
    python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print(f\"| {sys.argv[2]} | {j['triangles']} | {'valid' if j['valid'] else 'not valid'} | {sys.argv[3]} | {int(sys.argv[4])//1024} |\")" \
      "$tmp/scene.json" "$f" "$wall" "$kb"
  done
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  echo
  echo "| femur at 35 mm, a = 0.1 mm | wall s | peak MB | file |"
  echo "|---|---|---|---|"
  timed ./build/tpmsfill fill "$tmp/femur.off" "$tmp/f.stl" --quiet --scale 35 --cell 2 --voxel 0.1
  echo "| fill | $wall | $((kb / 1024)) | $(stat -c %s "$tmp/f.stl") bytes STL |"
  timed ./build/tpmsfill fill "$tmp/femur.off" "$tmp/f.stl" --quiet --scale 35 --cell 2 --voxel 0.1 \
    --field-out "$tmp/phi.vdb"
  echo "| fill --field-out phi.vdb | $wall | $((kb / 1024)) | $(stat -c %s "$tmp/phi.vdb") bytes VDB |"
  timed ./build/tpmsfill field info "$tmp/phi.vdb" >/dev/null
  echo "| field info phi.vdb (dense $(./build/tpmsfill field info "$tmp/phi.vdb" | head -1 | sed 's/.*field, //')) | $wall | $((kb / 1024)) | |"
  # The lattice's own level set as the femur's structure: stretched over the same box, it
  # gives the lattice back (up to the fit and a voxel).
  ./build/tpmsfill fill "$tmp/femur.off" "$tmp/f.stl" --quiet --scale 35 --cell 2 --voxel 0.1 \
    --report "$tmp/a.json"
  timed ./build/tpmsfill fill "$tmp/femur.off" "$tmp/g.stl" --quiet --scale 35 --voxel 0.1 \
    --field "$tmp/phi.vdb" --report "$tmp/b.json" 2>/dev/null
  porosity() { python3 -c "import json,sys; print(round(json.load(open(sys.argv[1]))['porosity'], 4))" "$1"; }
  echo "| fill --field phi.vdb (fitted on reading; porosity $(porosity "$tmp/b.json") against the gyroid's $(porosity "$tmp/a.json")) | $wall | $((kb / 1024)) | exit $code |"
  head -c 200 "$tmp/phi.vdb" >"$tmp/cut.vdb"
  timed ./build/tpmsfill field info "$tmp/cut.vdb" 2>/dev/null
  echo "| field info on its first 200 bytes (refused) | $wall | $((kb / 1024)) | exit $code |"
fi

if [[ "$section" == all || "$section" == seed000 ]]; then
  echo
  echo "## 34. seed 000/002's Table 2 side by side (a = 0.1 mm, T = 2 mm, C = 0, network)"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  ./build/tests/bench_fill_inputs "$tmp/femur.off" "$tmp" >/dev/null
  # The paper's femur box, 20 x 20 x 14 mm at a = 0.1 mm, is 201 x 201 x 141 = 5.70e6 samples:
  # its 5.6e6. Debian's femur (0.40 : 0.34 : 1) scaled by 33.5 gives a grid of 5.62e6 samples.
  : >"$tmp/seed000.tsv"
  for model in femur tube; do
    if [[ $model == femur ]]; then in="$tmp/femur.off" scale=33.5; else in="$tmp/tube.stl" scale=1; fi
    ./build/tpmsfill check --no-self-intersections --json "$in" >"$tmp/seed000-check.json"
    for type in primitive gyroid; do
      for field in band full; do
        # The model's distance does not depend on the lattice: the tube's whole grid runs once.
        [[ $field == full && $model == tube && $type == gyroid ]] && continue
        extra=()
        [[ $field == full ]] && extra=(--full-field)
        # The tube's whole grid: nodes near its axis are almost equidistant from the whole inner
        # wall, so no tree prunes their queries; it runs SEED000_LIMIT s (default 900) at most.
        limit=()
        [[ $field == full && $model == tube ]] && limit=(timeout "${SEED000_LIMIT:-900}")
        timed "${limit[@]}" ./build/tpmsfill fill "$in" "$tmp/seed000-out.stl" --quiet --scale "$scale" \
          --lattice "$type" --cell 2 --voxel 0.1 --report "$tmp/seed000-$model-$type-$field.json" "${extra[@]}"
        if ((code == 124)); then
          rm -f "$tmp/seed000-$model-$type-$field.json"
        elif ((code != 0)); then
          exit "$code"
        fi
        printf '%s\t%s\t%s\t%s\t%s\n' "$model" "$type" "$field" "$wall" "$kb" >>"$tmp/seed000.tsv"
      done
    done
    cp "$tmp/seed000-check.json" "$tmp/seed000-check-$model.json"
  done
  python3 - "$tmp" <<'PY'
import json, sys
tmp = sys.argv[1]
a = 0.1
scale = {"femur": 33.5, "tube": 1.0}
# Table 2 of seed 000 (002 is the same paper): size, triangles, samples, boundary-voxel s,
# distance s, the original method's distance s (its ref. [13]).
paper = {("femur", "primitive"): ("20×20×14", 424290, 5.6e6, 78, 410, 1.7e4),
         ("femur", "gyroid"): ("20×20×14", 521354, 5.6e6, 76, 414, 1.7e4),
         ("tube", "primitive"): ("40×40×20", 4767164, 3.2e7, 313, 1017, 3.2e4),
         ("tube", "gyroid"): ("40×40×20", 3693576, 3.2e7, 316, 1028, 3.2e4)}
runs = {}
for line in open(f"{tmp}/seed000.tsv"):
    m, t, f, wall, kb = line.split()
    try:
        r = json.load(open(f"{tmp}/seed000-{m}-{t}-{f}.json"))
    except FileNotFoundError:  # stopped by the time limit
        r = None
    st = {s["name"]: s["seconds"] for s in r["stages"]} if r else {}
    runs[m, t, f] = (r, st, float(wall), float(kb) / 1024)
geo = {}
for m in scale:
    c = json.load(open(f"{tmp}/seed000-check-{m}.json"))
    k = scale[m]  # check reads the file as it is; fill scaled it
    L, W, H = ((c["bbox"]["max"][i] - c["bbox"]["min"][i]) * k for i in range(3))
    S = c["area"] * k * k
    geo[m] = (L, W, H, S, (L / a + 1) * (W / a + 1) * (H / a + 1) / (S / a**2))
print("| model | lattice | box mm (ours / paper) | samples (ours / paper) | triangles out (ours / paper) | boundary voxels s: classify + band (ours / paper) | distance s (ours / paper) | whole grid's distance s (ours with --full-field / paper's ref. [13]) | distance queries band / grid | F from stage times (ours / paper) | F of eq. 11 (ours) | whole job s: band / full field | peak MB |")
print("|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for (m, t), (box, tri, smp, bv, dist, orig) in paper.items():
    r, st, wall, mb = runs[m, t, "band"]
    rf, stf, wallf, mbf = runs.get((m, t, "full")) or runs[m, "gyroid" if t == "primitive" else "primitive", "full"]
    L, W, H, S, F11 = geo[m]
    ours_box = f"{L:.1f}×{W:.1f}×{H:.1f}"
    bvs = st["classify"] + st["band"]
    if rf:
        full_s, F_time = f"{stf['distance']:.2f}", f"{stf['distance'] / st['distance']:.0f}"
    else:
        full_s, F_time = f"> {wallf:.0f} (stopped)", f"> {wallf / st['distance']:.0f}"
    print(f"| {m} | {'P' if t == 'primitive' else 'G'} | {ours_box} / {box} | {r['grid']['samples']:.3g} / {smp:.2g} | "
          f"{r['output']['triangles']:,} / {tri:,} | {bvs:.3f} / {bv} | {st['distance']:.3f} / {dist} | "
          f"{full_s} / {orig:.2g} | {r['distance_queries']:,} / {r['grid']['samples']:,} "
          f"({r['grid']['samples'] / r['distance_queries']:.1f}×) | {F_time} / {orig / dist:.0f} | "
          f"≥ {F11:.0f} | {wall:.2f} / {wallf:.2f}{'' if rf else ' (stopped)'} | {mb:.0f} / {mbf:.0f} |")
print()
for m in scale:
    L, W, H, S, F11 = geo[m]
    print(f"{m}: L×W×H = {L:.2f}×{W:.2f}×{H:.2f} mm, S = {S:.1f} mm², a = {a} mm: "
          f"(L/a+1)(W/a+1)(H/a+1)/(S/a²) = {F11:.1f}; the paper's right-hand form a(L+a)(W+a)(H+a)/S "
          f"= {a * (L + a) * (W + a) * (H + a) / S:.2f} (its a belongs in the denominator)")
print()
print("Ours: every output above is validated (closed, 2-manifold, outward, no self-intersections) before it is written:")
for (m, t, f), (r, st, wall, mb) in sorted(runs.items()):
    if r:
        print(f"- {m} {t} {f}: valid {r['valid']}, porosity {100 * r['porosity']:.2f} %, validate {st['validate']:.2f} s")
    else:
        print(f"- {m} {t} {f}: stopped after {wall:.0f} s")
PY
fi

if [[ "$section" == all || "$section" == inside ]]; then
  echo
  echo "## 7. classification: winding number vs parity (femur 35 mm, a = 0.1 mm)"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  ./build/tests/bench_classify "$tmp/femur.off" 5
fi

if [[ "$section" == all || "$section" == repair ]] && [[ -d ../shared/meshes ]]; then
  echo
  echo "## 8. repair on ../shared/meshes (defaults; output STL checked by tpmsfill check)"
  echo "| file | exit | wall s | peak MB | triangles in → out | defects found → fixed | wrapped (alpha, offset mm) | check of output |"
  echo "|---|---:|---:|---:|---|---|---|---|"
  for f in ../shared/meshes/*.{off,stl,STL,obj,ply}; do
    [[ -f "$f" ]] || continue
    rm -f "$tmp/repaired.stl"
    timed ./build/tpmsfill repair "$f" "$tmp/repaired.stl" --json >"$tmp/repair.json" 2>/dev/null
    verdict="nothing written"
    if [[ -f "$tmp/repaired.stl" ]]; then
      ./build/tpmsfill check "$tmp/repaired.stl" >/dev/null && verdict="valid" || verdict="NOT VALID"
    fi
    facts=$(python3 - "$tmp/repair.json" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
acts = "; ".join(f"{a['defect']} {a['found']} → {a['fixed']}" for a in j["actions"] if a["found"])
wrap = f"yes ({j['alpha']:.3g}, {j['offset']:.3g})" if j["wrapped"] else "no"
print(f"{j['before']['triangles']} → {j['after']['triangles']} | {acts or 'none'} | {wrap}")
PY
)
    printf '| %s | %s | %s | %.0f | %s | %s |\n' "$(basename "$f")" "$code" "$wall" \
      "$(awk -v k="$kb" 'BEGIN{print k/1024}')" "$facts" "$verdict"
  done
fi

if [[ "$section" == all || "$section" == lattice ]]; then
  printf 'OFF\n8 12 0\n0 0 0\n4 0 0\n4 4 0\n0 4 0\n0 0 4\n4 0 4\n4 4 4\n0 4 4\n3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n' >"$tmp/cube4.off"
  echo
  echo "## 9. porosity asked (0.7) vs measured, 4 mm cube = 2 x 2 x 2 cells of T = 2 mm, islands kept"
  echo "| type | network a = 0.1 | network a = 0.05 | sheet a = 0.1 | sheet a = 0.05 | solved level / thickness mm |"
  echo "|---|---:|---:|---:|---:|---|"
  for type in primitive gyroid diamond iwp neovius frd lidinoid splitp; do
    row="| $type"
    solved=""
    for style in "" --sheet; do
      for a in 0.1 0.05; do
        ./build/tpmsfill fill "$tmp/cube4.off" "$tmp/p.stl" --quiet --lattice "$type" $style \
          --porosity 0.7 --voxel "$a" --keep-islands --no-self-intersections --report "$tmp/p.json"
        read -r por value < <(python3 -c 'import json,sys; r=json.load(open(sys.argv[1])); l=r["lattice"]; print(100*r["porosity"], l["thickness"] if "sheet" in l["type"] else l["level"])' "$tmp/p.json")
        row="$row | $(printf '%.2f %%' "$por")"
        [[ "$a" == 0.05 ]] && solved="$solved $(printf '%.4f' "$value")"
      done
    done
    echo "$row | $solved |"
  done

  echo
  echo "## 10. the femur (35 mm, a = 0.1 mm) with each lattice-design feature"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  ./build/tests/bench_fill_inputs "$tmp/femur.off" "$tmp" >/dev/null
  cat >"$tmp/hybrid.json" <<'JSON'
{"lattice": {"type": "gyroid", "cell": 2, "porosity": 0.7},
 "blends": [{"lattice": {"type": "primitive"},
             "region": {"shape": "half-space", "point": [0, 0, 0], "axis": [0, 0, 1]},
             "width": 3, "transition": "beta"}]}
JSON
  echo "| design | wall s | compose s | porosity % | components | valid |"
  echo "|---|---:|---:|---:|---:|---|"
  design() {
    local name=$1
    shift
    timed ./build/tpmsfill fill "$tmp/femur35.stl" "$tmp/d.stl" --quiet --cell 2 --voxel 0.1 \
      --report "$tmp/d.json" "$@"
    ((code == 0)) || exit "$code"
    python3 - "$tmp/d.json" "$name" "$wall" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
wall = float(sys.argv[3])
compose = [s["seconds"] for s in r["stages"] if s["name"] == "compose"][0]
print(f"| {sys.argv[2]} | {wall:.2f} | {compose:.3f} | {100 * r['porosity']:.2f} | "
      f"{r['output']['components']} | {r['valid']} |")
PY
  }
  design "gyroid network, level 0"
  design "iwp sheet, --porosity 0.7" --lattice iwp --sheet --porosity 0.7
  design "gyroid, --rotate 30 20 10" --rotate 30 20 10
  design "gyroid, porosity 0.5 -> 0.85 by depth 0-3 mm" --grade porosity 0.5 0.85 --grade-along depth --grade-range 0 3
  design "gyroid, cell 1.5 -> 3 along z" --grade cell 1.5 3 --grade-along z
  design "gyroid, --porosity 0.7" --porosity 0.7
  design "gyroid, --porosity 0.7, cell 1.5 -> 3 by depth 0-3 mm" --porosity 0.7 --grade cell 1.5 3 \
    --grade-along depth --grade-range 0 3
  design "gyroid/primitive hybrid (recipe, Beta, 3 mm)" --recipe "$tmp/hybrid.json"
  design "gyroid, --skin 0.5" --skin 0.5
  design "gyroid, --skin 0.5 --skin-windows" --skin 0.5 --skin-windows
fi

if [[ "$section" == all || "$section" == field ]]; then
  echo "## 14. Seed 003: fitting a scanned field, ITDF sizes, porosity"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 \
    data/images/skull_2.9.inr
  echo "| coefficients | method | fit s | RMS / range | max error | cells across 2.9 | ITDF bytes |"
  echo "|---|---|---:|---:|---:|---:|---:|"
  for n in 16 32 48; do
    for method in direct lspia; do
      ./build/tpmsfill field fit "$tmp/skull_2.9.inr" "$tmp/s.itdf" --coefficients "$n" \
        --solid 2.9 inf --method "$method" --max-iterations 100 >"$tmp/fit.txt"
      python3 - "$tmp/fit.txt" "$n" "$method" "$(stat -c %s "$tmp/s.itdf")" <<'PY'
import re, sys
t = open(sys.argv[1]).read()
fit_s = re.search(r"\((?:direct|lspia), ([0-9.e+-]+) s", t).group(1)
rms = re.search(r"RMS [0-9.e+-]+ \(([0-9.]+) %", t).group(1)
mx = re.search(r"max ([0-9.e+-]+)", t).group(1)
fl = re.search(r"([0-9.]+) % of the cells changed side \((\d+)\)", t)
print(f"| {sys.argv[2]}³ | {sys.argv[3]} | {fit_s} | {rms} % | {mx} | {fl.group(1)} % ({fl.group(2)}) | {sys.argv[4]} |")
PY
    done
  done
  echo
  ./build/tests/bench_fit
  echo
  echo "| structure | voxel mm | triangles | binary STL bytes | ITDF bytes | STL / ITDF |"
  echo "|---|---:|---:|---:|---:|---:|"
  ./build/tpmsfill field fit "$tmp/skull_2.9.inr" "$tmp/skull.itdf" --coefficients 32 --solid 2.9 inf --quiet
  for voxel in 2 1; do
    ./build/tpmsfill field mesh "$tmp/skull.itdf" "$tmp/skull.stl" --voxel "$voxel" --quiet
    stl=$(stat -c %s "$tmp/skull.stl") itdf=$(stat -c %s "$tmp/skull.itdf")
    echo "| skull bone (32³, float32) | $voxel | $(((stl - 84) / 50)) | $stl | $itdf | $((stl / itdf)) |"
  done
  ./build/tpmsfill field fit "$tmp/skull_2.9.inr" "$tmp/skull16.itdf" --coefficients 32 --solid 2.9 inf \
    --coefficient-type int16 --quiet
  stl=$(stat -c %s "$tmp/skull.stl") itdf=$(stat -c %s "$tmp/skull16.itdf")
  echo "| skull bone (32³, int16) | 1 | $(((stl - 84) / 50)) | $stl | $itdf | $((stl / itdf)) |"
  echo
  echo "| porosity asked | measured (field mesh, skull bone) | measured (sponge) |"
  echo "|---:|---:|---:|"
  python3 scripts/sponge_field.py "$tmp/sponge.tdf" 20
  ./build/tpmsfill field fit "$tmp/sponge.tdf" "$tmp/sponge.itdf" --coefficients 24 --solid 0 inf --quiet
  for p in 0.5 0.7 0.85; do
    row="| $p"
    for f in skull sponge; do
      voxel=$([[ $f == skull ]] && echo 1 || echo 0.1)
      ./build/tpmsfill field mesh "$tmp/$f.itdf" "$tmp/p.stl" --voxel "$voxel" --porosity "$p" \
        --keep-islands >"$tmp/p.txt" 2>/dev/null
      row+=" | $(grep -E '^porosity +[0-9.]+ %' "$tmp/p.txt" | grep -oE '[0-9.]+ %' | head -n 1)"
    done
    echo "$row |"
  done
  # fill --field on every development mesh (holes, flips, several shells), at a voxel of
  # 1/120 of each one's diagonal, the sponge structure stretched over it at porosity 0.7.
  meshes=../shared/meshes
  if [[ -d "$meshes" ]]; then
    echo
    echo "| mesh | exit | s | triangles out | porosity | valid | warnings / error |"
    echo "|---|---:|---:|---:|---:|---|---|"
    for f in "$meshes"/*.{off,stl,STL,obj,ply}; do
      [[ -f "$f" ]] || continue
      voxel=$( (./build/tpmsfill check "$f" --json 2>/dev/null || true) | python3 -c "
import json, sys, math
b = json.load(sys.stdin)['bbox']
print('%.4g' % (math.dist(b['min'], b['max']) / 120))" 2>/dev/null) || voxel=1
      start=$(date +%s.%N)
      code=0
      ./build/tpmsfill fill "$f" "$tmp/ff.stl" --field "$tmp/sponge.itdf" --porosity 0.7 \
        --voxel "$voxel" --report "$tmp/ff.json" --quiet 2>"$tmp/ff.err" || code=$?
      secs=$(printf '%.2f' "$(echo "$(date +%s.%N) - $start" | bc)")
      if ((code == 0)); then
        python3 - "$tmp/ff.json" "$(basename "$f")" "$secs" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
w = "; ".join(x[:x.find(":")] if ":" in x else x[:60] for x in r.get("warnings", [])) or "-"
print(f"| {sys.argv[2]} | 0 | {float(sys.argv[3]):.2f} | {r['output']['triangles']} | "
      f"{100 * r['porosity']:.1f} % | {r['valid']} | {w} |")
PY
      else
        echo "| $(basename "$f") | $code | $secs | - | - | - | $(head -c 90 "$tmp/ff.err" | tr '|' '/') |"
      fi
    done
  fi
fi

if [[ "$section" == all || "$section" == conformal ]]; then
  echo
  echo "## 15. seed 004: lattice layers on surfaces (tpmsfill conformal, voxel H/10)"
  python3 scripts/surfaces.py "$tmp"
  cgal=/usr/share/doc/libcgal-demo/data.tar.gz
  [[ -f "$cgal" ]] && tar -xzf "$cgal" -C "$tmp" --strip-components=2 data/meshes/nefertiti.off \
    data/meshes/blade.off data/meshes/lion-head.off data/meshes/mushroom.off
  echo "| surface | job | wall s | peak MB | flips | area scale p5/p50/p95 | angle p5/p50/p95 | cells mm p5-p95 | smallest radius mm | heights mm | triangles | valid | warnings |"
  echo "|---|---|---:|---:|---:|---|---|---|---:|---|---:|---|---:|"
  conformal_case() {
    local name=$1 in=$2
    shift 2
    [[ -f "$in" ]] || { echo "| $name | (missing: libcgal-demo) |"; return; }
    timed ./build/tpmsfill conformal "$in" "$tmp/$name.stl" --quiet --report "$tmp/$name.json" "$@" \
      2>"$tmp/$name.err"
    ((code == 0)) || { echo "| $name | exit $code: $(head -1 "$tmp/$name.err") |"; return; }
    python3 - "$tmp/$name.json" "$name" "$wall" "$kb" "$(grep -c warning "$tmp/$name.err" || true)" "$*" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); c = r["conformal"]; l = c["layout"]
name, wall, kb, warnings, job = sys.argv[2], float(sys.argv[3]), float(sys.argv[4]), sys.argv[5], sys.argv[6]
a, g, s = l["area_scale"], l["angle_distortion"], c["cell_size"]
focal = "none" if c["focal_distance"] is None else f"{c['focal_distance']:.3g}"
print(f"| {name} | {job} | {wall:.2f} | {kb/1024:.0f} | {l['flips']} | {a['p5']:.3g}/{a['p50']:.3g}/{a['p95']:.3g} "
      f"| {g['p5']:.3g}/{g['p50']:.3g}/{g['p95']:.3g} | {s['p5']:.3g}-{s['p95']:.3g} | {focal} "
      f"| {c['height_min']:.3g} to {c['height_max']:.3g} | {r['output']['triangles']:,} | {r['valid']} | {warnings} |")
PY
  }
  conformal_case dome "$tmp/hemisphere.off" --height 3 --lattice primitive --cell 5 --voxel 0.3
  conformal_case wave "$tmp/wave.off" --height 3 --lattice gyroid --cell 5 --voxel 0.3
  conformal_case face "$tmp/nefertiti.off" --scale 20 --height 3 --lattice primitive --cell 5 --voxel 0.3
  conformal_case blade "$tmp/blade.off" --scale 2.5 --height 4 --recipe docs/recipes/conformal/blade-rings.json --voxel 0.4
  conformal_case blade-in "$tmp/blade.off" --height 0.3 --side in --lattice gyroid --cell 1 --voxel 0.03
  conformal_case dome-vertex "$tmp/hemisphere.off" --height 3 --lattice primitive --cell 5 --voxel 0.3 --map vertex
  conformal_case wave-vertex "$tmp/wave.off" --height 3 --lattice gyroid --cell 5 --voxel 0.3 --map vertex
  conformal_case face-vertex "$tmp/nefertiti.off" --scale 20 --height 3 --lattice primitive --cell 5 --voxel 0.3 --map vertex
  conformal_case lion-head "$tmp/lion-head.off" --scale 100 --height 3 --lattice primitive --cell 5 --voxel 0.3
  conformal_case mushroom "$tmp/mushroom.off" --scale 60 --height 3 --lattice primitive --cell 5 --voxel 0.3
  echo
  echo "threads: the face at 1 and 2 threads (identical output)"
  for t in 1 2; do
    timed ./build/tpmsfill conformal "$tmp/nefertiti.off" "$tmp/face-$t.stl" --quiet --scale 20 \
      --height 3 --lattice primitive --cell 5 --voxel 0.3 --threads "$t"
    echo "- $t thread(s): $wall s"
  done
  cmp -s "$tmp/face-1.stl" "$tmp/face-2.stl" && echo "- outputs byte-identical" || echo "- OUTPUTS DIFFER"
fi

if [[ "$section" == all || "$section" == layout ]]; then
  echo
  echo "## 35. seed 004's distortion: the square layout against auto (free where it does better)"
  python3 scripts/surfaces.py "$tmp" >/dev/null
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/nefertiti.off \
    data/meshes/blade.off data/meshes/lion-head.off data/meshes/mushroom.off
  echo "| surface | layout asked | exit | wall s | layout s | layout | free rounds | flips | area scale p5/p50/p95 | angle p5/p50/p95 | cells mm p5-p95 (× asked) | valid | message |"
  echo "|---|---|---:|---:|---:|---|---:|---:|---|---|---|---|---|"
  layout_case() {
    local name=$1 in=$2 layout=$3
    shift 3
    local extra=()
    [[ $layout == square ]] && extra=(--allow-distortion)
    timed ./build/tpmsfill conformal "$in" "$tmp/$name.stl" --quiet --report "$tmp/$name.json" \
      --layout "$layout" "${extra[@]}" "$@" 2>"$tmp/$name.err"
    if ((code != 0)); then
      echo "| $name | $layout | $code | $wall | - | - | - | - | - | - | - | - | $(head -1 "$tmp/$name.err" | sed 's/|/\//g') |"
      return
    fi
    python3 - "$tmp/$name.json" "$name" "$layout" "$wall" "$*" <<'PY'
import json, sys, re
r = json.load(open(sys.argv[1])); c = r["conformal"]; l = c["layout"]
name, layout, wall, job = sys.argv[2], sys.argv[3], float(sys.argv[4]), sys.argv[5]
asked = float(re.search(r"--cell ([0-9.]+)", job).group(1)) if "--cell" in job else 5.0
a, g, s = l["area_scale"], l["angle_distortion"], c["cell_size"]
t = {x["name"]: x["seconds"] for x in r["stages"]}
print(f"| {name} | {layout} | 0 | {wall:.2f} | {t['parameterize']:.2f} | {l['method']} | {l['free_iterations']} | {l['flips']} "
      f"| {a['p5']:.3g}/{a['p50']:.3g}/{a['p95']:.3g} | {g['p5']:.3g}/{g['p50']:.3g}/{g['p95']:.3g} "
      f"| {s['p5']:.3g}-{s['p95']:.3g} ({s['p5']/asked:.2f}-{s['p95']/asked:.2f}) | {r['valid']} | "
      f"{len(r['warnings'])} warning(s) |")
PY
  }
  for layout in square auto; do
    layout_case dome "$tmp/hemisphere.off" "$layout" --height 3 --lattice primitive --cell 5 --voxel 0.3
    layout_case wave "$tmp/wave.off" "$layout" --height 3 --lattice gyroid --cell 5 --voxel 0.3
    layout_case face "$tmp/nefertiti.off" "$layout" --scale 20 --height 3 --lattice primitive --cell 5 --voxel 0.3
    layout_case blade "$tmp/blade.off" "$layout" --scale 2.5 --height 4 --lattice primitive --cell 5 --voxel 0.4
    layout_case lion-head "$tmp/lion-head.off" "$layout" --scale 100 --height 3 --lattice primitive --cell 5 --voxel 0.3
    layout_case mushroom "$tmp/mushroom.off" "$layout" --scale 60 --height 3 --lattice primitive --cell 5 --voxel 0.3
  done
fi

if [[ "$section" == all || "$section" == any ]]; then
  echo
  echo "## 16. Any size: slabs and slices"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  femur="$tmp/femur.off"
  job=(--scale 35 --cell 2)
  summary() {  # NAME: one line from the fill report
    python3 - "$tmp/$1.json" "$1" "$wall" "$kb" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {r['grid']['samples']:,} | {r['slab_planes'] or 'whole grid'} | "
      f"{float(sys.argv[3]):.1f} | {float(sys.argv[4])/1024:.0f} | {r['output']['triangles']:,} | "
      f"{r['valid']} | {r['lattice_volume'] + r['islands_volume']:.2f} |")
PY
  }
  echo "| job | samples | slabs (planes) | wall s | peak MB | triangles | valid | volume with islands mm3 |"
  echo "|---|---:|---:|---:|---:|---:|---|---:|"
  # The whole grid needs about 7 GB: run it only where that leaves room.
  if (($(free -g | awk '/Mem:/ {print $7}') >= 10)); then
    timed ./build/tpmsfill fill "$femur" "$tmp/whole.stl" "${job[@]}" --voxel 0.0175 --memory 64G \
      --quiet --report "$tmp/fill-whole.json"
    summary fill-whole
  fi
  # Over the budget the slabs stream: the output is validated and written as it is made.
  timed ./build/tpmsfill fill "$femur" "$tmp/slabs.stl" "${job[@]}" --voxel 0.0175 --memory 4G \
    --quiet --report "$tmp/fill-slabs.json"
  summary fill-slabs
  timed ./build/tpmsfill fill "$femur" "$tmp/slabs-1g.stl" "${job[@]}" --voxel 0.0175 --memory 1G \
    --quiet --report "$tmp/fill-slabs-1g.json"
  summary fill-slabs-1g
  cmp -s "$tmp/slabs.stl" "$tmp/slabs-1g.stl" || echo "- OUTPUTS DIFFER (4G, 1G)"
  [[ -f "$tmp/whole.stl" ]] && { cmp -s "$tmp/whole.stl" "$tmp/slabs.stl" &&
    echo "- whole grid and streamed slabs (4G, 1G): STL byte-identical" || echo "- OUTPUTS DIFFER"; }
  rm -f "$tmp/whole.stl" "$tmp/slabs-1g.stl"
  timed ./build/tpmsfill slice "$femur" "$tmp/femur.cli" "${job[@]}" --voxel 0.0175 --layer 0.05 \
    --binary --quiet --report "$tmp/slice.json"
  python3 - "$tmp/slice.json" "$tmp/fill-slabs.json" "$wall" "$kb" "$(stat -c %s "$tmp/femur.cli")" <<'PY'
import json, sys
s, f = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
wall, kb, size = float(sys.argv[3]), float(sys.argv[4]), int(sys.argv[5])
n = s["slice"]["layers"]
kept = f["lattice_volume"] + f["islands_volume"]  # fill's lattice with its islands kept
print(f"- slice, layers 0.05 mm, a = 0.0175 mm, binary CLI: {n} layers, {wall:.1f} s "
      f"({1000*wall/n:.0f} ms a layer), {kb/1024:.0f} MB peak, {size/1e6:.0f} MB file, "
      f"{s['slice']['contours']:,} contours; volume {s['slice']['volume']:.2f} mm3 against "
      f"fill's {kept:.2f} (islands kept): {100*(s['slice']['volume']/kept-1):+.2f} %")
PY
  # Depth-graded porosity: slice reads the depth from fill's grid planes within the ramp's reach.
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 \
    data/meshes/elephant-with-holes.off
  graded=(--scale 30 --cell 3 --voxel 0.1 --porosity 0.7 --grade porosity 0.5 0.8 --grade-along depth)
  timed ./build/tpmsfill fill "$tmp/elephant-with-holes.off" "$tmp/e.stl" "${graded[@]}" \
    --keep-islands --quiet --report "$tmp/e-fill.json"
  fill_wall=$wall
  timed ./build/tpmsfill slice "$tmp/elephant-with-holes.off" "$tmp/e.cli" "${graded[@]}" \
    --layer 0.1 --quiet --report "$tmp/e-slice.json"
  python3 - "$tmp/e-fill.json" "$tmp/e-slice.json" "$fill_wall" "$wall" "$kb" <<'PY'
import json, sys
f, s = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
print(f"- depth-graded elephant at 30 mm, a = 0.1, L = 0.1: fill --keep-islands {float(sys.argv[3]):.1f} s, "
      f"slice {float(sys.argv[4]):.1f} s ({s['slice']['layers']} layers, {float(sys.argv[5])/1024:.0f} MB); "
      f"volume {s['slice']['volume']:.1f} against {f['lattice_volume']:.1f} mm3: "
      f"{100*(s['slice']['volume']/f['lattice_volume']-1):+.2f} %")
PY
  if command -v mpirun >/dev/null && grep -q "TPMSFILL_MPI:BOOL=ON" build/CMakeCache.txt; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    echo
    # One thread a rank, so that the ranks, not the threads, share the cores.
    echo "| mpirun -n (1 thread each) | fill a = 0.05 wall s | peak MB (largest process) | slice a = 0.05, L = 0.05 wall s |"
    echo "|---:|---:|---:|---:|"
    for n in 1 2 3; do
      timed mpirun -n "$n" --oversubscribe ./build/tpmsfill fill "$femur" "$tmp/mpi-$n.stl" "${job[@]}" \
        --voxel 0.05 --threads 1 --quiet
      fw=$wall fk=$kb
      timed mpirun -n "$n" --oversubscribe ./build/tpmsfill slice "$femur" "$tmp/mpi-$n.cli" "${job[@]}" \
        --voxel 0.05 --layer 0.05 --threads 1 --quiet
      echo "| $n | $fw | $((fk / 1024)) | $wall |"
    done
    cmp -s "$tmp/mpi-1.stl" "$tmp/mpi-3.stl" && cmp -s "$tmp/mpi-1.cli" "$tmp/mpi-3.cli" &&
      echo "- 1, 2 and 3 ranks: STL and CLI byte-identical" || echo "- OUTPUTS DIFFER"
    # Over the budget rank 0 streams the parts as they arrive.
    timed mpirun -n 3 --oversubscribe ./build/tpmsfill fill "$femur" "$tmp/mpi-3s.stl" "${job[@]}" \
      --voxel 0.05 --threads 1 --memory 250M --quiet --report "$tmp/mpi-3s.json"
    python3 - "$tmp/mpi-3s.json" "$wall" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
peak = max(s["peak_memory_mb"] for s in r["stages"])
print(f"- mpirun -n 3 --memory 250M (rank 0 streams): {float(sys.argv[2]):.2f} s, rank 0 peak "
      f"{peak:.0f} MB, slabs of {r['slab_planes']} planes")
PY
    cmp -s "$tmp/mpi-1.stl" "$tmp/mpi-3s.stl" && echo "- streamed at rank 0: STL byte-identical" ||
      echo "- OUTPUTS DIFFER (streamed at rank 0)"
  else
    echo "- MPI: not built with -DTPMSFILL_MPI=ON or mpirun missing; skipped"
  fi
fi

if [[ "$section" == all || "$section" == vs-openvdb ]]; then
  echo
  echo "## 17. vs-openvdb: tpmsfill against issue 16's OpenVDB pipeline (gyroid network, T = 2 mm, 2 threads)"
  peer=../shared/peers/openvdb_tpms  # beside the checkout on the development machine only
  ref=build-openvdb_tpms/openvdb_tpms
  runs=${VS_RUNS:-5}
  skip=""
  if [[ ! -f "$peer/build.sh" ]]; then
    skip="no peer at $peer (the development machine's shared folder)"
  elif [[ "$section" == all ]] && ! dpkg -s libopenvdb-dev >/dev/null 2>&1; then
    skip="libopenvdb-dev is not installed (\`bash scripts/bench.sh vs-openvdb\` installs it when run as root)"
  elif ! bash "$peer/build.sh" build-openvdb_tpms >"$tmp/peer-build.log" 2>&1; then
    skip="the peer did not build: $(tail -n 1 "$tmp/peer-build.log")"
  fi
  if [[ -n "$skip" ]]; then
    echo "- vs-openvdb: skipped: $skip"
  else
    tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
    ./build/tests/bench_fill_inputs "$tmp/femur.off" "$tmp" >/dev/null  # femur35.stl, tube.stl
    vs="$tmp/vs"
    mkdir -p "$vs"
    echo "tpmsfill at $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src include CMakeLists.txt ||
      echo ' (sources modified)'); $runs alternating rounds a job; both tools read the same STL"
    # vs_job NAME IN VOXEL: rounds of tpmsfill, reference --eval lut, reference --eval direct, each
    # its whole process timed; tpmsfill's report and the reference's JSON line kept per run.
    vs_job() {
      local name=$1 in=$2 a=$3 i ev
      for ((i = 1; i <= runs; i++)); do
        timed ./build/tpmsfill fill "$in" "$vs/$name-t.stl" --quiet --cell 2 --voxel "$a" \
          --threads 2 --report "$vs/$name-t-$i.json"
        ((code == 0)) || { echo "- vs-openvdb: tpmsfill failed ($code) on $name"; exit "$code"; }
        echo "$wall $kb" >"$vs/$name-t-$i.time"
        for ev in lut direct; do
          timed "$ref" "$in" "$vs/$name-$ev.stl" --a "$a" --T 2 --size 0 --eval "$ev" --threads 2 \
            >"$vs/$name-$ev-$i.json"
          ((code == 0)) || { echo "- vs-openvdb: the reference failed ($code) on $name"; exit "$code"; }
          echo "$wall $kb" >"$vs/$name-$ev-$i.time"
        done
      done
      for ev in t lut direct; do  # the last run's outputs, checked by the same rules
        ./build/tpmsfill check --json --no-self-intersections "$vs/$name-$ev.stl" \
          >"$vs/$name-$ev-check.json" 2>/dev/null || true
        rm -f "$vs/$name-$ev.stl"
      done
    }
    vs_job femur-0.1 "$tmp/femur35.stl" 0.1
    vs_job femur-0.05 "$tmp/femur35.stl" 0.05
    vs_job tube "$tmp/tube.stl" 0.1
    # Thread scaling of tpmsfill's stages, 1 and 2 threads alternating.
    for ((i = 1; i <= runs; i++)); do
      for t in 1 2; do
        timed ./build/tpmsfill fill "$tmp/femur35.stl" "$vs/threads.stl" --quiet --cell 2 --voxel 0.05 \
          --threads "$t" --report "$vs/threads$t-$i.json"
        ((code == 0)) || { echo "- vs-openvdb: tpmsfill failed ($code) at $t threads"; exit "$code"; }
        echo "$wall $kb" >"$vs/threads$t-$i.time"
      done
    done
    python3 - "$vs" "$runs" <<'PY'
import json, statistics, sys
vs, runs = sys.argv[1], int(sys.argv[2])
med = statistics.median
jobs = [("femur-0.1", "femur 35 mm, voxel 0.1"), ("femur-0.05", "femur 35 mm, voxel 0.05"),
        ("tube", "tube 40 x 20 mm, 2 mm wall, 4.7e6 triangles, voxel 0.1")]
# Issue 39's targets, against `--eval lut`: the ratio at most this, peak memory at most the
# reference's.
target = {"femur-0.1": 0.6, "femur-0.05": 0.5, "tube": 0.25}
def times(stem):  # [(wall s, peak MB)] over the runs
    out = []
    for i in range(1, runs + 1):
        w, kb = open(f"{vs}/{stem}-{i}.time").read().split()
        out.append((float(w), float(kb) / 1024))
    return out
def reports(stem):
    return [json.load(open(f"{vs}/{stem}-{i}.json")) for i in range(1, runs + 1)]
def stage_medians(reps):  # tpmsfill: name -> (median s, median peak MB), in stage order
    names = []
    for r in reps:
        names += [s["name"] for s in r["stages"] if s["name"] not in names]
    return {n: (med([sum(s["seconds"] for s in r["stages"] if s["name"] == n) for r in reps]),
                med([max([s["peak_memory_mb"] for s in r["stages"] if s["name"] == n] or [0]) for r in reps]))
            for n in names}

print()
print("| job | tpmsfill s | MB | reference s | MB | ratio | target |")
print("|---|---:|---:|---:|---:|---:|---|")
for ev in ("lut", "direct"):
    for job, label in jobs:
        t, r = times(f"{job}-t"), times(f"{job}-{ev}")
        tw, rw = med([x[0] for x in t]), med([x[0] for x in r])
        ratio = tw / rw
        tm, rm = med([x[1] for x in t]), med([x[1] for x in r])
        goal = "-"
        if ev == "lut":
            met = ratio <= target[job] and tm <= rm
            goal = f"<= {target[job]}, memory <= reference: {'met' if met else 'not met'}"
        print(f"| {label} (reference `--eval {ev}`) | {tw:.2f} | {tm:.0f} | {rw:.2f} | "
              f"{rm:.0f} | {ratio:.2f} | {goal} |")
print()
print("Every run's wall time (s), in the order run:")
for job, _ in jobs:
    print(f"- {job}: " + "; ".join(f"{tool} " + " ".join(f"{x[0]:.2f}" for x in times(f"{job}-{k}"))
                                   for k, tool in (("t", "tpmsfill"), ("lut", "lut"), ("direct", "direct"))))

print()
print("Outputs (the last run of each; `tpmsfill check --no-self-intersections` on both):")
print()
print("| job | tool | samples | triangles | volume mm3 | area mm2 | components | check |")
print("|---|---|---:|---:|---:|---:|---:|---|")
num = lambda v, f: "-" if v is None else format(v, f)
for job, _ in jobs:
    for k, tool in (("t", "tpmsfill"), ("lut", "reference lut"), ("direct", "reference direct")):
        rep = json.load(open(f"{vs}/{job}-{k}-{runs}.json"))
        samples = rep["grid"]["samples"] if k == "t" else rep["samples"]
        tris = rep["output"]["triangles"] if k == "t" else rep["out_tris"]
        try:
            c = json.load(open(f"{vs}/{job}-{k}-check.json"))
            facts = (f"{num(c['volume'], '.2f')} | {num(c['area'], '.1f')} | {c['components']} | "
                     + ("valid" if c["valid"] else "; ".join(c["problems"])))
        except (OSError, ValueError, KeyError):
            facts = "- | - | - | check failed"
        print(f"| {job} | {tool} | {samples:,} | {tris:,} | {facts} |")

print()
print("tpmsfill per stage, medians (s, and the stage's peak MB from the report):")
print()
meds = {job: stage_medians(reports(f"{job}-t")) for job, _ in jobs}
names = []
for job, _ in jobs:
    names += [n for n in meds[job] if n not in names]
print("| stage | " + " | ".join(j for j, _ in jobs) + " |")
print("|---|" + "---:|" * len(jobs))
for n in names:
    print(f"| {n} | " + " | ".join(f"{meds[j][n][0]:.3f} ({meds[j][n][1]:.0f})" if n in meds[j] else "-"
                                   for j, _ in jobs) + " |")
print("| sum of stages | " + " | ".join(f"{med([r['total_seconds'] for r in reports(f'{j}-t')]):.3f}" for j, _ in jobs) + " |")
print("| process wall | " + " | ".join(f"{med([x[0] for x in times(f'{j}-t')]):.3f}" for j, _ in jobs) + " |")

print()
print("Reference per stage, medians of its own timers (s):")
print()
cols = [(job, ev) for job, _ in jobs for ev in ("lut", "direct")]
rstages = ["read", "sdf", "fill", "tpms", "boolean", "mesh", "write", "total"]
rmed = {c: {s: med([r["times_s"][s] for r in reports(f"{c[0]}-{c[1]}")]) for s in rstages} for c in cols}
print("| stage | " + " | ".join(f"{j} {e}" for j, e in cols) + " |")
print("|---|" + "---:|" * len(cols))
for s in rstages:
    print(f"| {s} | " + " | ".join(f"{rmed[c][s]:.3f}" for c in cols) + " |")
print("| process wall | " + " | ".join(f"{med([x[0] for x in times(f'{j}-{e}')]):.3f}" for j, e in cols) + " |")
print("| peak RSS MiB (its own) | " + " | ".join(f"{med([r['peak_rss_mib'] for r in reports(f'{j}-{e}')]):.0f}" for j, e in cols) + " |")

print()
print("tpmsfill on femur 35 mm, voxel 0.05, 1 and 2 threads (medians, alternating runs):")
print()
m1, m2 = stage_medians(reports("threads1")), stage_medians(reports("threads2"))
print("| stage | 1 thread s | 2 threads s | speed-up |")
print("|---|---:|---:|---:|")
def row(n, a, b):
    print(f"| {n} | {a:.3f} | {b:.3f} | {a / b if b > 0 else float('nan'):.2f} |")
for n in list(m1) + [n for n in m2 if n not in m1]:
    row(n, m1.get(n, (0,))[0], m2.get(n, (0,))[0])
row("sum of stages", med([r["total_seconds"] for r in reports("threads1")]),
    med([r["total_seconds"] for r in reports("threads2")]))
row("process wall", med([x[0] for x in times("threads1")]), med([x[0] for x in times("threads2")]))
print(f"| peak MB (process) | {med([x[1] for x in times('threads1')]):.0f} | {med([x[1] for x in times('threads2')]):.0f} | |")
print()
print(f"reference: OpenVDB {reports('femur-0.1-lut')[0]['openvdb']}, threads {reports('femur-0.1-lut')[0]['threads']}")
PY
  fi
fi

if [[ "$section" == all || "$section" == material ]]; then
  echo
  echo "## 20. seed 001: tets, material and the cube map (tpmsfill material info)"
  echo
  echo "libcgal-demo's bear, bunny00, dino, elephant, fandisk and sphere (those tpmsfill check passes),"
  echo "tets of size diagonal / D, material = geodesic distance to the bottom (boundary points within"
  echo "diagonal / 100 of the lowest):"
  echo
  echo "Tets and points after the chords are split (the points that added in their column);"
  echo "inverted: by the harmonic interior, then after untangling."
  echo
  echo "| mesh | D | tets | points | split points | volume vs surface | genus | flipped boundary faces | inverted tets, harmonic → untangled | flat tets | untangled points | wall s | peak MB | outcome |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
  mkdir -p "$tmp/mat"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp/mat" --strip-components=2 \
    data/meshes/bunny00.off data/meshes/dino.off data/meshes/bear.off data/meshes/fandisk.off \
    data/meshes/ellipe0.003.off data/meshes/elephant.off data/meshes/sphere.off 2>/dev/null || true
  for f in "$tmp"/mat/*.off; do
    ./build/tpmsfill check --json "$f" >"$tmp/c.json" 2>/dev/null || continue
    diag=$(python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["bbox"]; print(sum((b["max"][i]-b["min"][i])**2 for i in range(3))**0.5)' "$tmp/c.json")
    for D in 30 60; do
      cell=$(python3 -c "print($diag / $D)"); depth=$(python3 -c "print($diag / 100)")
      timed timeout 900 ./build/tpmsfill material info "$f" --cell "$cell" \
        --material geodesic "$depth" --json >"$tmp/m.json" 2>"$tmp/err.txt"
      python3 - "$tmp/m.json" "$(basename "$f")" "$D" "$wall" "$kb" "$code" "$tmp/err.txt" <<'PY'
import json, sys
name, D, wall, kb, code = sys.argv[2], sys.argv[3], float(sys.argv[4]), int(sys.argv[5]), sys.argv[6]
try:
    d = json.load(open(sys.argv[1]))
except Exception:
    d = {}
err = open(sys.argv[7]).read().strip().splitlines()
why = [l for l in err if "warning" not in l]
outcome = "mapped" if code == "0" else ("refused: " + (why[-1] if why else "exit " + code))[:150].replace("|", "/")
cm = d.get("cube_map", {})
vol = (100 * (d["volume_mm3"] / d["surface_volume_mm3"] - 1)) if "volume_mm3" in d else float("nan")
inverted = f"{cm['harmonic_inverted_tets']} → {cm['inverted_tets']}" if cm else ""
print(f"| {name} | {D} | {d.get('tets', '')} | {d.get('points', '')} | {d.get('split_points', '')} | {vol:+.2f} % | {d.get('genus', '')} | "
      f"{cm.get('flipped_boundary_faces', '')} | {inverted} | {cm.get('flat_tets', '')} | {cm.get('untangled_points', '')} | "
      f"{wall:.2f} | {kb / 1024:.0f} | {outcome} |")
PY
    done
  done
fi

if [[ "$section" == all || "$section" == material || "$section" == material-fit ]]; then
  echo
  echo "## 21. seed 001: the spline fit, THB against the uniform baseline (tpmsfill material fit)"
  echo
  echo "Tets of size diagonal / 30 and the geodesic material of §20. THB: the octree of ≤ 5 tets per"
  echo "cell, then 2 rounds of progressive refinement; uniform: n³ control points with n³ about 4 and"
  echo "8 times THB's final count. RS over the tets' samples (docs/method.md step 8); errors at the"
  echo "tets' points; folded: Gauss points with det J_G ≤ 0. Steps: --method ${FIT_METHOD:-euler}"
  echo "(FIT_METHOD=newton for the converged fit)."
  echo
  echo "| mesh | tets | basis | control points | ratio | G steps | RS G % | M steps | RS M % | G rms / max mm | M rms | folded | wall s | peak MB |"
  echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|"
  extract_material_meshes
  for name in ${FIT_MESHES:-bunny00 bear fandisk sphere}; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    thb_nc=0
    for basis in thb u4 u8; do
      extra=()
      if [[ "$basis" != thb ]]; then
        factor=${basis#u}
        extra=(--uniform "$(python3 -c "print(max(4, round(($factor * $thb_nc) ** (1 / 3))))")")
      fi
      timed timeout 1800 ./build/tpmsfill material fit "$f" "$tmp/m.tsm" --cell "$cell" \
        --material geodesic "$depth" --json --method "${FIT_METHOD:-euler}" "${extra[@]}" \
        >"$tmp/fit.json" 2>"$tmp/err.txt"
      line=$(python3 - "$tmp/fit.json" "$name" "$basis" "$wall" "$kb" "$code" "$thb_nc" <<'PY'
import json, sys
name, basis, wall, kb, code, thb_nc = sys.argv[2], sys.argv[3], float(sys.argv[4]), int(sys.argv[5]), sys.argv[6], int(sys.argv[7])
text = open(sys.argv[1]).read()
try:
    d = json.loads(text[text.index("{"):text.rindex("}") + 1])
    r = d["rounds"][-1]
except Exception:
    print(f"| {name} | | {basis} | | | | | | | | | | {wall:.1f} | {kb / 1024:.0f} |  (exit {code})\t0")
    sys.exit(0)
nc = r["control_points"]
label = "THB, " + str(len(d["rounds"])) + " rounds" if basis == "thb" else f"uniform {round(nc ** (1 / 3))}³"
ratio = f"{thb_nc / nc:.3f}" if basis != "thb" else "1"
print(f"| {name} | {d['tets']} | {label} | {nc} | {ratio} | {r['geometry_iterations']} | "
      f"{r['geometry_rs_percent']:.1f} | {r.get('material_iterations', '')} | {r.get('material_rs_percent', 0):.1f} | "
      f"{r['geometry_rms_mm']:.4g} / {r['geometry_max_mm']:.4g} | {r.get('material_rms', 0):.4g} | "
      f"{r['folded_samples']} of {r['samples']} | {wall:.1f} | {kb / 1024:.0f} |\t{nc}")
PY
)
      echo "${line%%$'\t'*}"
      [[ "$basis" == thb ]] && thb_nc=${line##*$'\t'}
    done
  done
fi

if [[ "$section" == all || "$section" == material || "$section" == material-unfold ]]; then
  echo
  echo "## 21c. seed 001: G kept fold-free (tpmsfill material fit, the default, against --allow-folds)"
  echo
  echo "Tets and material as §21, THB, the default three rounds, Euler steps; with --allow-folds and"
  echo "by default. folded: the last round's Gauss points with det J_G ≤ 0 (3³ an element), and in"
  echo "brackets points of the finer sample (5³ inside an element, 4³ reaching its faces); opened:"
  echo "watched points folded at the rounds' starts, over all rounds; untangled: control points the"
  echo "foldover-free energy moved"
  echo "where pushing them open failed; found: folds between the watched points that det J_G's"
  echo "Bernstein bound found on the last G and that were pushed open; proven: the written model's"
  echo "elements where the bound proves det J_G > 0 (folded / undecided in brackets)."
  echo
  echo "| mesh | control points | folded | proven | RS G / M % | G rms mm | wall s | peak MB | control points | folded | opened | untangled | found | proven | RS G / M % | G rms mm | wall s | peak MB |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  extract_material_meshes
  for name in ${FIT_MESHES:-bunny00 bear fandisk sphere}; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    row="| $name"
    for flag in --allow-folds ""; do
      timed timeout 3600 ./build/tpmsfill material fit "$f" "$tmp/m.tsm" --cell "$cell" \
        --material geodesic "$depth" --json $flag >"$tmp/fit.json" 2>"$tmp/err.txt"
      row+=$(python3 - "$tmp/fit.json" "$wall" "$kb" "$code" "$flag" <<'PY'
import json, sys
wall, kb, code, flag = float(sys.argv[2]), int(sys.argv[3]), sys.argv[4], sys.argv[5] if len(sys.argv) > 5 else ""
text = open(sys.argv[1]).read()
try:
    d = json.loads(text[text.index("{"):text.rindex("}") + 1])
    r = d["rounds"][-1]
except Exception:
    print(f" | | (exit {code}) | | | | | {wall:.1f} | {kb / 1024:.0f}", end="")
    sys.exit(0)
fine = f" ({r.get('fine_folded_samples', 0)} of {r.get('fine_samples', 0)})"
opened = "" if flag else (f" | {sum(x.get('fitted_folded_samples', 0) for x in d['rounds'])}"
                          f" | {sum(x.get('untangled_control_points', 0) for x in d['rounds'])}"
                          f" | {r.get('found_folded_points', 0)}")
c = d.get("fold_certificate", {})
proven = f" | {c.get('proven')} of {c.get('elements')} ({c.get('folded')} / {c.get('undecided')})"
print(f" | {r['control_points']} | {r['folded_samples']} of {r['samples']}{fine}{opened}{proven} | "
      f"{r['geometry_rs_percent']:.2f} / {r.get('material_rs_percent', 0):.2f} | "
      f"{r['geometry_rms_mm']:.4g} | {wall:.1f} | {kb / 1024:.0f}", end="")
PY
)
    done
    echo "$row |"
  done
fi

if [[ "$section" == all || "$section" == material || "$section" == material-slice ]]; then
  echo
  echo "## 22. seed 001: direct slicing (bench_solid_slice, tpmsfill material slice)"
  extract_material_meshes
  for name in bunny00 bear fandisk sphere; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    ./build/tpmsfill material info "$f" --cell "$cell" --material geodesic "$depth" \
      --tets "$tmp/tets.vtk" >/dev/null 2>&1
    ./build/tpmsfill material fit "$f" "$tmp/$name.tsm" --cell "$cell" --material geodesic "$depth" \
      --quiet 2>/dev/null
    taus=$(python3 -c "print(' '.join('%.3g' % (($diag / d) ** 3) for d in (25, 50, 100)))")
    echo
    echo "### $name (diagonal $diag; tau = (diagonal / 25, 50, 100)³, the seed's 10 : 1 : 0.1 mm³)"
    echo
    ./build/tests/bench_solid_slice "$tmp/$name.tsm" "$f" "$tmp/tets.vtk" $taus 0
    layer=$(python3 -c "print('%.3g' % ($zspan / 100))")
    timed ./build/tpmsfill material slice "$tmp/$name.tsm" "$tmp/$name.cli" --layer "$layer" --json \
      >"$tmp/s.json" 2>/dev/null
    python3 - "$tmp/s.json" "$name" "$wall" "$kb" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"\n`material slice` of {sys.argv[2]}: {d['layers']} layers of {d['layer_mm']} mm at the default tau "
      f"({d['tau_mm3']:.3g}): {d['triangles']} triangles, {d['flipped']} turned over, "
      f"{float(sys.argv[3]):.1f} s, {int(sys.argv[4]) / 1024:.0f} MB peak")
PY
  done
fi

if [[ "$section" == all || "$section" == material || "$section" == material-tables ]]; then
  echo
  echo "## 21b. seed 001's Tables 1-2 side by side (tpmsfill material fit)"
  echo
  extract_material_meshes
  extract_seed_models
  echo "Tets of size diagonal / 30; material: the femur's geodesic distance from its cut (diagonal / 100"
  echo "deep), the duck's distance to its box's centre (the seed's rules). Both bases take Euler steps"
  echo "until RS moves by less than 0.01 points a step (at most 100 a field and round), the seed's"
  echo "uniform n³ (its Table 2: 40³, 41³, 38³), and THB the seed's progressive refinement with each"
  echo "model's marking (the share of the squared residual whose leaves split, and the rounds; the"
  echo "lower femur's octree counts 20 tets a cell, its tets meshed finer where its map folded). Seed"
  echo "columns from Li & Fu 2021 Tables 1-2 (nc its control points, ni its iterations, its RS over"
  echo "the tets' points). Our ni: steps over all rounds; RS and errors: the last round's; bound: det"
  echo "J_G's Bernstein bound on the written G, elements folded / undecided (a folded one is refused)."
  echo
  echo "| model | basis | marking | steps | nc | nc / uniform | G ni | RS G % | M ni | RS M % | G rms / max | M rms | bound | seed nc | seed ni G / M | seed RS G / M % | wall s | peak MB |"
  echo "|---|---|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|"
  stop=(--rs-change 0.01 --max-iterations 100)
  # TABLE_MODELS="duck" runs some of them (the lower femur takes about an hour).
  for name in ${TABLE_MODELS:-lower-femur duck upper-femur}; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    seed_material "$name"
    methods=(euler newton)
    case $name in
      duck) seed_thb="27455 | 23 / 16 | 80.47 / 88.66"; seed_uniform="54872 | 31 / 19 | 83.84 / 90.27"
        n=38; marking=(--refine-share 0.5 --refinements 2) ;;
      upper-femur) seed_thb="21659 | 23 / 27 | 85.33 / 88.03"; seed_uniform="64000 | 28 / 27 | 84.62 / 85.92"
        n=40; marking=(--refine-share 0.65 --refinements 3) ;;
      # 25 min a fit (meshing finer where its map folds and mapping take 16): Euler steps only.
      lower-femur) seed_thb="17409 | 20 / 25 | 86.76 / 90.13"; seed_uniform="68921 | 25 / 27 | 84.57 / 82.66"
        n=41; marking=(--max-tets-per-cell 20 --refine-share 0.65 --refinements 2); methods=(euler) ;;
    esac
    for basis in thb uniform; do
      for method in "${methods[@]}"; do
        extra=("${marking[@]}")
        [[ $basis == uniform ]] && extra=(--uniform "$n")
        timed timeout 3600 ./build/tpmsfill material fit "$f" "$tmp/m.tsm" --cell "$cell" "${material[@]}" \
          --json --method "$method" "${stop[@]}" "${extra[@]}" >"$tmp/fit.json" 2>"$tmp/err.txt"
        [[ $name == lower-femur && $basis == thb ]] && cp "$tmp/fit.json" "$tmp/lower.json"
        seed=$seed_thb; [[ $basis == uniform ]] && seed=$seed_uniform
        python3 - "$tmp/fit.json" "$tmp/err.txt" "$name" "$basis" "$method" "$wall" "$code" "$seed" \
          "$n" "$kb" "${extra[*]}" <<'PY'
import json, sys
name, basis, method, wall, code, seed, n, kb, marking = sys.argv[3:12]
# "--max-tets-per-cell 20 --refine-share 0.65" as "tets a cell 20, share 0.65"
words = {"--max-tets-per-cell": "tets a cell", "--refine-share": "share", "--refinements": "refinements"}
flags = marking.split()
marking = "" if basis == "uniform" else ", ".join(
    f"{words[flags[i]]} {flags[i + 1]}" for i in range(0, len(flags), 2))
text = open(sys.argv[1]).read()
try:
    d = json.loads(text[text.index("{"):text.rindex("}") + 1]); r = d["rounds"][-1]
except Exception:
    said = open(sys.argv[2]).read().replace("\r", "\n").splitlines()
    why = next((l.strip() for l in reversed(said) if l.startswith("tpmsfill:") and "nothing written" in l),
               next((l.strip() for l in reversed(said) if l.startswith("tpmsfill:")), ""))[:200]
    label = "THB" if basis == "thb" else f"uniform {n}³"
    print(f"| {name} | {label} | {marking} | {method} | | | | | | | | | {why} | {seed} | "
          f"{float(wall):.1f} (exit {code}) | {int(kb) // 1024} |"); sys.exit(0)
nc = r["control_points"]
label = f"THB, {len(d['rounds'])} rounds" if basis == "thb" else f"uniform {round(nc ** (1 / 3))}³"
steps_g = sum(x["geometry_iterations"] for x in d["rounds"])
steps_m = sum(x.get("material_iterations", 0) for x in d["rounds"])
b = d["fold_certificate"]
print(f"| {name} | {label} | {marking} | {method} | {nc} | {nc / int(n) ** 3:.2f} | {steps_g} | "
      f"{r['geometry_rs_percent']:.1f} | {steps_m} | {r.get('material_rs_percent', 0):.1f} | "
      f"{r['geometry_rms_mm']:.4g} / {r['geometry_max_mm']:.4g} | {r.get('material_rms', 0):.4g} | "
      f"{b['folded']} / {b['undecided']}{' refused' if 'refused' in d else ''} | {seed} | "
      f"{float(wall):.1f}{f' (exit {code})' if code != '0' else ''} | {int(kb) // 1024} |")
PY
      done
    done
  done
  # The lower femur's cube map, from its THB fit's report.
  if [[ -s "$tmp/lower.json" ]]; then
    echo
    python3 - "$tmp/lower.json" <<'PY'
import json, sys
text = open(sys.argv[1]).read()
d = json.loads(text[text.index("{"):text.rindex("}") + 1]); m = d["cube_map"]
print(f"lower-femur's cube map (geodesic from the cut, --up 0 0 -1): {d['surface_triangles']} "
      f"triangles, genus {d['genus']}, {d['tets']} tets; {m['flipped_boundary_faces']} "
      f"flipped boundary faces, {m['relaxed_patches']} crowded patches relaxed, "
      f"{m['harmonic_inverted_tets']} harmonic inverted tets, folded by pass "
      f"{', '.join(map(str, m.get('folded_by_pass', [])))} (pass {m.get('kept_pass', 0)} kept), "
      f"{m.get('opened_points', 0)} points untangled locally after, "
      f"{m['inverted_tets']} inverted and {m['flat_tets']} flat left")
PY
  fi
fi

if [[ "$section" == all || "$section" == material || "$section" == material-tspline ]]; then
  echo
  echo "## 21d. seed 001's T-splines on the octrees it fits (tpmsfill material info --tspline)"
  echo
  extract_material_meshes
  extract_seed_models
  echo "Tets of size diagonal / 30, the seed's octree (≤ 5 tets a cell, 2:1 balanced, levels 2-8);"
  echo "on it THB (the fit's basis) and the seed's T-splines (anchors at every vertex, knots by rays)."
  echo "Σ φ sampled at 27 points an element; the bound is the largest |coefficient| of Σ φ − 1."
  echo
  echo "| model | tets | cells (deepest) | THB functions | T-spline functions | T-spline elements | Σ φ from / to | bound | incompatible pairs | cells affected | wall s | peak MB |"
  echo "|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|"
  for name in bunny00 bear fandisk sphere upper-femur duck; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    timed ./build/tpmsfill material info "$f" --cell "$cell" --material geodesic "$depth" --tspline \
      --json >"$tmp/i.json" 2>/dev/null
    python3 - "$tmp/i.json" "$name" "$wall" "$kb" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); o = d["octree"]; t = d["tspline"]
print(f"| {sys.argv[2]} | {d['tets']} | {o['leaves']} ({o['deepest_level']}) | {d['thb']['functions']} | "
      f"{t['functions']} | {t['elements']} | {t['sum_range'][0]:.3f} / {t['sum_range'][1]:.3f} | "
      f"{t['unity_error']:.3g} | {t['incompatible_pairs']} | {t['cells_affected']} | "
      f"{float(sys.argv[3]):.1f} | {int(sys.argv[4]) / 1024:.0f} |")
PY
  done
fi

if [[ "$section" == all || "$section" == material || "$section" == material-audit ]]; then
  echo
  echo "## 22b. issue 40's acceptance, model by model (material fit, slice, iso; the defaults)"
  echo
  extract_material_meshes
  extract_seed_models
  echo "Each model fitted by default (THB, fold-free, 3 rounds; tets of the diagonal / 30), sliced"
  echo "into about 100 layers (height / 100) at the default tau, and cut at the material's 25, 50"
  echo "and 75 % (iso). Stack volume: the layers' areas times their height, against the surface's."
  echo "Iso pieces: the spline surfaces' pieces at the three values, then (in brackets) those of"
  echo "the tets' own surfaces (linear in each tet), each \"pieces / under 1 % of the largest's area\":"
  echo "a small piece the tets have too is a cap of the data, one they lack a tear."
  echo
  echo "| model | nc | RS G / M % | folded Gauss / finer points | bound: proven / folded / undecided | surface mm³ | stack mm³ | difference | turned over | iso pieces / small (tets') | non-manifold edges | fit s | slice s |"
  echo "|---|---:|---|---|---|---:|---:|---:|---:|---|---:|---:|---:|"
  for name in bunny00 bear fandisk sphere upper-femur duck lower-femur; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    seed_material "$name"
    volume=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["volume"])' "$tmp/c.json")
    ./build/tpmsfill material info "$f" --cell "$cell" "${material[@]}" --tets "$tmp/a.vtk" \
      >/dev/null 2>&1
    # shellcheck disable=SC2086  # FIT_ARGS: more options for the fits, as words
    timed ./build/tpmsfill material fit "$f" "$tmp/a.tsm" --cell "$cell" "${material[@]}" --json \
      ${FIT_ARGS:-} >"$tmp/fit.json" 2>/dev/null
    fit_wall=$wall
    values=$(python3 -c 'import json,sys; t=open(sys.argv[1]).read(); d=json.loads(t[t.index("{"):t.rindex("}")+1]); lo,hi=d["material_range"]; print(*[lo+q*(hi-lo) for q in (0.25,0.5,0.75)])' "$tmp/fit.json")
    layer=$(python3 -c "print('%.3g' % ($zspan / 100))")
    timed ./build/tpmsfill material slice "$tmp/a.tsm" "$tmp/a.cli" --layer "$layer" --json >"$tmp/s.json" 2>/dev/null
    slice_wall=$wall
    # shellcheck disable=SC2086  # the values are words
    ./build/tpmsfill material iso "$tmp/a.tsm" "$tmp/iso.ply" --values $values --json >"$tmp/iso.json" 2>/dev/null
    python3 - "$tmp/fit.json" "$tmp/s.json" "$tmp/iso.json" "$name" "$volume" "$fit_wall" "$slice_wall" \
      "$tmp/a.vtk" <<'PY'
import json, math, sys
def load(p):
    t = open(p).read(); return json.loads(t[t.index("{"):t.rindex("}") + 1])
fit, sl, iso = load(sys.argv[1]), load(sys.argv[2]), load(sys.argv[3])
name, volume, fw, sw = sys.argv[4], float(sys.argv[5]), float(sys.argv[6]), float(sys.argv[7])
r = fit["rounds"][-1]; c = fit.get("fold_certificate", {})
surfaces = iso["surfaces"]
# The tets' own iso-surfaces (linear in each tet): pieces joined through the edges they cross.
tok = open(sys.argv[8]).read().split(); i = 0; pts, tets, mat = [], [], []
while i < len(tok):
    if tok[i] == "POINTS":
        n = int(tok[i + 1]); i += 3; pts = [tuple(map(float, tok[i + 3 * k:i + 3 * k + 3])) for k in range(n)]; i += 3 * n
    elif tok[i] == "CELLS":
        n = int(tok[i + 1]); i += 3
        for _ in range(n):
            m = int(tok[i]); tets.append(tuple(map(int, tok[i + 1:i + 1 + m]))); i += 1 + m
    elif tok[i] == "SCALARS":
        i += 6; mat = [float(x) for x in tok[i:i + len(pts)]]; i += len(pts)
    else:
        i += 1
def tet_pieces(v):
    parent = {}
    def find(x):
        while parent.setdefault(x, x) != x:
            parent[x] = parent[parent[x]]; x = parent[x]
        return x
    def at(e):
        a, b = e; t = (v - mat[a]) / (mat[b] - mat[a])
        return [pts[a][k] + t * (pts[b][k] - pts[a][k]) for k in range(3)]
    def tri(p, q, s):
        u = [q[k] - p[k] for k in range(3)]; w = [s[k] - p[k] for k in range(3)]
        return math.sqrt((u[1] * w[2] - u[2] * w[1]) ** 2 + (u[2] * w[0] - u[0] * w[2]) ** 2 + (u[0] * w[1] - u[1] * w[0]) ** 2) / 2
    polys = []
    for t in tets:
        below = [p for p in t if mat[p] < v]; above = [p for p in t if mat[p] >= v]
        edges = [(min(a, b), max(a, b)) for a in below for b in above]
        if not edges: continue
        for e in edges[1:]: parent[find(e)] = find(edges[0])
        polys.append(edges)
    area = {}
    for edges in polys:
        p = [at(e) for e in edges]  # a quad's corners go (b0a0, b0a1, b1a0, b1a1): 0-1-3-2
        a = tri(*p) if len(p) == 3 else tri(p[0], p[1], p[3]) + tri(p[0], p[3], p[2])
        area[find(edges[0])] = area.get(find(edges[0]), 0) + a
    if not area: return "0 / 0"
    big = max(area.values())
    return f"{len(area)} / {sum(a < 0.01 * big for a in area.values())}"
print(f"| {name} | {r['control_points']} | {r['geometry_rs_percent']:.1f} / {r.get('material_rs_percent', 0):.1f} | "
      f"{r['folded_samples']} / {r.get('fine_folded_samples', 0)} | "
      f"{c.get('proven', '')} / {c.get('folded', '')} / {c.get('undecided', '')} | "
      f"{volume:.5g} | {sl['volume_mm3']:.5g} | {100 * (sl['volume_mm3'] / volume - 1):+.2f} % | {sl['flipped']} | "
      f"{', '.join(str(s['pieces']) + ' / ' + str(s['small_pieces']) + ' (' + tet_pieces(s['material']) + ')' for s in surfaces)} | "
      f"{sum(s['non_manifold_edges'] for s in surfaces)} | {fw:.1f} | {sw:.1f} |")
PY
  done
fi

if [[ "$section" == all || "$section" == material || "$section" == material-grade ]]; then
  echo
  echo "## 23. seed 001: a lattice graded by the fitted material (bench_material_volume, fill --grade-by)"
  extract_material_meshes
  for name in bunny00 bear fandisk; do
    f="$tmp/mat/$name.off"
    material_sizes "$f" || continue
    ./build/tpmsfill material fit "$f" "$tmp/$name.tsm" --cell "$cell" --material geodesic "$depth" \
      --quiet 2>/dev/null
    echo
    echo "### $name (diagonal $diag; material: geodesic distance to the bottom)"
    echo
    ./build/tests/bench_material_volume "$tmp/$name.tsm" 32 64 128
    lattice_cell=$(python3 -c "print('%.3g' % ($diag / 8))")
    voxel=$(python3 -c "print('%.3g' % ($diag / 120))")
    for run in plain graded cells; do
      case $run in
        plain) args=(--porosity 0.65) ;;
        graded) args=(--grade porosity 0.5 0.8 --grade-by "$tmp/$name.tsm") ;;
        cells) args=(--porosity 0.65 --grade cell "$lattice_cell" "$(python3 -c "print('%.3g' % (2 * $lattice_cell))")" --grade-by "$tmp/$name.tsm") ;;
      esac
      timed ./build/tpmsfill fill "$f" "$tmp/$run.stl" --cell "$lattice_cell" --voxel "$voxel" \
        "${args[@]}" --quiet --report "$tmp/$run.json" 2>/dev/null
      python3 - "$tmp/$run.json" "$run" "$wall" "$kb" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
g = d["recipe"]["grading"]
what = (f"{g[0]['what']} {g[0]['start']:.4g} to {g[0]['end']:.4g} by the material ({g[0]['from']:.4g} to {g[0]['to']:.4g})"
        if g else "porosity 0.65")
print(f"\n`fill` {sys.argv[2]} ({what}): porosity {100 * d['porosity']:.1f} %, "
      f"{d['output']['triangles']} triangles, valid {d['valid']}, "
      f"{float(sys.argv[3]):.1f} s, {int(sys.argv[4]) / 1024:.0f} MB peak")
PY
    done
  done
fi

if [[ "$section" == all || "$section" == decimate-cgal ]]; then
  echo
  echo "## 19. decimate every valid libcgal-demo mesh (TOL = bounding-box diagonal / 500)"
  mkdir -p "$tmp/cgal"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp/cgal" --strip-components=2 data/meshes
  echo
  echo "| mesh | triangles before → after | reduction | TOL mm | measured max mm (to / from input) | volume change | rounds | wall s | peak MB | check of output |"
  echo "|---|---|---:|---:|---|---:|---:|---:|---:|---|"
  valid=0 skipped=0
  for f in "$tmp"/cgal/*.{off,stl,obj,ply}; do
    [[ -f "$f" ]] || continue
    if ! ./build/tpmsfill check --json "$f" >"$tmp/c.json" 2>/dev/null; then
      skipped=$((skipped + 1)); continue
    fi
    valid=$((valid + 1))
    tol=$(python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["bbox"]; print(sum((b["max"][i]-b["min"][i])**2 for i in range(3))**0.5/500)' "$tmp/c.json")
    out="$tmp/dec.${f##*.}"; [[ "$out" == *.off ]] && out="$tmp/dec.ply"
    timed timeout 900 ./build/tpmsfill decimate "$f" "$out" --tolerance "$tol" --quiet \
      --report "$tmp/dec.json" 2>"$tmp/err.txt"
    if [[ $code != 0 ]]; then
      echo "| $(basename "$f") | exit $code: $(head -c 120 "$tmp/err.txt" | tr '\n|' '  ') | | | | | | | | |"; continue
    fi
    ./build/tpmsfill check "$out" >/dev/null 2>&1 && verdict="valid" || verdict="NOT VALID"
    python3 - "$tmp/dec.json" "$(basename "$f")" "$wall" "$kb" "$verdict" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print(f"| {sys.argv[2]} | {d['triangles_before']:,} → {d['triangles_after']:,} | "
      f"**{d['reduction']:.2f}×** | {d['tolerance']:.4g} | {d['to_input']['max']:.4g} / "
      f"{d['from_input']['max']:.4g} | {100 * d['volume_change']:+.3f} % | {d['rounds']} | "
      f"{float(sys.argv[3]):.1f} | {int(sys.argv[4]) / 1024:.0f} | {sys.argv[5]} |")
PY
  done
  echo
  echo "$valid valid meshes decimated; $skipped files not valid (or unreadable) were left out"
fi

if [[ "$section" == all || "$section" == decimate || "$section" == decimate-meshes ]]; then
  echo
  echo "## 19. decimation that keeps the proof (fill --decimate TOL, TOL = voxel/4)"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" --strip-components=2 data/meshes/femur.off
  [[ -f "$tmp/femur35.stl" ]] || ./build/tests/bench_fill_inputs "$tmp/femur.off" "$tmp" >/dev/null
  # decimate_row NAME OUT.stl REPORT.json: one table row from a fill --decimate report.
  decimate_row() {
    local verdict
    ./build/tpmsfill check "$2" >/dev/null 2>&1 && verdict="valid" || verdict="NOT VALID"
    python3 - "$3" "$1" "$code" "$wall" "$kb" "$verdict" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); d = r["decimation"]
t = {s["name"]: s["seconds"] for s in r["stages"]}
print(f"| {sys.argv[2]} | {sys.argv[3]} | {d['triangles_before']:,} → {d['triangles_after']:,} | "
      f"**{d['reduction']:.2f}×** | {d['tolerance']:.4g} | {d['to_input']['max']:.4g} / "
      f"{d['from_input']['max']:.4g} | {100 * d['volume_change']:+.3f} % | {d['rounds']} | "
      f"{t.get('decimate', 0):.1f} | {float(sys.argv[4]):.1f} | {int(sys.argv[5]) / 1024:.0f} | "
      f"{sys.argv[6]} |")
PY
  }
  header='| case | exit | triangles before → after | reduction | TOL mm | measured max mm (to / from input) | volume change | rounds | decimate s | wall s | peak MB | check of output |'
  rule='|---|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---|'
  if [[ "$section" != decimate-meshes ]]; then
  echo
  echo "femur 35 mm, gyroid network T = 2 mm, a = 0.05 mm, TOL = 0.0125 mm:"
  echo "\`tpmsfill fill femur35.stl out.stl --cell 2 --voxel 0.05 --decimate 0.0125 --report r.json\`"
  echo
  echo "$header"; echo "$rule"
  timed ./build/tpmsfill fill "$tmp/femur35.stl" "$tmp/dec.stl" --quiet --cell 2 --voxel 0.05 \
    --decimate 0.0125 --report "$tmp/dec.json" 2>"$tmp/err.txt"
  if [[ $code == 0 ]]; then decimate_row "femur 35 mm, a = 0.05" "$tmp/dec.stl" "$tmp/dec.json"
  else echo "| femur | $code | $(head -c 120 "$tmp/err.txt") |"; fi
  sed 's/^/    /' "$tmp/err.txt"
  fi
  if [[ -d ../shared/meshes ]]; then
    echo
    echo "every mesh of ../shared/meshes: cell = longest side / 15, voxel a = cell / 10, TOL = a / 4:"
    echo
    echo "$header"; echo "$rule"
    for f in ../shared/meshes/*.{off,stl,STL,obj,ply}; do
      [[ -f "$f" ]] || continue
      ./build/tpmsfill check --no-self-intersections --json "$f" >"$tmp/c.json" 2>/dev/null || true
      read -r cell voxel tol < <(python3 -c 'import json,sys; j=json.load(open(sys.argv[1])); b=j["bbox"]; L=max(b["max"][i]-b["min"][i] for i in range(3)); print(L/15, L/150, L/600)' "$tmp/c.json" 2>/dev/null || echo "0 0 0")
      [[ "$cell" != 0 ]] || continue
      timed timeout 900 ./build/tpmsfill fill "$f" "$tmp/dec.stl" --quiet --cell "$cell" \
        --voxel "$voxel" --decimate "$tol" --report "$tmp/dec.json" 2>"$tmp/err.txt"
      if [[ $code == 0 ]]; then decimate_row "$(basename "$f")" "$tmp/dec.stl" "$tmp/dec.json"
      else echo "| $(basename "$f") | $code | $(head -c 120 "$tmp/err.txt" | tr '\n|' '  ') |"; fi
      grep -h "warning" "$tmp/err.txt" | sed 's/^/    /' || true
    done
  fi
fi

if [[ "$section" == all || "$section" == placement ]]; then
  echo
  echo "## 26. every mesh where a printer puts it (bench_placement)"
  if [[ -d ../shared/meshes ]]; then
    echo; echo "../shared/meshes, every readable mesh:"; echo
    ./build/tests/bench_placement ../shared/meshes/*.{off,stl,STL,obj,ply}
  fi
  mkdir -p "$tmp/cgal"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp/cgal" --strip-components=2 \
    --wildcards 'data/meshes/*.off' 2>/dev/null || true
  echo; echo "libcgal-demo's data/meshes, those check calls valid:"; echo
  ./build/tests/bench_placement --valid-only "$tmp"/cgal/*.off
  echo; echo "assimp-testmodels, those check calls valid:"; echo
  mapfile -t assimp < <(find /usr/share/assimp/models -type f \( -iname '*.stl' -o -iname '*.obj' \
    -o -iname '*.ply' -o -iname '*.off' \) | sort)
  ./build/tests/bench_placement --valid-only "${assimp[@]}"
  echo
  echo "preflight forecast against the run (section 4's inputs; --progress json gives the forecast):"
  echo
  echo "| case | samples | triangles forecast | triangles out | ratio | seconds forecast | wall s |"
  echo "|---|---:|---:|---:|---:|---|---:|"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp" data/meshes/femur.off
  ./build/tests/bench_fill_inputs "$tmp/data/meshes/femur.off" "$tmp" >/dev/null
  for c in femur35 tube; do
    timed ./build/tpmsfill fill "$tmp/$c.stl" "$tmp/out.stl" --cell 2 --voxel 0.1 --progress json \
      --report "$tmp/r.json" 2>"$tmp/err.txt" >/dev/null
    python3 - "$c" "$tmp/err.txt" "$tmp/r.json" "$wall" <<'PY'
import json, sys
name, err, report, wall = sys.argv[1:5]
f = next(json.loads(l)["preflight"] for l in open(err) if l.startswith('{"preflight"'))
r = json.load(open(report))
out = r["output"]["triangles"]
print(f"| {name} | {f['samples']:,} | {f['triangles']:,.0f} | {out:,} | {f['triangles'] / out:.2f} | "
      f"{f['seconds'][0]:.2g} to {f['seconds'][1]:.2g} | {wall} |")
PY
  done
  echo
  echo "slice's preflight against the run (the same inputs, --layer 0.1, ASCII CLI):"
  echo
  echo "| case | layers | points forecast | points out | ratio | MB forecast | MB out | seconds forecast | wall s |"
  echo "|---|---:|---:|---:|---:|---:|---:|---|---:|"
  for c in femur35 tube; do
    timed ./build/tpmsfill slice "$tmp/$c.stl" "$tmp/out.cli" --layer 0.1 --cell 2 --voxel 0.1 \
      --progress json --report "$tmp/r.json" 2>"$tmp/err.txt" >/dev/null
    python3 - "$c" "$tmp/err.txt" "$tmp/r.json" "$wall" "$(stat -c %s "$tmp/out.cli")" <<'PY'
import json, sys
name, err, report, wall, size = sys.argv[1:6]
f = next(json.loads(l)["preflight"] for l in open(err) if l.startswith('{"preflight"'))
r = json.load(open(report))["slice"]
print(f"| {name} | {f['layers']} | {f['points']:,.0f} | {r['points']:,} | {f['points'] / r['points']:.2f} | "
      f"{f['bytes'] / 1e6:.1f} | {int(size) / 1e6:.1f} | {f['seconds'][0]:.2g} to {f['seconds'][1]:.2g} | {wall} |")
PY
  done
fi

if [[ "$section" == all || "$section" == memory ]]; then
  echo
  echo "## 27. memory: the estimate against the peak"
  echo
  echo "Each type's surface area per volume times its cell (a 20 mm cube of 2 mm cells at 0.1 mm; the cube's"
  echo "cut faces, the solid's share of 2400 mm^2, taken off): the table in fill.cpp's area_per_volume."
  echo
  echo "| type | style | porosity | area / volume x cell | without the cut faces |"
  echo "|---|---|---:|---:|---:|"
  python3 - "$tmp/cube.off" <<'PY'
import sys
pts = [(x, y, z) for z in (0, 20) for y in (0, 20) for x in (0, 20)]
quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
with open(sys.argv[1], "w") as f:
    f.write("OFF\n8 12 0\n" + "".join("%d %d %d\n" % p for p in pts))
    f.write("".join("3 %d %d %d\n3 %d %d %d\n" % (a, b, c, a, c, d) for a, b, c, d in quads))
PY
  for style in network sheet; do
    for type in gyroid primitive diamond iwp neovius frd lidinoid splitp; do
      sheet=(); [[ $style == sheet ]] && sheet=(--sheet)
      ./build/tpmsfill fill "$tmp/cube.off" "$tmp/m.stl" --quiet --lattice "$type" "${sheet[@]}" \
        --cell 2 --voxel 0.1 --report "$tmp/m.json" 2>/dev/null
      python3 - "$type" "$style" "$tmp/m.json" <<'PY'
import json, sys
name, style, report = sys.argv[1:4]
r = json.load(open(report))
density, porosity = r["surface_density"], r["porosity"]
print(f"| {name} | {style} | {porosity:.2f} | {2 * density:.2f} | "
      f"{2 * (density - (1 - porosity) * 2400 / 8000):.2f} |")
PY
    done
  done
  mkdir -p "$tmp/mem"
  tar -xzf /usr/share/doc/libcgal-demo/data.tar.gz -C "$tmp/mem" --strip-components=2 \
    data/meshes/ChineseDragon-10kv.off data/meshes/elephant.off data/meshes/femur.off 2>/dev/null || true
  meshes=("$tmp"/mem/*.off)
  [[ -d ../shared/meshes ]] && meshes+=(../shared/meshes/*.{off,stl,STL,obj,ply})
  echo
  echo "| mesh | voxel mm | budget | samples | slab planes | triangles | estimate MB | peak MB | peak / estimate | peak / budget |"
  echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|"
  for f in "${meshes[@]}"; do
    [[ -f "$f" ]] || continue
    ./build/tpmsfill check --no-self-intersections --json "$f" >"$tmp/c.json" 2>/dev/null || true
    L=$(python3 -c 'import json,sys; b=json.load(open(sys.argv[1]))["bbox"]; print(max(b["max"][i]-b["min"][i] for i in range(3)))' "$tmp/c.json" 2>/dev/null) || continue
    for div in 10 15 20; do
      cell=$(python3 -c "print($L / 15)"); voxel=$(python3 -c "print($L / 15 / $div)")
      for budget in none half; do
        flags=()
        if [[ $budget == half ]]; then
          est=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["estimated_memory_bytes"])' "$tmp/m.json")
          flags=(--memory "$(python3 -c "print(int($est / 2))")")
        fi
        timed timeout 900 ./build/tpmsfill fill "$f" "$tmp/m.stl" --quiet --yes --cell "$cell" \
          --voxel "$voxel" --report "$tmp/m.json" "${flags[@]}" 2>"$tmp/err.txt"
        if [[ $code != 0 ]]; then
          echo "| $(basename "$f") | $(printf %.4g "$voxel") | $budget | refused (exit $code): $(head -c 120 "$tmp/err.txt" | tr '\n|' '  ') |"
          break
        fi
        python3 - "$(basename "$f")" "$voxel" "$budget" "$kb" "$tmp/m.json" "${flags[1]:-0}" <<'PY'
import json, sys
name, voxel, budget, kb, report, given = sys.argv[1:7]
r = json.load(open(report))
peak = int(kb) * 1024
est = r["estimated_memory_bytes"]
given = int(given)
print(f"| {name} | {float(voxel):.4g} | {budget if budget == 'none' else f'{given / 2**20:.0f} MB'} | "
      f"{r['grid']['samples']:,} | {r['slab_planes'] or ''} | {r['output']['triangles']:,} | {est / 2**20:.0f} | "
      f"{peak / 2**20:.0f} | {peak / est:.2f} | {peak / given if given else float('nan'):.2f} |")
PY
      done
    done
  done
fi

if [[ "$section" == all || "$section" == memory ]]; then
  echo
  echo "The service with serve --memory 1G: each fill job plans within the budget and ends as the"
  echo "kernel counted it (the job's peak_memory_bytes, its rusage)."
  echo
  echo "| mesh | voxel mm | state | slab planes | estimate MB | peak MB | peak / budget |"
  echo "|---|---:|---|---:|---:|---:|---:|"
  start_service "$tmp/serve-memory" --memory 1G
  for voxel in 0.4 0.2; do
    python3 - "$port" "$tmp/mem/ChineseDragon-10kv.off" "$voxel" <<'PY'
import json, sys, time, urllib.request
port, mesh, voxel = sys.argv[1:4]
token = "bench-token-0123456789"
boundary = "tpmsfill-bench"
body = (f"--{boundary}\r\nContent-Disposition: form-data; name=\"mesh\"; filename=\"dragon.off\"\r\n\r\n").encode()
body += open(mesh, "rb").read()
body += (f"\r\n--{boundary}\r\nContent-Disposition: form-data; name=\"options\"\r\n\r\n"
         + json.dumps({"voxel": float(voxel)}) + f"\r\n--{boundary}--\r\n").encode()
headers = {"Authorization": "Bearer " + token}
req = urllib.request.Request(f"http://127.0.0.1:{port}/v1/fill", data=body, method="POST",
                             headers={**headers, "Content-Type": f"multipart/form-data; boundary={boundary}"})
job = json.load(urllib.request.urlopen(req))["id"]
while True:
    j = json.load(urllib.request.urlopen(urllib.request.Request(
        f"http://127.0.0.1:{port}/v1/jobs/{job}?wait=30", headers=headers)))
    if j["state"] in ("done", "failed", "cancelled"):
        break
r = j.get("report") or {}
peak = j.get("peak_memory_bytes", 0)
print(f"| ChineseDragon-10kv.off | {voxel} | {j['state']} | {r.get('slab_planes') or ''} | "
      f"{r.get('estimated_memory_bytes', 0) / 2**20:.0f} | {peak / 2**20:.0f} | {peak / 2**30:.2f} |")
PY
  done
  kill "$server" 2>/dev/null || true
  wait "$server" 2>/dev/null || true
fi

if [[ "$section" == all || "$section" == slow-clients ]]; then
  echo
  echo "## 28. the service under slow clients"
  echo
  echo "| slow clients | health: median s | health: max s | slow clients let go after s |"
  echo "|---:|---:|---:|---:|"
  for n in 0 70 200; do
    start_service "$tmp/serve-$n"
    python3 - "$port" "$n" <<'PY'
import socket, statistics, sys, threading, time, urllib.request
port, n = int(sys.argv[1]), int(sys.argv[2])
slow = []
for _ in range(n):
    s = socket.create_connection(("127.0.0.1", port))
    s.setblocking(False)
    slow.append(s)
head = b"GET /v1/health HTTP/1.1\r\nHost: x\r\nX-Slow: "
start = time.monotonic()
closed_at = {}
done = False
def trickle():
    i = 0
    while not done:
        for k, s in enumerate(slow):
            if k in closed_at:
                continue
            try:
                s.send(head[i:i + 1] if i < len(head) else b"x")
            except OSError:
                closed_at[k] = time.monotonic() - start
            try:
                if s.recv(512) == b"":
                    closed_at[k] = time.monotonic() - start
            except BlockingIOError:
                pass
            except OSError:
                closed_at[k] = time.monotonic() - start
        i += 1
        time.sleep(0.2)
t = threading.Thread(target=trickle)
t.start()
time.sleep(1)
times = []
for _ in range(20):
    t0 = time.monotonic()
    urllib.request.urlopen(f"http://127.0.0.1:{port}/v1/health", timeout=120).read()
    times.append(time.monotonic() - t0)
    time.sleep(0.2)
while n and len(closed_at) < n and time.monotonic() - start < 40:
    time.sleep(0.2)
done = True
t.join()
let_go = f"{max(closed_at.values()):.1f}" if closed_at else "-"
print(f"| {n} | {statistics.median(times):.4f} | {max(times):.4f} | {let_go} |")
PY
    kill "$server"
    wait "$server" 2>/dev/null || true
  done
fi

