#!/usr/bin/env bash
# Does `tpmsfill repair` meet its tolerance on the messy meshes people have? The corpus: every
# mesh of ../shared/meshes (when present), of libcgal-demo's data.tar.gz and of
# assimp-testmodels (STL, OBJ, PLY, OFF) that `tpmsfill check` finds invalid (exit 1), one of
# each set of byte-identical files. Each is repaired with the defaults (`--json`, nothing
# accepted past the tolerance) and the written mesh checked again; one table row per mesh:
# route that won, deviation against the tolerance, time. docs/benchmarks.md §29 quotes it.
#   bash scripts/repair_corpus.sh [BUILD] > corpus.md
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tool=$build/tpmsfill
[[ -x $tool ]] || { echo "repair_corpus: build $tool first (bash scripts/build.sh $build)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

meshes=()
source scripts/real_meshes.sh
real_meshes "$work"
candidates=("${meshes[@]}")
if [[ -d /usr/share/assimp/models ]]; then
  while IFS= read -r f; do candidates+=("$f"); done < <(find /usr/share/assimp/models -type f \
    \( -iname '*.off' -o -iname '*.ply' -o -iname '*.obj' -o -iname '*.stl' \) | sort)
fi
[[ ${#candidates[@]} -gt 0 ]] || { echo "repair_corpus: no meshes (apt-get install libcgal-demo assimp-testmodels)" >&2; exit 2; }

declare -A seen
corpus=()
for f in "${candidates[@]}"; do
  sum=$(sha256sum "$f" | cut -c1-64)
  [[ -n ${seen[$sum]:-} ]] && continue
  seen[$sum]=1
  timeout 300 "$tool" check "$f" >/dev/null 2>&1
  [[ $? -eq 1 ]] && corpus+=("$f")
done

echo "| mesh | source | exit | route | deviation (mm) | tolerance (mm) | deviation / tolerance | volume | check of output | s |"
echo "|---|---|---:|---|---:|---:|---:|---:|---|---:|"
for m in "${corpus[@]}"; do
  case $m in
    ../shared/*) source=shared ;;
    /usr/share/assimp/*) source=assimp ;;
    *) source=cgal-demo ;;
  esac
  rm -f "$work/out.stl"
  start=$(date +%s.%N)
  timeout 900 "$tool" repair "$m" "$work/out.stl" --json --progress none >"$work/out.json" 2>"$work/err"
  rc=$?
  end=$(date +%s.%N)
  verdict="-"
  if [[ -f $work/out.stl ]]; then
    "$tool" check "$work/out.stl" >/dev/null 2>&1 && verdict=valid || verdict="NOT VALID"
  fi
  python3 - "$m" "$source" "$rc" "$work/out.json" "$verdict" "$start" "$end" <<'PY'
import json, sys, os
m, source, rc, path, verdict, start, end = sys.argv[1:]
name = os.path.basename(m)
if "/assimp/models/" in m:
    name = m.split("/assimp/models/")[1]
seconds = float(end) - float(start)
try:
    j = json.load(open(path))
except Exception:
    print(f"| {name} | {source} | {rc} | - | - | - | - | - | {verdict} | {seconds:.1f} |"); sys.exit()
route = j.get("route") or ("wrap" if j.get("wrapped") else "repair")
if not j["valid"]:
    print(f"| {name} | {source} | {rc} | none valid | - | {j['tolerance']:.3g} | - | - | {verdict} | {seconds:.1f} |"); sys.exit()
d = j["deviation"]
worst = max(d["to_input"]["max"], d["from_input"]["max"], d["bbox_growth"], d["added_thickness"])
ratio = worst / j["tolerance"] if j["tolerance"] else float("nan")
print(f"| {name} | {source} | {rc} | {route} | {worst:.3g} | {j['tolerance']:.3g} | {ratio:.2f} | "
      f"{100 * d['volume_change']:+.1f} % | {verdict} | {seconds:.1f} |")
PY
done | tee "$work/rows"
python3 - "$work/rows" <<'PY'
import sys
rows = [[c.strip() for c in l.split("|")[1:-1]] for l in open(sys.argv[1]) if l.startswith("|")]
ok = [r for r in rows if r[2] == "0" and r[8] == "valid"]
routes = {}
for r in ok:
    routes[r[3]] = routes.get(r[3], 0) + 1
times = sorted(float(r[9]) for r in rows)
n = len(rows)
print(f"\n{n} invalid meshes; {len(ok)} repaired valid within the tolerance and written "
      f"({100 * len(ok) / max(n, 1):.1f} %); routes: " + ", ".join(f"{k} {v}" for k, v in sorted(routes.items())))
if times:
    print(f"time: median {times[len(times) // 2]:.1f} s, largest {times[-1]:.1f} s")
PY
