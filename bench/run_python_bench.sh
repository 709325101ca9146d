#!/usr/bin/env bash
# The Python binding's cost (issue 17's figures), from a built tree:
#   1. a whole `polyaxis.plan(part)` + `plan.write(dir)` in a fresh python3 (import included) against
#      `polyaxis plan part -o dir` on the same part: medians of RUNS runs each (hyperfine when present);
#   2. the time to get a plan's program as numpy arrays (views: no copy) for a program of about a
#      million points (the impeller scaled by 1.5), and to copy it out, for comparison.
# Usage: bench/run_python_bench.sh [BUILD_DIR]   (RUNS=5 by default)
set -euo pipefail
build=${1:-build}
src=$(cd "$(dirname "$0")/.." && pwd)
runs=${RUNS:-5}
cli=$build/apps/polyaxis/polyaxis
export PYTHONPATH=$build/python
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for part in l_block pen_rack impeller; do
  stl=$src/examples/parts/$part.stl
  if command -v hyperfine >/dev/null; then
    hyperfine -r "$runs" -N --export-json "$work/$part.json" \
      -n cli "$cli plan $stl -o $work/cli -q" \
      -n python "/usr/bin/python3 -c \"import polyaxis; polyaxis.plan('$stl').write('$work/py')\"" >/dev/null
    /usr/bin/python3 - "$work/$part.json" "$part" <<'PY'
import json, sys
r = {x["command"]: x["median"] for x in json.load(open(sys.argv[1]))["results"]}
print(f"{sys.argv[2]:10s} cli {r['cli']:.3f} s  python {r['python']:.3f} s  overhead {r['python'] - r['cli']:+.3f} s "
      f"({100 * (r['python'] / r['cli'] - 1):+.1f} %)")
PY
  else
    echo "hyperfine not found (apt-get install hyperfine)"; exit 1
  fi
done
/usr/bin/python3 - "$src" <<'PY'
import sys, time
import numpy as np
import polyaxis
src = sys.argv[1]
opts = polyaxis.PlanOptions(strategy="single")
opts.part.scale = 1.5
t = time.perf_counter()
plan = polyaxis.plan(f"{src}/examples/parts/impeller.stl", opts)
t_plan = time.perf_counter() - t
t = time.perf_counter()
program = plan.program
t_views = time.perf_counter() - t
n = len(program["tip"])
t = time.perf_counter()
copied = {k: np.array(v) for k, v in program.items()}
t_copy = time.perf_counter() - t
print(f"impeller x1.5: {n} program points, plan {t_plan:.1f} s; plan.program as numpy views {t_views * 1e6:.0f} us, "
      f"copied out {t_copy * 1e3:.1f} ms ({sum(a.nbytes for a in copied.values()) / 1e6:.0f} MB)")
PY
