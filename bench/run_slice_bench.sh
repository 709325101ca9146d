#!/usr/bin/env bash
# Planar slicing at 0.2 mm layers of bumpy geodesic spheres (100 mm tall, ~500 layers) of 82k,
# 328k, 1.3M and 5.2M triangles: polyaxis' whole `slice` process against PrusaSlicer's and
# CuraEngine's slicing step alone, timed as /work/shared/BENCHMARKS.md says, in the same run.
# Prints Markdown tables on stdout (progress on stderr).
# Usage (from the repo root): bench/run_slice_bench.sh
#   RUNS=3          runs per figure (median; hyperfine adds one warm-up run for polyaxis)
#   LEVELS="6 7 8 9" subdivision levels of the meshes to run (20*4^LEVEL triangles)
#   PEER_LIMIT_S=60 if one peer run takes longer than this, its other runs are skipped
set -euo pipefail
cd "$(dirname "$0")/.."

runs=${RUNS:-3}
levels=${LEVELS:-6 7 8 9}
peer_limit_s=${PEER_LIMIT_S:-60}
layer=0.2

# 1. Tools.
missing=()
for p in prusa-slicer cura-engine cura hyperfine time; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ "${#missing[@]}" -gt 0 ]; then
  echo "installing ${missing[*]}" >&2
  apt-get update -q >&2 && apt-get install -y -q --no-install-recommends "${missing[@]}" >&2
fi
cura_def=$(dpkg -L cura | grep '/definitions/fdmprinter.def.json$' | head -n 1)
[ -n "$cura_def" ] || { echo "fdmprinter.def.json not found in the cura package" >&2; exit 1; }

# 2. Build and meshes.
[ -f build/CMakeCache.txt ] || cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake -S . -B build >/dev/null  # picks up the make_bench_mesh target if the tree was configured before it
cmake --build build -j2 --target polyaxis make_bench_mesh >/dev/null
cli=build/apps/polyaxis/polyaxis
mkdir -p bench/data
declare -A names=([6]=bumpy_82k [7]=bumpy_328k [8]=bumpy_1.3m [9]=bumpy_5.2m)
for k in $levels; do
  f=bench/data/${names[$k]}.stl
  [ -f "$f" ] || { echo "making $f" >&2; build/bench/make_bench_mesh "$k" "$f" >&2; }
done

tmp=$(mktemp -d /tmp/polyaxis-slice-bench.XXXXXX)
trap 'rm -rf "$tmp"' EXIT

median() {  # median of the numbers given as arguments
  printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {
    if (NR == 0) print "n/a"; else if (NR % 2) print v[(NR + 1) / 2]; else print (v[NR / 2] + v[NR / 2 + 1]) / 2 }'
}
hyperfine_ms() {  # hyperfine median of one command, ms
  hyperfine -N --runs "$runs" --warmup 1 --export-json "$tmp/hf.json" "$1" >/dev/null 2>&1 ||
    { echo "hyperfine failed: $1" >&2; exit 1; }
  /usr/bin/python3 -c "import json,sys;print('%.0f'%(1000*json.load(open(sys.argv[1]))['results'][0]['median']))" "$tmp/hf.json"
}
peak_mib() {  # GNU time's maximum resident set size of one run of the command, MiB
  /usr/bin/time -f %M -o "$tmp/time.txt" "$@" >/dev/null 2>&1
  echo $(( $(tail -n 1 "$tmp/time.txt") / 1024 ))
}
prusa_step_ms() {  # PrusaSlicer log: first 'slice_mesh to polygons' to last 'removing top empty layers'
  awk '
    function secs(field,  t) { split(field, t, /[:\]]/); return t[1] * 3600 + t[2] * 60 + t[3] }
    /slice_mesh to polygons/ && s == "" { s = secs($2) }
    /Slicing volumes - removing top empty layers/ { e = secs($2) }
    END { if (s == "" || e == "") print "n/a"; else { d = e - s; if (d < 0) d += 86400; printf "%.0f\n", d * 1000 } }' "$1"
}
cura_step_ms() {  # CuraEngine log: 'slice of mesh took' + 'slice make polygons took'
  awk '
    /slice of mesh took [0-9.]+ seconds/ { a += $(NF - 1); na++ }
    /slice make polygons took [0-9.]+ seconds/ { b += $(NF - 1); nb++ }
    END { if (!na || !nb) print "n/a"; else printf "%.0f\n", (a + b) * 1000 }' "$1"
}
peer_argv() {  # sets cmd to the peer's command line for a mesh (BENCHMARKS.md's flags)
  if [ "$1" = prusa ]; then
    cmd=(prusa-slicer --export-gcode --layer-height "$layer" --first-layer-height "$layer" --skirts 0
      --brim-width 0 --perimeter-generator classic --loglevel 4 --perimeters 1 --top-solid-layers 0
      --bottom-solid-layers 0 --fill-density 0% "$2" -o "$tmp/prusa.gcode")
  else
    cmd=(CuraEngine slice -v -j "$cura_def" -s layer_height="$layer" -s layer_height_0="$layer"
      -s adhesion_type=none -s machine_width=200 -s machine_depth=200 -s machine_height=200
      -s wall_line_count=1 -s top_layers=0 -s bottom_layers=0 -s initial_bottom_layers=0
      -s infill_sparse_density=0 -s infill_line_distance=0 -l "$2" -o "$tmp/cura.gcode")
  fi
}
# Runs a peer (prusa or cura) up to $runs times on a mesh; sets peer_ms (median step time),
# peer_mib (median peak RSS), peer_layers and peer_note.
run_peer() {
  local peer=$1 mesh=$2 i wall kb cmd steps=() mibs=()
  peer_argv "$peer" "$mesh"
  peer_note=""
  for ((i = 1; i <= runs; i++)); do
    /usr/bin/time -f '%e %M' -o "$tmp/peer-time.txt" "${cmd[@]}" >"$tmp/$peer.log" 2>&1 ||
      { echo "$peer failed on $mesh; log: $(tail -n 5 "$tmp/$peer.log")" >&2; steps=(); break; }
    read -r wall kb < <(tail -n 1 "$tmp/peer-time.txt")
    steps+=("$("${peer}_step_ms" "$tmp/$peer.log")")
    mibs+=($((kb / 1024)))
    if [ "${steps[-1]}" = "n/a" ]; then
      echo "$peer: slicing-step log lines not found in $tmp/$peer.log:" >&2
      grep -nE "slice|Slicing|took" "$tmp/$peer.log" | head -n 20 >&2 || true
      steps=(); break
    fi
    if awk -v w="$wall" -v l="$peer_limit_s" 'BEGIN { exit !(w > l) }' && [ "$i" -lt "$runs" ]; then
      peer_note="¹"; echo "$peer took ${wall}s on $mesh: skipping its other runs" >&2; break
    fi
  done
  if [ "${#steps[@]}" -eq 0 ]; then peer_ms="n/a"; peer_mib="n/a"; else
    peer_ms=$(median "${steps[@]}"); peer_mib=$(median "${mibs[@]}"); fi
  if [ "$peer" = cura ]; then
    peer_layers=$(grep -m1 '^;LAYER_COUNT:' "$tmp/cura.gcode" 2>/dev/null | cut -d: -f2 || true)
  else
    peer_layers=$(grep -c '^;LAYER_CHANGE' "$tmp/prusa.gcode" 2>/dev/null || true)
  fi
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b + 0 > 0 && a + 0 > 0) printf "%.2f", a / b; else print "—" }'; }

