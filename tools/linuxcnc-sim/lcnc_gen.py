#!/usr/bin/python3
"""Generate a throw-away headless LinuxCNC 2.9 sim config (INI + HAL) from a
small JSON machine description.  Usage:
    lcnc_gen.py CONFIG.json PROGRAM.ngc OUTDIR
Writes OUTDIR/run.ini, OUTDIR/run.hal, OUTDIR/tool.tbl, OUTDIR/program.ngc
"""
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))

# JSON key -> kinematics HAL pin suffix (xyzac-trt-kins / xyzbc-trt-kins, LinuxCNC 2.9)
PIN_KEYS = {
    "pivot_x_mm": "x-offset",
    "pivot_y_mm": "y-offset",
    "pivot_z_mm": "z-offset",
    "x_offset_mm": "x-offset",
    "y_offset_mm": "y-offset",
    "z_offset_mm": "z-offset",
    "x_rot_point_mm": "x-rot-point",
    "y_rot_point_mm": "y-rot-point",
    "z_rot_point_mm": "z-rot-point",
    "tool_offset_mm": "tool-offset",
}

CONTINUOUS_LIMIT = 1.0e9      # joint/axis limit used for a continuous rotary
WIDE_WORLD_LIMIT = 1.0e6      # world (AXIS_x) limit for XYZ with non-trivial kins


def die(msg):
    sys.stderr.write("lcnc_gen: %s\n" % msg)
    sys.exit(2)


def lim_pair(v, name):
    if v is None:
        return None
    if isinstance(v, dict):
        if v.get("continuous"):
            return None
        return float(v["min"]), float(v["max"])
    if len(v) != 2:
        die("limit %s must be [min,max] or null" % name)
    return float(v[0]), float(v[1])


def from_machine_file(cfg):
    """accept a polyaxis machine file (e.g. examples/machines/ded5_ac.json) too"""
    if "pivot" not in cfg and "feed" not in cfg:
        return cfg
    c = dict(cfg)
    c.setdefault("kins", cfg.get("kinematics", "xyzac-trt"))
    for k, v in (cfg.get("pivot") or {}).items():
        if k in PIN_KEYS:
            c.setdefault(k, v)
    feed = cfg.get("feed") or {}
    c.setdefault("max_velocity", {
        "linear_mm_s": feed.get("linear_max_mm_min", 6000) / 60.0,
        "rotary_deg_s": feed.get("rotary_max_deg_min", 21600) / 60.0})
    acc = cfg.get("accel") or {}
    c.setdefault("max_accel", {"linear_mm_s2": acc.get("linear_mm_s2", 1000),
                               "rotary_deg_s2": acc.get("rotary_deg_s2", 3600)})
    return c


def program_kins(prog_path):
    """polyaxis programs whose axis words are joint positions say so in their header: those run
    with identity kinematics, whatever the machine's own kinematics module is"""
    with open(prog_path, errors="replace") as f:
        for _, line in zip(range(20), f):
            if "axis words are joint positions" in line:
                return "trivkins"
    return None


