#!/usr/bin/env bash
# What report.html costs: the `plan` process with and without the page (hyperfine medians), the
# page's size, `polyaxis view` rewriting it from plan.json, and how long headless Chromium
# (software WebGL) takes until the viewer has drawn its first frame (viewer/test/browser_test.mjs).
# Parts: the impeller and generated meshes of about 82k and 1.3M triangles (bench/make_bench_mesh).
set -euo pipefail
cd "$(dirname "$0")/.."
source bench/plan_bench_setup.sh
median() { /usr/bin/python3 -c "import json;print('%.2f'%json.load(open('$1'))['results'][0]['median'])"; }
echo "| part | program points | plan --no-html s | plan s | report.html MiB | view s | browser ready s |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for f in examples/parts/impeller.stl bench/data/bumpy_82k.stl bench/data/bumpy_1.3m.stl; do
  name=$(basename "$f" .stl)
  runs=${RUNS:-3}
  hyperfine -N --runs "$runs" --export-json "$out/a.json" "$cli --quiet plan $f --no-html -o $out/a" >/dev/null 2>&1
  hyperfine -N --runs "$runs" --export-json "$out/b.json" "$cli --quiet plan $f -o $out/$name" >/dev/null 2>&1
  hyperfine -N --runs "$runs" --export-json "$out/c.json" "$cli view $out/$name/plan.json -o $out/v.html" >/dev/null 2>&1
  points=$(grep -c "^\[" "$out/$name/plan.json" || true)
  size=$(/usr/bin/python3 -c "import os;print('%.1f'%(os.path.getsize('$out/$name/report.html')/1048576))")
  ready=$(node viewer/test/browser_test.mjs "$out/$name/report.html" --timeout 180 | sed -n 's/.*ready in \([0-9.]*\) s.*/\1/p' | tail -1)
  echo "| $name | $points | $(median "$out/a.json") | $(median "$out/b.json") | $size | $(median "$out/c.json") | $ready |"
done