# 3. Measure.
threads_default=$(nproc)
rows=() thread_rows=() notes=()
for k in $levels; do
  name=${names[$k]}
  f=bench/data/$name.stl
  tris=$(( ($(stat -c %s "$f") - 84) / 50 ))
  echo "== $name ($tris triangles)" >&2
  summary=$("$cli" --quiet slice "$f" --layer "$layer" -o "$tmp/out" 2>"$tmp/polyaxis.err") ||
    { cat "$tmp/polyaxis.err" >&2; exit 1; }
  layers=${summary%% layers*}
  [ -s "$tmp/polyaxis.err" ] && notes+=("polyaxis on $name said: $(tr '\n' ' ' <"$tmp/polyaxis.err")")
  slice_ms=$(hyperfine_ms "$cli slice $f --layer $layer -o $tmp/out")
  slice1_ms=$(hyperfine_ms "$cli slice $f --layer $layer -o $tmp/out --threads 1")
  read_ms=$(hyperfine_ms "$cli inspect --quiet $f --no-self-intersections")
  mibs=()
  for ((i = 1; i <= runs; i++)); do mibs+=("$(peak_mib "$cli" slice "$f" --layer "$layer" -o "$tmp/out")"); done
  ours_mib=$(median "${mibs[@]}")
  echo "   polyaxis: slice ${slice_ms} ms (1 thread ${slice1_ms} ms), read+repair ${read_ms} ms, ${ours_mib} MiB" >&2
  run_peer prusa "$f"; prusa_ms=$peer_ms; prusa_note=$peer_note; prusa_layers=$peer_layers
  echo "   PrusaSlicer: slicing step ${prusa_ms} ms, ${prusa_layers} layers" >&2
  run_peer cura "$f"; cura_ms=$peer_ms; cura_note=$peer_note; cura_mib=$peer_mib; cura_layers=$peer_layers
  echo "   CuraEngine: slicing step ${cura_ms} ms, ${cura_layers} layers, ${cura_mib} MiB" >&2
  for pl in "$prusa_layers" "$cura_layers"; do
    if [ -n "$pl" ] && [ "$pl" -gt 0 ] 2>/dev/null && [ $(( pl > layers ? pl - layers : layers - pl )) -gt 1 ]; then
      notes+=("$name: polyaxis made $layers layers, a peer $pl"); fi
  done
  rows+=("| $name | $tris | $layers | $slice_ms | $read_ms | $prusa_ms$prusa_note | $cura_ms$cura_note | $(ratio "$slice_ms" "$prusa_ms") | $(ratio "$slice_ms" "$cura_ms") | $ours_mib | $cura_mib |")
  thread_rows+=("| $name | $tris | $slice1_ms | $slice_ms | $(ratio "$slice1_ms" "$slice_ms") |")
done

# 4. Report.
echo "Slicing at $layer mm, medians of $runs runs, $(date -u +%Y-%m-%dT%H:%MZ), $(nproc) cores;" \
  "PrusaSlicer $(dpkg-query -W -f='${Version}' prusa-slicer), CuraEngine $(dpkg-query -W -f='${Version}' cura-engine)."
echo
echo "| mesh | triangles | layers | polyaxis slice (whole process) ms | polyaxis read+repair ms | PrusaSlicer slicing step ms | CuraEngine slicing step ms | polyaxis/Prusa | polyaxis/Cura | polyaxis peak MiB | CuraEngine peak MiB |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
printf '%s\n' "${rows[@]}"
echo
echo "| mesh | triangles | polyaxis slice --threads 1 ms | default ($threads_default threads) ms | speed-up |"
echo "|---|---:|---:|---:|---:|"
printf '%s\n' "${thread_rows[@]}"
case "${rows[*]}" in *¹*) echo; echo "¹ one run only: it took longer than ${peer_limit_s} s." ;; esac
if [ "${#notes[@]}" -gt 0 ]; then echo; printf -- '- %s\n' "${notes[@]}"; fi
