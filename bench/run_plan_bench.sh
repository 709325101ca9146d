#!/usr/bin/env bash
# Time `polyaxis plan` stage by stage on every reference part and on generated meshes of about
# 100k and 1.3M triangles (bench/make_bench_mesh, see bench/README.md). Prints a Markdown table
# from each run's report.json and timings.json (timings_s) plus the whole process's wall time (hyperfine median).
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/plan_bench_setup.sh
echo "| part | triangles | layers | program points | whole s | read | repair | slice | toolpath | program | support | gcode | simulate |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for f in examples/parts/*.stl bench/data/bumpy_82k.stl bench/data/bumpy_1.3m.stl; do
  name=$(basename "$f" .stl)
  runs=${RUNS:-3}
  hyperfine -N --runs "$runs" --warmup 0 --export-json "$out/h.json" "$cli --quiet plan $f -o $out/$name" >/dev/null 2>&1
  whole=$(/usr/bin/python3 -c "import json;print('%.2f'%json.load(open('$out/h.json'))['results'][0]['median'])")
  tris=$("$cli" --quiet inspect "$f" --json --no-self-intersections | /usr/bin/python3 -c "import json,sys;print(json.load(sys.stdin)['triangles'])")
  /usr/bin/python3 - "$out/$name/report.json" "$name" "$tris" "$whole" "$out/$name/plan.json" "$out/$name/timings.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
points = sum(1 for line in open(sys.argv[5]) if line.startswith('['))
t = json.load(open(sys.argv[6]))["timings_s"]
cols = [t[k] for k in ("read", "repair", "slice", "toolpath", "program", "support", "gcode", "simulate")]
print("| %s | %s | %d | %d | %s | %s |" % (sys.argv[2], sys.argv[3], r["layers"], points, sys.argv[4], " | ".join("%.3f" % c for c in cols)))
PY
done
