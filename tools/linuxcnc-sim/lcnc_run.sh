#!/bin/bash
# lcnc_run.sh CONFIG.json PROGRAM.ngc
#
# Runs PROGRAM headless through LinuxCNC 2.9 (Debian linuxcnc-uspace, sim
# motion with the kinematics/limits of CONFIG.json) and prints one JSON line:
#   {"ok":..,"errors":[..],"trajectory_time_s":T,"wall_time_s":W, ...details}
# Exit 0 = program ran clean, 1 = controller reported an error (limit, G-code
# error, ...), 2 = the run could not be started / completed.
#
# Environment knobs (all optional):
#   LCNC_SPEED     clock speed factor for rtapi_app+milltask+io via libfaketime
#                  (default: CONFIG "speed", else 300; 1 = real time, no faketime)
#   LCNC_SERVO_NS  servo period in ns (default: CONFIG "servo_period_ns", else 2000000;
#                  the standard sim uses 1000000)
#   LCNC_TIMEOUT   real-time limit in seconds per attempt (default 900)
#   LCNC_RETRIES   extra attempts after an infrastructure failure (default 2)
#   LCNC_KEEP=1    keep the generated run directory (kept anyway on failure)
#   LCNC_WORKDIR   where run directories go (default ${TMPDIR:-/tmp}/polyaxis-lcnc)
set -u
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
PY=/usr/bin/python3
FT_LIB=/usr/lib/x86_64-linux-gnu/faketime/libfaketime.so.1

emit_fail() {  # $1 = message
    $PY -c 'import json,sys; print(json.dumps({"ok": False, "errors": [sys.argv[1]],
        "trajectory_time_s": None, "wall_time_s": 0.0}))' "$1"
}