def main():
    if len(sys.argv) != 4:
        die("usage: lcnc_gen.py CONFIG.json PROGRAM.ngc OUTDIR")
    cfg_path, prog_path, out = sys.argv[1:]
    with open(cfg_path) as f:
        cfg = json.load(f)
    os.makedirs(out, exist_ok=True)
    cfg = from_machine_file(cfg)

    kins = os.environ.get("LCNC_KINS") or program_kins(prog_path) or cfg.get("kins", "xyzac-trt-kins")
    if kins in ("xyzac-trt-kins", "xyzac-trt"):
        kins, coords = "xyzac-trt-kins", "XYZAC"
    elif kins in ("xyzbc-trt-kins", "xyzbc-trt"):
        kins, coords = "xyzbc-trt-kins", "XYZBC"
    elif kins in ("trivkins", "identity"):
        kins = "trivkins"
        coords = "".join(k.upper() for k in "xyzabc" if k in cfg["limits"])
    else:
        die("unsupported kins %r" % kins)
    trivial = kins == "trivkins"

    limits = cfg["limits"]
    vel = cfg.get("max_velocity", {})
    acc = cfg.get("max_accel", {})
    lin_v = float(vel.get("linear_mm_s", 100.0))
    rot_v = float(vel.get("rotary_deg_s", 360.0))
    lin_a = float(acc.get("linear_mm_s2", 1000.0))
    rot_a = float(acc.get("rotary_deg_s2", 3600.0))
    servo_ns = int(cfg.get("servo_period_ns", 2000000))
    # world (Cartesian) XYZ limits: by default wide for non-trivial kins since
    # the machine limits are joint limits; "world_limits" may override.
    world = cfg.get("world_limits")

    pins = {}
    for k, pin in ([] if trivial else PIN_KEYS.items()):
        if k in cfg and cfg[k] is not None:
            pins[pin] = float(cfg[k])
    for pin, v in (cfg.get("kins_pins") or {}).items():
        pins[pin] = float(v)

    ini = []
    w = ini.append
    w("[EMC]\nVERSION = 1.1\nMACHINE = lcnc_run headless %s\nDEBUG = 0\n" % kins)
    w("[DISPLAY]\nDISPLAY = %s/lcnc_display.py\n" % HERE)
    w("CYCLE_TIME = 0.100\nPOSITION_OFFSET = RELATIVE\nPOSITION_FEEDBACK = COMMANDED\n")
    w("MAX_FEED_OVERRIDE = 1.0\n")
    w("[LCNCRUN]\nPROGRAM = %s/program.ngc\nRESULT = %s/result.json\n" % (out, out))
    speed = float(os.environ.get("LCNC_SPEED_OVERRIDE") or cfg.get("speed", 1))
    run_timeout = float(os.environ.get("LCNC_TIMEOUT_S") or cfg.get("timeout_s", 600))
    # the display itself runs in real time (not faked), hence SPEED = 1 there
    w("TIMEOUT = %g\nSPEED = 1\n" % max(5.0, run_timeout - 15.0))
    w("STALL_S = %g\n" % float(os.environ.get("LCNC_STALL_S") or cfg.get("stall_s", 10.0)))
    task_cycle = float(os.environ.get("LCNC_TASK_CYCLE") or cfg.get("task_cycle_s", 0.001))
    w("[TASK]\nTASK = milltask\nCYCLE_TIME = %g\n" % task_cycle)
    w("[RS274NGC]\nPARAMETER_FILE = %s/run.var\n" % out)
    w("RS274NGC_STARTUP_CODE = %s\n" % cfg.get("startup_code", "G21 G17 G90 G94 G40 G49 G54 G80"))
    servo_ns = int(os.environ.get("LCNC_SERVO_NS") or servo_ns)
    # COMM_TIMEOUT is read by milltask with its (faked) clock: 30 s of real time
    w("[EMCMOT]\nEMCMOT = motmod\nCOMM_TIMEOUT = %g\nBASE_PERIOD = 0\nSERVO_PERIOD = %d\n"
      % (30.0 * max(1.0, speed), servo_ns))
    io_cycle = float(os.environ.get("LCNC_IO_CYCLE") or cfg.get("io_cycle_s", 0.1))
    w("[EMCIO]\nEMCIO = io\nCYCLE_TIME = %g\nTOOL_TABLE = %s/tool.tbl\n" % (io_cycle, out))
    w("[HAL]\nHALFILE = %s/run.hal\n" % out)
    w("[TRAJ]\nCOORDINATES = %s\nLINEAR_UNITS = mm\nANGULAR_UNITS = degree\n" % coords)
    w("DEFAULT_LINEAR_VELOCITY = %g\nMAX_LINEAR_VELOCITY = %g\n" % (lin_v, lin_v))
    w("DEFAULT_LINEAR_ACCELERATION = %g\nMAX_LINEAR_ACCELERATION = %g\n" % (lin_a, lin_a))
    w("DEFAULT_ANGULAR_VELOCITY = %g\nMAX_ANGULAR_VELOCITY = %g\n" % (rot_v, rot_v))
    w("DEFAULT_ANGULAR_ACCELERATION = %g\nMAX_ANGULAR_ACCELERATION = %g\n" % (rot_a, rot_a))
    for k in ("ARC_BLEND_ENABLE", "ARC_BLEND_FALLBACK_ENABLE", "ARC_BLEND_OPTIMIZATION_DEPTH",
              "ARC_BLEND_GAP_CYCLES", "ARC_BLEND_RAMP_FREQ"):
        if k.lower() in cfg:
            w("%s = %s\n" % (k, cfg[k.lower()]))
    w("POSITION_FILE = %s/position.txt\n" % out)
    kline = "trivkins coordinates=%s" % coords if trivial else kins
    w("[KINS]\nKINEMATICS = %s\nJOINTS = %d\n" % (kline, len(coords)))

    joints = []
    for jno, ax in enumerate(coords):
        key = ax.lower()
        rotary = ax in "ABC"
        lp = lim_pair(limits.get(key), key)
        cont = lp is None
        jmin, jmax = (-CONTINUOUS_LIMIT, CONTINUOUS_LIMIT) if cont else lp
        if not rotary and world is None and not trivial:
            amin, amax = -WIDE_WORLD_LIMIT, WIDE_WORLD_LIMIT
        elif not rotary and world is not None and key in world:
            amin, amax = world[key]
        else:
            amin, amax = jmin, jmax
        v = rot_v if rotary else lin_v
        a = rot_a if rotary else lin_a
        home = 0.0 if jmin <= 0.0 <= jmax else 0.5 * (jmin + jmax)
        w("[AXIS_%s]\nMIN_LIMIT = %.9g\nMAX_LIMIT = %.9g\nMAX_VELOCITY = %g\nMAX_ACCELERATION = %g\n"
          % (ax, amin, amax, v, a))
        w("[JOINT_%d]\nTYPE = %s\nHOME = %.9g\nHOME_OFFSET = %.9g\nMIN_LIMIT = %.9g\nMAX_LIMIT = %.9g\n"
          "MAX_VELOCITY = %g\nMAX_ACCELERATION = %g\nFERROR = 1e9\nMIN_FERROR = 1e9\n"
          "HOME_SEARCH_VEL = 0\nHOME_LATCH_VEL = 0\nHOME_SEQUENCE = 0\n"
          % (jno, "ANGULAR" if rotary else "LINEAR", home, home, jmin, jmax, v, a))
        joints.append((jno, ax, cont))

    hal = []
    h = hal.append
    h("loadrt %s\n" % kline)
    h("loadrt [EMCMOT]EMCMOT base_period_nsec=[EMCMOT]BASE_PERIOD "
      "servo_period_nsec=[EMCMOT]SERVO_PERIOD num_joints=[KINS]JOINTS num_dio=8 num_aio=4\n")
    h("addf motion-command-handler servo-thread\naddf motion-controller servo-thread\n")
    for pin, v in sorted(pins.items()):
        h("setp %s.%s %.12g\n" % (kins, pin, v))
    for jno, ax, cont in joints:
        h("net j%d-pos joint.%d.motor-pos-cmd => joint.%d.motor-pos-fb\n" % (jno, jno, jno))
    h("net estop-loop iocontrol.0.user-enable-out => iocontrol.0.emc-enable-in\n")
    h("net tool-prep-loop iocontrol.0.tool-prepare => iocontrol.0.tool-prepared\n")
    h("net tool-change-loop iocontrol.0.tool-change => iocontrol.0.tool-changed\n")
    h("setp spindle.0.at-speed 1\n")
    # ---- trajectory-time instrumentation (all in the servo thread, nominal periods)
    # tm_motion : seconds during which motion is not in position (TP active)
    # tm_span   : seconds since the first motion after reset (flipflop latch)
    # tm_latch  : value of tm_span at the end of the last motion (sample/hold)
    # tm_total  : free-running seconds of servo-thread time
    h("loadrt not names=tm_moving\n")
    h("loadrt flipflop names=tm_started\n")
    h("loadrt mux2 names=tm_mgate,tm_sgate,tm_latch\n")
    h("loadrt integ names=tm_motion,tm_span,tm_total\n")
    for f in ("tm_moving", "tm_started", "tm_mgate", "tm_sgate", "tm_motion", "tm_span",
              "tm_total", "tm_latch"):
        h("addf %s servo-thread\n" % f)
    h("net tm-inpos motion.in-position => tm_moving.in\n")
    h("net tm-moving tm_moving.out => tm_mgate.sel tm_started.set tm_latch.sel\n")
    h("setp tm_mgate.in0 0\nsetp tm_mgate.in1 1\nsetp tm_sgate.in0 0\nsetp tm_sgate.in1 1\n")
    h("setp tm_total.in 1\n")
    h("net tm-mgate tm_mgate.out => tm_motion.in\n")
    h("net tm-started tm_started.out => tm_sgate.sel\n")
    h("net tm-sgate tm_sgate.out => tm_span.in\n")
    h("net tm-span tm_span.out => tm_latch.in1\n")
    h("net tm-latch tm_latch.out => tm_latch.in0\n")
    h("net tm-reset => tm_motion.reset tm_span.reset tm_started.reset\n")

    if cfg.get("trace") or os.environ.get("LCNC_TRACE"):
        # per-servo-cycle trace while moving: tm_total, current-vel, joints 0..2
        h("loadrt sampler depth=16000 cfg=fffff\naddf sampler.0 servo-thread\n")
        h("net tm-moving => sampler.0.enable\n")
        h("net tm-total tm_total.out => sampler.0.pin.0\n")
        h("net tr-vel motion.current-vel => sampler.0.pin.1\n")
        for j in range(3):
            h("net j%d-pos => sampler.0.pin.%d\n" % (j, j + 2))
        with open(os.path.join(out, "trace.sh"), "w") as f:
            f.write("#!/bin/sh\nexec halsampler -c 0 > %s/trace.txt\n" % out)
        os.chmod(os.path.join(out, "trace.sh"), 0o755)
        h("loadusr %s/trace.sh\n" % out)
    with open(os.path.join(out, "run.ini"), "w") as f:
        f.write("".join(ini))
    with open(os.path.join(out, "run.hal"), "w") as f:
        f.write("".join(hal))
    with open(os.path.join(out, "tool.tbl"), "w") as f:
        f.write("".join("T%d P%d D0 Z0 ;\n" % (i, i) for i in range(1, 11)))
    with open(os.path.join(out, "run.var"), "w") as f:
        f.write("5220 1.0\n")
    shutil.copyfile(prog_path, os.path.join(out, "program.ngc"))


if __name__ == "__main__":
    main()
