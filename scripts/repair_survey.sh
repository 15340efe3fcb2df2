#!/usr/bin/env bash
# How far `tpmsfill repair` moves real meshes: runs it on every mesh in ../shared/meshes (when
# present) and every libcgal-demo mesh under 2 MB, and prints one table row per mesh
# (deviation max and p95 as % of the diagonal, volume change, box growth, wrapped or not),
# then the distribution. docs/benchmarks.md §13 quotes its output.
#   bash scripts/repair_survey.sh [BUILD] > survey.md
set -uo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
tool=$build/tpmsfill
[[ -x $tool ]] || { echo "repair_survey: build $tool first (bash scripts/build.sh $build)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
meshes=()
source scripts/real_meshes.sh
real_meshes "$work" -size -2M
echo "| mesh | exit | wrapped | to input max / p95 (% diag) | from input max / p95 (% diag) | volume | box growth (% diag) | within 1 % | s |"
echo "|---|---:|---|---:|---:|---:|---:|---|---:|"
for m in "${meshes[@]}"; do
  json=$work/out.json
  timeout 300 "$tool" repair "$m" "$work/out.off" --json --accept-deviation > "$json" 2> "$work/err"
  rc=$?
  python3 - "$m" "$rc" "$json" <<'PY'
import json, math, sys, os
name, rc, path = os.path.basename(sys.argv[1]), sys.argv[2], sys.argv[3]
try:
    j = json.load(open(path))
except Exception:
    print(f"| {name} | {rc} | - | - | - | - | - | - | - |"); sys.exit()
b = j["before"]["bbox"]
diag = math.dist(b["min"], b["max"]) if b else 0
if not j["valid"] or diag == 0:
    print(f"| {name} | {rc} | {j['wrapped']} | not valid | | | | | {j['seconds']:.2f} |"); sys.exit()
d = j["deviation"]
pc = lambda v: 100 * v / diag
print(f"| {name} | {rc} | {'wrap' if j['wrapped'] else 'no'} | {pc(d['to_input']['max']):.3g} / {pc(d['to_input']['p95']):.2g} "
      f"| {pc(d['from_input']['max']):.3g} / {pc(d['from_input']['p95']):.2g} | {100*d['volume_change']:+.2f} % "
      f"| {pc(d['bbox_growth']):.3g} | {'yes' if j['within_tolerance'] else 'NO'} | {j['seconds']:.2f} |")
PY
done | tee "$work/rows"
python3 - "$work/rows" <<'PY'
import sys, re
rows = [l.split("|")[1:-1] for l in open(sys.argv[1]) if l.startswith("|")]
valid = [r for r in rows if "/" in r[3]]
worst = [max(float(r[3].split("/")[0]), float(r[4].split("/")[0])) for r in valid]
p95 = [max(float(r[3].split("/")[1]), float(r[4].split("/")[1])) for r in valid]
wraps = sum(1 for r in valid if r[2].strip() == "wrap")
within = sum(1 for r in valid if r[7].strip() == "yes")
worst.sort(); p95.sort()
q = lambda a, f: a[min(len(a) - 1, int(f * (len(a) - 1)))] if a else float("nan")
print(f"\n{len(rows)} meshes, {len(valid)} repaired valid, {wraps} wrapped, {within} within the 1 % tolerance")
print(f"max deviation (% of diagonal): median {q(worst, .5):.3g}, 90th percentile {q(worst, .9):.3g}, largest {q(worst, 1):.3g}")
print(f"p95 deviation (% of diagonal): median {q(p95, .5):.3g}, largest {q(p95, 1):.3g}")
PY
