#!/usr/bin/python3
"""A plan run through LinuxCNC 2.9's own controller (tools/linuxcnc-sim): trajectory planner, soft
limits and all. Usage:

    controller_test.py POLYAXIS RUNNER MACHINE.json PART.stl run        [plan options...]
    controller_test.py POLYAXIS RUNNER MACHINE.json PART.stl limit-short [plan options...]

`run` plans the part on MACHINE.json and runs the program to its end in the controller configured
from the same machine file. It fails on any controller error (limit, G-code error), on a program the
controller did not run to its last line, and on a build-time estimate (report.json's build_time_s)
more than 2 % away from the controller's trajectory time.

`limit-short` plans the part the same way, then gives the controller a copy of the machine file
whose tilt (A or B) limit is one degree short of the program's largest tilt. The controller must refuse
the program with a limit error (runner exit 1): the limits the planner checks are the limits the
controller enforces.

Exit 0 = pass, 1 = fail."""
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

ESTIMATE_TOLERANCE = 0.02   # the bound on |estimate / controller - 1|


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def axis_words(ngc):
    """(line number, [(axis letter, value), ...]) for each line of NGC with axis words, comments
    removed (LinuxCNC's line numbers start at 1)"""
    with open(ngc) as f:
        for n, line in enumerate(f, 1):
            line = re.sub(r"\(.*?\)|;.*", "", line).upper()
            words = [(ax, float(v)) for ax, v in re.findall(r"([XYZABC])\s*([-+]?[0-9.]+)", line)]
            if words:
                yield n, words


def first_line_beyond(ngc, axis, limit, side):
    """the first line whose AXIS word goes beyond LIMIT on SIDE ('max' or 'min')"""
    for n, words in axis_words(ngc):
        if any(ax == axis and (v > limit if side == "max" else v < limit) for ax, v in words):
            return n
    return None


def program_extents(ngc):
    """per axis word: [min, max] over the program, and the number of its last line with an axis word"""
    ext, last = {}, 0
    for n, words in axis_words(ngc):
        last = n
        for ax, v in words:
            lo, hi = ext.get(ax, (float("inf"), float("-inf")))
            ext[ax] = (min(lo, v), max(hi, v))
    return ext, last


def plan(polyaxis, machine, part, opts, out):
    cmd = [polyaxis, "plan", part, "--machine", machine, "--quiet", "--no-html", "-o", out] + opts
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        fail("plan exited %d: %s\n%s" % (r.returncode, " ".join(cmd), r.stderr))
    stem = os.path.splitext(os.path.basename(part))[0]
    with open(os.path.join(out, "report.json")) as f:
        return os.path.join(out, stem + ".ngc"), json.load(f)


def run_controller(runner, machine, ngc):
    # Each attempt well within CTest's limit (900 s), retries included: a run that hangs is killed
    # by the runner, never left behind by CTest.
    env = dict(os.environ)
    env.setdefault("LCNC_TIMEOUT", "240")
    env.setdefault("LCNC_RETRIES", "2")
    r = subprocess.run([runner, machine, ngc], capture_output=True, text=True, env=env)
    sys.stderr.write(r.stderr)
    try:
        res = json.loads(r.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        fail("the runner printed no result (exit %d): %s %s" % (r.returncode, r.stdout, r.stderr))
    print("controller: exit %d, %s" % (r.returncode, json.dumps(res)))
    return r.returncode, res


def check_run(runner, machine, ngc, report):
    rc, res = run_controller(runner, machine, ngc)
    if rc != 0 or not res.get("ok") or res.get("errors"):
        fail("the controller did not run the program clean: %s" % res.get("errors"))
    _, last = program_extents(ngc)
    if (res.get("last_line") or 0) < last:
        fail("the controller stopped at line %s of %d" % (res.get("last_line"), last))
    controller = res["trajectory_time_s"]
    estimate = report["build_time_s"]
    ratio = estimate / controller - 1.0
    print("build time: estimate %.1f s, controller %.1f s (%+.2f %%), feed time %.1f s (%+.2f %%)"
          % (estimate, controller, 100 * ratio, report["feed_time_s"],
             100 * (report["feed_time_s"] / controller - 1.0)))
    if abs(ratio) > ESTIMATE_TOLERANCE:
        fail("the build-time estimate is %+.2f %% off the controller's time" % (100 * ratio))


def check_limit_short(runner, machine, ngc, work):
    with open(machine) as f:
        m = json.load(f)
    axis = "A" if "a" in m["limits"] else "B"
    ext, _ = program_extents(ngc)
    if axis not in ext:
        fail("the program never tilts: it cannot show a tilt limit")
    lo, hi = ext[axis]
    limit = m["limits"][axis.lower()]
    # one degree short of the program's extreme on the side the program passes first (the
    # controller stops there: the shorter the run)
    at_max = first_line_beyond(ngc, axis, hi - 1.0, "max") if hi > 0.0 else None
    at_min = first_line_beyond(ngc, axis, lo + 1.0, "min") if lo < 0.0 else None
    if at_max is None and at_min is None:
        fail("the program's tilt stays within one degree of 0")
    if at_min is None or (at_max is not None and at_max <= at_min):
        limit["max"] = hi - 1.0
        side = "%s max %.4f (the program reaches %.4f, first beyond at line %d)" % (axis, limit["max"], hi, at_max)
    else:
        limit["min"] = lo + 1.0
        side = "%s min %.4f (the program reaches %.4f, first beyond at line %d)" % (axis, limit["min"], lo, at_min)
    short = os.path.join(work, "machine_one_degree_short.json")
    with open(short, "w") as f:
        json.dump(m, f)
    print("machine file with %s" % side)
    rc, res = run_controller(runner, short, ngc)
    if rc != 1:
        fail("the controller should refuse the program with a limit error (exit 1), got exit %d" % rc)
    if not any(re.search(r"limit", e, re.I) for e in res.get("errors", [])):
        fail("the controller's errors name no limit: %s" % res.get("errors"))
    if res.get("run_dir", "").startswith(tempfile.gettempdir()):
        shutil.rmtree(res["run_dir"], ignore_errors=True)   # the runner keeps a failed run's files


def main():
    if len(sys.argv) < 6 or sys.argv[5] not in ("run", "limit-short"):
        sys.stderr.write(__doc__)
        sys.exit(1)
    polyaxis, runner, machine, part, mode = sys.argv[1:6]
    with tempfile.TemporaryDirectory(prefix="polyaxis-controller-") as work:
        ngc, report = plan(polyaxis, machine, part, sys.argv[6:], os.path.join(work, "plan"))
        if mode == "run":
            check_run(runner, machine, ngc, report)
        else:
            check_limit_short(runner, machine, ngc, work)
    print("PASS")


if __name__ == "__main__":
    main()
