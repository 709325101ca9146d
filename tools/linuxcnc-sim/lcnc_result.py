#!/usr/bin/python3
"""Turn one lcnc_run.sh attempt (run dir) into the JSON result line.
usage: lcnc_result.py RUNDIR T_START T_END SPEED ATTEMPT
exit 0 = clean, 1 = controller error, 3 = machinery failure (retryable)."""
import json
import os
import re
import sys

run, t0, t1, speed, attempt = sys.argv[1:]
wall = float(t1) - float(t0)


def read(name):
    try:
        with open(os.path.join(run, name), errors="replace") as f:
            return f.read()
    except OSError:
        return ""


def program_dwell(path):
    """sum of G4 P<seconds> in the program (G4 is timed by milltask, not by
    motion, so it is not in the motion-time integrator).  Straight-line
    programs only: O-word loops/subroutines are not expanded."""
    total = 0.0
    for line in read(path).splitlines():
        line = re.sub(r"\(.*?\)|;.*", "", line).upper().replace(" ", "")
        if re.search(r"G0*4(?![0-9.])", line):
            m = re.search(r"P([-+]?[0-9.]+)", line)
            if m:
                total += float(m.group(1))
    return total


out = {"ok": False, "errors": [], "trajectory_time_s": None, "wall_time_s": round(wall, 3)}
machinery = []          # failures of the tooling / LinuxCNC plumbing, not of the program
r = {}
try:
    r = json.loads(read("result.json") or "{}")
except ValueError:
    machinery.append("unreadable result.json")
fatal = read("fatal").strip()
if fatal:
    machinery.append("lcnc_run: " + fatal)
log = read("linuxcnc.out")

out["errors"] = list(r.get("errors", []))
for e in list(out["errors"]):
    if e.startswith("lcnc_run:"):          # our own watchdog / setup messages
        out["errors"].remove(e)
        machinery.append(e)
done = r.get("stage") == "done"
for line in log.splitlines():
    # an I/O timeout during the setup that the display then retried is not a failure of the run
    if done and "timed out waiting for last command done" in line:
        out.setdefault("messages", []).append("linuxcnc log: " + line.strip())
        continue
    if re.search(r"USRMOT: ERROR: command timeout|RTAPI: ERROR|Can't execute DISPLAY|"
                 r"timed out waiting for last command done|insmod .* failed", line):
        machinery.append("linuxcnc log: " + line.strip())
if not r:
    tail = [l for l in log.splitlines() if l.strip() and "fallback_uid" not in l][-6:]
    machinery.append("linuxcnc produced no result; log tail: " + " | ".join(tail))
elif r.get("stage") != "done":
    machinery.append("run did not get past stage '%s'" % r.get("stage"))

if r.get("stage") == "done":
    dwell = program_dwell("program.ngc")
    mt = r.get("motion_time_s") or 0.0
    out["trajectory_time_s"] = round(mt + dwell, 4)
    out["motion_time_s"] = round(mt, 4)
    out["dwell_time_s"] = round(dwell, 4)
    out["span_time_s"] = round(r.get("span_time_s") or 0.0, 4)
    out["run_wall_s"] = r.get("run_real_s")
    out["last_line"] = r.get("last_line")
    out["final_joints"] = r.get("final_joints")
if r.get("messages"):
    out["messages"] = (out.get("messages", []) + r["messages"])[:20]
if r.get("setup_retries"):
    out["setup_retries"] = r["setup_retries"]
if r.get("servo_stalls"):
    out["servo_stalls_real_s"] = [s[1] for s in r["servo_stalls"]][:20]
out["speed"] = float(speed)
ini = read("run.ini")
m = re.search(r"SERVO_PERIOD = (\d+)", ini)
if m:
    out["servo_period_s"] = int(m.group(1)) * 1e-9
out["attempts"] = int(attempt)

if machinery:
    out["errors"] = machinery + out["errors"]
    # a run that merely took too long is not retried
    code = 2 if any("timeout (" in m or "real-time timeout" in m for m in machinery) else 3
elif out["errors"]:
    code = 1
else:
    code = 0
out["ok"] = code == 0
if code != 0 or os.environ.get("LCNC_KEEP") == "1":
    out["run_dir"] = run
print(json.dumps(out))
sys.exit(code)