if [ $# -ne 2 ] || [ ! -r "$1" ] || [ ! -r "$2" ]; then
    echo "usage: $0 CONFIG.json PROGRAM.ngc" >&2
    emit_fail "bad arguments (usage: lcnc_run.sh CONFIG.json PROGRAM.ngc)"
    exit 2
fi
CFG=$(readlink -f "$1"); PROG=$(readlink -f "$2")
SPEED=${LCNC_SPEED:-$($PY -c 'import json,sys; print(json.load(open(sys.argv[1])).get("speed", 300))' "$CFG" 2>/dev/null)}
SPEED=${SPEED:-300}
TIMEOUT=${LCNC_TIMEOUT:-900}
RETRIES=${LCNC_RETRIES:-2}
T_START=$(date +%s.%N)

command -v linuxcnc >/dev/null || { emit_fail "linuxcnc not found: apt-get install linuxcnc-uspace"; exit 2; }
WORK=${LCNC_WORKDIR:-${TMPDIR:-/tmp}/polyaxis-lcnc}
mkdir -p "$WORK" || { emit_fail "cannot create $WORK"; exit 2; }

# LinuxCNC allows one instance per machine (/tmp/linuxcnc.lock): serialize every
# run on the machine, whichever checkout it comes from.
exec 9>/tmp/polyaxis-lcnc.lock
if ! flock -w "$TIMEOUT" 9; then emit_fail "could not get /tmp/polyaxis-lcnc.lock"; exit 2; fi

# rtapi_app (setuid root) refuses to run as root without a fallback uid; its
# socket directory must be writable by that uid.
mkdir -p "$WORK/rt" && chmod 1777 "$WORK/rt"
export RTAPI_UID=${RTAPI_UID:-65534}
export RTAPI_FIFO_PATH="$WORK/rt/.rtapi_fifo"
unset DISPLAY   # never try X

run_once() {  # $1 = run dir; runs linuxcnc once, leaves $1/result.json
    local RUN=$1 LPID SID TIMED_OUT=0 DEADLINE
    export LCNC_SPEED_OVERRIDE=$SPEED LCNC_TIMEOUT_S=$TIMEOUT
    if ! $PY "$HERE/lcnc_gen.py" "$CFG" "$PROG" "$RUN" 2>"$RUN/gen.err"; then
        echo "config generation failed: $(tr '\n' ' ' <"$RUN/gen.err")" >"$RUN/fatal"
        return
    fi
    local PATHX=$PATH
    if [ "$SPEED" != "1" ]; then
        [ -r "$FT_LIB" ] || { echo "libfaketime missing: apt-get install libfaketime" >"$RUN/fatal"; return; }
        # Only rtapi_app (servo thread = motion + trajectory planner), io and
        # milltask (task cycle, G4 dwell timer, motion command timeouts) see a
        # clock running SPEED x faster.  halcmd spawns rtapi_app and io, the
        # linuxcnc script starts milltask: wrap both via PATH.
        mkdir -p "$RUN/bin"
        for prog in halcmd milltask; do
            cat >"$RUN/bin/$prog" <<EOF
#!/bin/sh
LD_PRELOAD=$FT_LIB FAKETIME="+0 x$SPEED" FAKETIME_ONLY_CMDS=rtapi_app,milltask,io exec /usr/bin/$prog "\$@"
EOF
            chmod +x "$RUN/bin/$prog"
        done
        PATHX="$RUN/bin:$PATH"
    fi
    # default timer slack (50 us) stretches every short sleep of the (sped-up)
    # task; 1 ns is inherited by all children
    echo 1 >/proc/$BASHPID/timerslack_ns 2>/dev/null || true
    PATH=$PATHX setsid linuxcnc -r "$RUN/run.ini" >"$RUN/linuxcnc.out" 2>&1 </dev/null &
    LPID=$!
    sleep 0.2
    SID=$(ps -o sid= -p $LPID 2>/dev/null | tr -d ' ')
    [ -z "$SID" ] && SID=$LPID
    DEADLINE=$(( $(date +%s) + TIMEOUT ))
    while kill -0 $LPID 2>/dev/null; do
        if [ "$(date +%s)" -ge "$DEADLINE" ]; then TIMED_OUT=1; break; fi
        sleep 0.2
    done
    if [ $TIMED_OUT = 1 ]; then
        echo "killed after $TIMEOUT s real-time timeout" >"$RUN/fatal"
        # stop our display first: it writes its result and exits, then the
        # linuxcnc script runs its own Cleanup
        local dpid
        dpid=$(ps -e -o pid=,sid=,args= | awk -v s="$SID" '$2==s && /lcnc_display.py/ {print $1}')
        [ -n "$dpid" ] && kill -TERM $dpid 2>/dev/null
        sleep 2
        kill -TERM $LPID 2>/dev/null
        for i in $(seq 50); do kill -0 $LPID 2>/dev/null || break; sleep 0.2; done
    fi
    wait $LPID 2>/dev/null
    # whatever is left of this session (only processes we started): TERM, KILL
    local pids
    pids=$(ps -e -o pid=,sid= | awk -v s="$SID" '$2==s {print $1}')
    if [ -n "$pids" ]; then
        kill -TERM $pids 2>/dev/null; sleep 1
        pids=$(ps -e -o pid=,sid= | awk -v s="$SID" '$2==s {print $1}')
        [ -n "$pids" ] && kill -KILL $pids 2>/dev/null
        sleep 0.3
        if ! ps -C rtapi_app -o stat= | grep -vq '^Z'; then
            # forced kill: remove what linuxcnc's own Cleanup would have removed
            for k in 0x48414c32 0x90280A48 0x48484c34; do ipcrm -M $k 2>/dev/null; done
            while read -r b x t x x x x x x m x; do
                [ "$b$t" = "BSHMEM" ] && ipcrm -M "$m" 2>/dev/null
            done </usr/share/linuxcnc/linuxcnc.nml
            rm -f /tmp/linuxcnc.lock
        fi
    fi
}

ATTEMPT=0
while :; do
    ATTEMPT=$((ATTEMPT + 1))
    RUN=$(mktemp -d "$WORK/run.XXXXXX")
    run_once "$RUN"
    T_END=$(date +%s.%N)
    OUT=$($PY "$HERE/lcnc_result.py" "$RUN" "$T_START" "$T_END" "$SPEED" "$ATTEMPT")
    RC=$?
    # retry only failures of the machinery (rc 3), not controller errors
    if [ $RC = 3 ] && [ $ATTEMPT -le "$RETRIES" ]; then
        echo "lcnc_run.sh: attempt $ATTEMPT failed in the machinery, retrying: $OUT" >&2
        continue
    fi
    [ $RC = 3 ] && RC=2
    echo "$OUT"
    if [ "${LCNC_KEEP:-0}" != 1 ] && [ $RC = 0 ]; then rm -rf "$RUN"; fi
    exit $RC
done
