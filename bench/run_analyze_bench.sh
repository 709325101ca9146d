#!/usr/bin/env bash
# Time `polyaxis analyze` stage by stage (overhang map, centroidal axis, skeleton, decomposition)
# on every reference part and on the ~1.3M-triangle bumpy sphere (bench/make_bench_mesh 8).
# Prints a Markdown table of the timings_s of analysis.json (median of RUNS runs), and how far the
# two opinions on the shape agree: the mean and largest distance from a centroidal-axis node to the
# nearest edge of the distance-field skeleton (straight segments between its nodes), in mm.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target polyaxis make_bench_mesh >/dev/null
mkdir -p bench/data
[ -f bench/data/bumpy_1.3m.stl ] || build/bench/make_bench_mesh 8 bench/data/bumpy_1.3m.stl >/dev/null
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
runs=${RUNS:-3}
echo "| part | triangles | overhang ms | centroidal axis ms | skeleton ms | decomposition ms | regions | axis branches | skeleton edges | axis→skeleton mean mm | max mm |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
for f in examples/parts/*.stl bench/data/bumpy_1.3m.stl; do
  name=$(basename "$f" .stl)
  for i in $(seq "$runs"); do
    build/apps/polyaxis/polyaxis --quiet analyze "$f" -o "$out/$name" >/dev/null 2>&1
    cp "$out/$name/analysis.json" "$out/$name.$i.json"
  done
  /usr/bin/python3 - "$name" "$f" "$out" "$runs" <<'PY'
import json, statistics, sys, struct, os
name, path, out, runs = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
docs = [json.load(open(f"{out}/{name}.{i}.json")) for i in range(1, runs + 1)]
med = lambda k: statistics.median(d["timings_s"][k] for d in docs) * 1000
d = docs[0]
data = open(path, "rb").read(84)
tris = (os.path.getsize(path) - 84) // 50 if not data.startswith(b"solid") else sum(1 for l in open(path, errors="ignore") if "endfacet" in l)
def seg_dist(p, a, b):
    ab = [b[i] - a[i] for i in range(3)]
    ap = [p[i] - a[i] for i in range(3)]
    l2 = sum(x * x for x in ab)
    t = max(0.0, min(1.0, sum(ap[i] * ab[i] for i in range(3)) / l2)) if l2 > 0 else 0.0
    return sum((ap[i] - t * ab[i]) ** 2 for i in range(3)) ** 0.5
mean = worst = float("nan")
if d["skeleton"] and d["skeleton"]["edges"]:
    pos = {n["id"]: n["position"] for n in d["skeleton"]["nodes"]}
    segs = [(pos[e["from"]], pos[e["to"]]) for e in d["skeleton"]["edges"]]
    dists = [min(seg_dist(n["position"], a, b) for a, b in segs) for n in d["centroidal_axis"]["nodes"]]
    if dists:
        mean, worst = sum(dists) / len(dists), max(dists)
print("| %s | %d | %.1f | %.1f | %.1f | %.1f | %d | %d | %d | %.1f | %.1f |" % (name, tris, med("overhang"), med("centroidal_axis"), med("skeleton"), med("decompose"),
      len(d["regions"]), len(d["centroidal_axis"]["branches"]), len(d["skeleton"]["edges"]) if d["skeleton"] else 0, mean, worst))
PY
done
