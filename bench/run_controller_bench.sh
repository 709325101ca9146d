#!/usr/bin/env bash
# Nightly-size: plans run through LinuxCNC 2.9's simulator (tools/linuxcnc-sim) against the build-time
# estimate. For each part (default: the impeller and the decomposed L-block) it plans on the default
# machine (examples/machines/ded5_ac.json), runs the whole program in the controller and prints
# report.json's estimate and feed time against the controller's trajectory time, with the wall time.
# The impeller takes about 15 minutes of wall time at the runner's default x300 clock.
# Usage: bench/run_controller_bench.sh [BUILD_DIR] [PART...]   (figures also in bench/results/)
set -euo pipefail
build=${1:-build}
shift || true
parts=("$@")
[ ${#parts[@]} -gt 0 ] || parts=(impeller l_block)
src=$(cd "$(dirname "$0")/.." && pwd)
cli=$build/apps/polyaxis/polyaxis
machine=$src/examples/machines/ded5_ac.json
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$src/bench/results"
out=$src/bench/results/controller_$(date +%Y%m%d_%H%M%S).jsonl
for part in "${parts[@]}"; do
  "$cli" plan "$src/examples/parts/$part.stl" --machine "$machine" --quiet --no-html -o "$work/$part" >/dev/null
  LCNC_TIMEOUT=${LCNC_TIMEOUT:-3600} "$src/tools/linuxcnc-sim/lcnc_run.sh" "$machine" "$work/$part/$part.ngc" \
    >"$work/$part.lcnc.json" || true
  /usr/bin/python3 - "$part" "$work/$part/report.json" "$work/$part.lcnc.json" "$work/$part/$part.ngc" <<'PY' | tee -a "$out"
import json, sys
part, report, lcnc, ngc = sys.argv[1:]
r = json.load(open(report))
c = json.loads(open(lcnc).read().strip().splitlines()[-1])
t = c.get("trajectory_time_s")
row = {"part": part, "moves": sum(1 for l in open(ngc) if l.startswith(("G0", "G1"))),
       "controller_ok": c.get("ok"), "controller_errors": c.get("errors"), "controller_s": t,
       "estimate_s": round(r["build_time_s"], 1), "feed_time_s": round(r["feed_time_s"], 1),
       "estimate_vs_controller_pct": round(100 * (r["build_time_s"] / t - 1), 2) if t else None,
       "feed_vs_controller_pct": round(100 * (r["feed_time_s"] / t - 1), 2) if t else None,
       "wall_s": c.get("wall_time_s"), "speed": c.get("speed")}
print(json.dumps(row))
PY
done
