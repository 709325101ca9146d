#!/usr/bin/env bash
# `polyaxis laminate` on dome_sphere and on bumpy geodesic spheres of 82k and 328k triangles (100 mm
# tall), on sheets of 1, 2, 3 and 6 mm, 600x600 mm: the whole process's time (hyperfine median)
# beside `inspect`'s (reading and repairing the mesh once), the stages from lamination.json, the
# layers, sheets and their use, and the deviation of the sloped stack against vertical edges. No open
# tool laminates with sloped edges, so there is no peer to time.
# Prints a Markdown table on stdout (progress on stderr).
# Usage (from the repo root): bench/run_laminate_bench.sh      RUNS=5 runs per figure
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${RUNS:-5}
for p in hyperfine; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || {
    apt-get update -q >&2 && apt-get install -y -q --no-install-recommends "$p" >&2
  }
done
[ -f build/CMakeCache.txt ] || cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target polyaxis make_bench_mesh >/dev/null
cli=build/apps/polyaxis/polyaxis
mkdir -p bench/data
for k in 6 7; do
  name=$([ "$k" = 6 ] && echo bumpy_82k || echo bumpy_328k)
  [ -f "bench/data/$name.stl" ] || { echo "making bench/data/$name.stl" >&2; build/bench/make_bench_mesh "$k" "bench/data/$name.stl" >&2; }
done
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
median() { python3 -c "import json,sys; print('%.3f' % json.load(open(sys.argv[1]))['results'][0]['median'])" "$1"; }
echo "| part | triangles | laminate s | inspect s | layers / nesting / programs s | layers | sheets | mean use | sloped mm³ | stepped mm³ |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for part in examples/parts/dome_sphere.stl bench/data/bumpy_82k.stl bench/data/bumpy_328k.stl; do
  echo "timing $part" >&2
  args="--sheets 1,2,3,6 --sheet-size 600x600"
  hyperfine -N -w 1 -r "$runs" --export-json "$out/l.json" "$cli -q laminate $part $args -o $out/o" >/dev/null 2>&1
  hyperfine -N -w 1 -r "$runs" --export-json "$out/i.json" "$cli -q inspect $part --no-self-intersections" >/dev/null 2>&1
  tri=$("$cli" -q inspect "$part" --json --no-self-intersections | python3 -c "import json,sys; print(json.load(sys.stdin)['triangles'])")
  python3 - "$out/o/lamination.json" "$part" "$tri" "$(median "$out/l.json")" "$(median "$out/i.json")" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
st = d["stage_seconds"]
use = sum(s["utilisation"] for s in d["sheets"]) / max(1, len(d["sheets"]))
print(f"| {sys.argv[2].split('/')[-1]} | {sys.argv[3]} | {sys.argv[4]} | {sys.argv[5]} | {st['layers']:.2f} / {st['nesting']:.2f} / {st['programs']:.2f} "
      f"| {len(d['layers'])} | {len(d['sheets'])} | {100 * use:.1f} % | {d['sloped_deviation_mm3']:.0f} | {d['stepped_deviation_mm3']:.0f} |")
PY
done
