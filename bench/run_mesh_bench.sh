#!/usr/bin/env bash
# Read + repair + check of binary STL tori of about 100k, 1M and 4M triangles, on one core,
# against admesh reading the same files. Prints a Markdown table.
# Usage: bench/run_mesh_bench.sh   (installs admesh, hyperfine and GNU time when missing)
set -euo pipefail
cd "$(dirname "$0")/.."
for p in admesh hyperfine time; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ -n "${missing[*]:-}" ]; then apt-get update -q && apt-get install -y -q --no-install-recommends "${missing[@]}"; fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j"$(nproc)" --target polyaxis make_torus_stl bench_mesh >/dev/null
mkdir -p bench/data
declare -A sizes=([torus_100k]=100000 [torus_1m]=1000000 [torus_4m]=4000000)
for name in torus_100k torus_1m torus_4m; do
  [ -f bench/data/$name.stl ] || build/bench/make_torus_stl "${sizes[$name]}" bench/data/$name.stl >/dev/null
done
cli=build/apps/polyaxis/polyaxis
one_core=(taskset -c 0)
peak_kb() { command time -f %M "$@" 2>&1 >/dev/null | tail -n 1; }
median_s() {  # hyperfine median of a command, seconds
  hyperfine -N --runs "${RUNS:-5}" --warmup 1 --export-json /tmp/polyaxis-bench.json "$1" >/dev/null 2>&1
  /usr/bin/python3 -c "import json;print('%.3f'%json.load(open('/tmp/polyaxis-bench.json'))['results'][0]['median'])"
}
echo "| mesh | triangles | file MB | polyaxis read+repair+check s | with self-intersections s | admesh s | polyaxis peak B/triangle | admesh peak B/triangle |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for name in torus_100k torus_1m torus_4m; do
  f=bench/data/$name.stl
  tris=$(( ($(stat -c %s "$f") - 84) / 50 ))
  mb=$(( $(stat -c %s "$f") / 1000000 ))
  ours=$(median_s "${one_core[*]} $cli inspect --quiet $f --no-self-intersections")
  if [ "$tris" -le 1100000 ]; then selfint=$(median_s "${one_core[*]} $cli inspect --quiet $f"); else selfint="—"; fi
  theirs=$(median_s "${one_core[*]} admesh $f")
  ours_kb=$(peak_kb "${one_core[@]}" "$cli" inspect "$f" --no-self-intersections)
  theirs_kb=$(peak_kb "${one_core[@]}" admesh "$f")
  echo "| $name | $tris | $mb | $ours | $selfint | $theirs | $(( ours_kb * 1024 / tris )) | $(( theirs_kb * 1024 / tris )) |"
done
