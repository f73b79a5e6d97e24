#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# x4ctl gcode --svg on the simulated port: the planned toolpath and the
# motors' positions read during the run, top and side view, in machine
# units (the polylines' points are machine coordinates: read back here).
#   check-gcode-svg.sh X4CTL
set -u
x4ctl=$1
# shellcheck source=tests/x4ctl/check-lib.sh
. "$(dirname "$0")/check-lib.sh"
# 100 steps/mm, Y reversed, arc tolerance 0.01 mm.
cat >"$dir/m.ini" <<'INI'
[X4STEP]
OUTPUT_MODE = step-dir
ARC_TOLERANCE = 0.01
JUNCTION_DEVIATION = 0.02
[TRAJ]
COORDINATES = XYZ
LINEAR_UNITS = mm
[AXIS_X]
MIN_LIMIT = -100
MAX_LIMIT = 100
MAX_VELOCITY = 20
MAX_ACCELERATION = 200
[AXIS_Y]
MIN_LIMIT = -100
MAX_LIMIT = 100
MAX_VELOCITY = 20
MAX_ACCELERATION = 200
[AXIS_Z]
MIN_LIMIT = -100
MAX_LIMIT = 100
MAX_VELOCITY = 10
MAX_ACCELERATION = 100
[JOINT_0]
MOTOR = 1
SCALE = 100
[JOINT_1]
MOTOR = 2
SCALE = -100
[JOINT_2]
MOTOR = 3
SCALE = 100
INI
# A pocket's outline with arcs; it ends off the step grid (X 12.345 Y 6.789).
printf '%s\n' "G21 G90" "G0 X5 Y5" "G1 Z-1 F100" "G1 X20 F600" "G3 X30 Y15 I0 J10" "G1 Y25" \
	"G2 X10 Y25 I-10 J0" "G0 Z2" "G0 X12.345 Y6.789" "M2" >"$dir/part.ngc"

# check_svg FILE MODE: the plot's content (MODE run: both paths; check: planned only).
check_svg() {
	python3 - "$1" "$2" <<'PY'
import math, sys, xml.etree.ElementTree as ET
path, mode = sys.argv[1], sys.argv[2]
ns = {"s": "http://www.w3.org/2000/svg"}
root = ET.parse(path).getroot()
step, tol = 0.01, 0.01
def pts(view, cls):
    p = view.find(f".//s:polyline[@class='{cls}']", ns)
    if p is None:
        sys.exit(f"{view.get('id')}: no {cls} polyline")
    return [tuple(map(float, xy.split(","))) for xy in p.get("points").split()]
def off(q, line):  # distance from q to the polyline
    best = math.inf
    for a, b in zip(line, line[1:]):
        dx, dy = b[0] - a[0], b[1] - a[1]
        dd = dx * dx + dy * dy
        t = 0 if dd == 0 else max(0, min(1, ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / dd))
        best = min(best, math.hypot(q[0] - a[0] - t * dx, q[1] - a[1] - t * dy))
    return best
ends = {"top": (12.345, 6.789), "side": (12.345, 2)}
done_end = {"top": (12.35, 6.79), "side": (12.35, 2)}  # round(end x SCALE) / SCALE
for vid in ("top", "side"):
    view = root.find(f".//s:g[@id='{vid}']", ns)
    if view is None:
        sys.exit(f"no {vid} view")
    planned, done = pts(view, "planned"), pts(view, "done")
    if max(abs(a - b) for a, b in zip(planned[-1], ends[vid])) > 1e-9:
        sys.exit(f"{vid}: planned path ends at {planned[-1]}, not {ends[vid]}")
    if mode == "check":
        if done:
            sys.exit(f"{vid}: --check drew {len(done)} done points")
        continue
    if len(done) < 20:
        sys.exit(f"{vid}: only {len(done)} positions of the motors")
    if max(abs(a - b) for a, b in zip(done[-1], done_end[vid])) > 1e-9:
        sys.exit(f"{vid}: the motors end at {done[-1]}, not {done_end[vid]}")
    worst = max(off(q, planned) for q in done)
    if worst > tol + 2 * step:
        sys.exit(f"{vid}: a position {worst:.4f} mm off the planned path")
    print(f"{vid}: {len(planned)} planned points, {len(done)} positions, worst {worst:.4f} mm off")
PY
}

"$x4ctl" --sim gcode --svg "$dir/run.svg" --machine "$dir/m.ini" "$dir/part.ngc" </dev/null >"$dir/out" 2>&1
st=$?
tail -1 "$dir/out"
[ $st -eq 0 ]
check "a run with --svg: exit 0" $?
check_svg "$dir/run.svg" run
check "the plot: both views, the planned path to the programmed end, the motors' positions on it, their end exact" $?
"$x4ctl" gcode --check --svg "$dir/check.svg" --machine "$dir/m.ini" "$dir/part.ngc" >/dev/null 2>&1 &&
	check_svg "$dir/check.svg" check
check "--check --svg: the planned path only" $?
"$x4ctl" --sim gcode --svg "$dir/no/such/dir.svg" --machine "$dir/m.ini" "$dir/part.ngc" </dev/null >"$dir/out" 2>&1
st=$?
cat "$dir/out"
[ $st -ne 0 ] && grep -q -- "--svg $dir/no/such/dir.svg: cannot write" "$dir/out" && ! grep -q '^gcode: done' "$dir/out"
check "an unwritable --svg file fails before anything moves" $?
exit $failed
