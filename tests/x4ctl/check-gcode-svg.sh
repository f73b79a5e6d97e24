#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# x4ctl gcode --svg on the simulated port: the planned toolpath and the
# motors' positions read during the run, top and side view, in work
# coordinates (the paths' points are coordinates, mapped to the page by
# each view's transform: read back here), and the page around them.
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

# check_svg FILE MODE: the plot read back (MODE run: planned and done;
# check: planned only; aborted: planned, done and not done; flat: a 0.3 mm
# engraving, planned only). Each view's data group maps work coordinates
# to the page by its transform; everything is checked in those coordinates.
check_svg() {
	python3 - "$@" <<'PY'
import math, re, sys, xml.etree.ElementTree as ET
path, mode = sys.argv[1], sys.argv[2]
ns = {"s": "http://www.w3.org/2000/svg"}
S = "{http://www.w3.org/2000/svg}"
root = ET.parse(path).getroot()
step, tol = 0.01, 0.01
bad = []
def fail(msg):
    bad.append(msg)
def paths(view, cls):  # the subpaths of the path of this class: lists of (h, v)
    p = view.find(f".//s:path[@class='{cls}']", ns)
    if p is None:
        return None, []
    subs = []
    for cmd, x, y in re.findall(r"([ML])\s*(-?[0-9.e+-]+),(-?[0-9.e+-]+)", p.get("d")):
        if cmd == "M":
            subs.append([])
        subs[-1].append((float(x), float(y)))
    return p, subs
def off(q, line):  # distance from q to the polyline
    best = math.inf
    for a, b in zip(line, line[1:]):
        dx, dy = b[0] - a[0], b[1] - a[1]
        dd = dx * dx + dy * dy
        t = 0 if dd == 0 else max(0, min(1, ((q[0] - a[0]) * dx + (q[1] - a[1]) * dy) / dd))
        best = min(best, math.hypot(q[0] - a[0] - t * dx, q[1] - a[1] - t * dy))
    return best
def round_125(v):  # 1, 2 or 5 times a power of ten
    e = math.floor(math.log10(v))
    return any(abs(v - m * 10 ** e) < 1e-9 * v for m in (1, 2, 5))

ends = {"top": (12.345, 6.789), "side": (12.345, 2)}
done_end = {"top": (12.35, 6.79), "side": (12.35, 2)}  # round(end x SCALE) / SCALE
if mode == "flat":
    ends = {"top": (30, 0), "side": (30, 1)}
worst_all = 0
for vid in ("top", "side"):
    view = root.find(f".//s:g[@id='{vid}']", ns)
    if view is None:
        sys.exit(f"no {vid} view")
    data = view.find(".//s:g[@class='data']", ns)
    a, b, c, d, e, f = map(float, re.fullmatch(r"matrix\((.*)\)", data.get("transform")).group(1).split())
    page = lambda q: (a * q[0] + e, d * q[1] + f)
    fr = view.find("s:rect[@class='frame']", ns)
    x0, y0 = float(fr.get("x")), float(fr.get("y"))
    x1, y1 = x0 + float(fr.get("width")), y0 + float(fr.get("height"))
    # Cuts solid, rapids dashed.
    cut, cuts = paths(view, "cut")
    rapid, rapids = paths(view, "rapid")
    if cut is None or rapid is None:
        fail(f"{vid}: no cut or no rapid path"); continue
    if cut.get("stroke-dasharray") or not rapid.get("stroke-dasharray"):
        fail(f"{vid}: cuts dashed ({cut.get('stroke-dasharray')}) or rapids solid")
    planned = [q for sub in cuts + rapids for q in sub]
    if mode != "flat" and rapids[-1][-1] != ends[vid]:
        fail(f"{vid}: the last rapid ends at {rapids[-1][-1]}, not at the programmed end {ends[vid]}")
    # Framed on the program: every planned point within the frame; work zero marked.
    outside = [q for q in planned if not (x0 - 1e-6 <= page(q)[0] <= x1 + 1e-6 and y0 - 1e-6 <= page(q)[1] <= y1 + 1e-6)]
    if outside:
        fail(f"{vid}: {len(outside)} points outside the frame, e.g. {outside[0]}")
    # ... and tight: no more than a grid step and the margin beyond the
    # program and work zero (not the machine's envelope, not where it stood).
    for (lo, hi), (plo, phi), axis in (((x0, x1), (e + a * min(0, *[q[0] for q in planned]), e + a * max(0, *[q[0] for q in planned])), 0),
                                        ((y1, y0), (f + d * min(0, *[q[1] for q in planned]), f + d * max(0, *[q[1] for q in planned])), 1)):
        labels = sorted(float(t.get("data-value")) for t in view.iter(S + "text")
                        if t.get("class") == "label" and t.get("data-axis") == {"top": "XY", "side": "XZ"}[vid][axis])
        grid = (labels[1] - labels[0]) * abs(a if axis == 0 else d) if len(labels) > 1 else 0
        slack = grid + 0.05 * abs(hi - lo)
        if abs(plo - lo) > slack or abs(hi - phi) > slack:
            fail(f"{vid}: the frame {lo:.0f}..{hi:.0f} px is loose around the program's {plo:.0f}..{phi:.0f} px")
    o = view.find("s:g[@class='origin']", ns)
    if o is None or max(abs(float(o.get("data-x")) - e), abs(float(o.get("data-y")) - f)) > 1e-6:
        fail(f"{vid}: work zero is not marked at (0, 0)")
    # Gridlines labelled with round numbers, a 1-2-5 step apart.
    for axis in {"top": "XY", "side": "XZ"}[vid]:
        labels = [t for t in view.iter(S + "text") if t.get("class") == "label" and t.get("data-axis") == axis]
        vals = [float(t.text) for t in labels]
        steps = {round(q - p, 9) for p, q in zip(vals, vals[1:])}
        if len(vals) < 3 or len(steps) > 2 or not all(s > 0 and round_125(s) for s in steps):
            fail(f"{vid}: {axis} labels {[t.text for t in labels]} are not a 1-2-5 step apart")
        elif any(len(t.text.split(".")[1]) > max(0, -math.floor(math.log10(min(steps)))) if "." in t.text else False
                 for t in labels):
            fail(f"{vid}: {axis} labels with more decimals than their step: {[t.text for t in labels]}")
    if vid == "side":
        zpx = abs(d) * (max(q[1] for q in planned) - min(q[1] for q in planned))
        if zpx < 60:
            fail(f"side: Z spans {zpx:.1f} px only")
        if mode == "flat" and not (abs(d) > 2 * abs(a) and "Z scale" in "".join(view.itertext())):
            fail(f"side: a 0.3 mm engraving on X's scale ({a} px/mm, Z {abs(d)} px/mm)")
    done, dones = paths(view, "done")
    notdone, notdones = paths(view, "not-done-rapid")
    if mode in ("check", "flat"):
        if done is not None:
            fail(f"{vid}: --check drew done positions")
        continue
    if done is None or cut.get("stroke") == done.get("stroke"):
        fail(f"{vid}: no done path, or in the planned cuts' colour"); continue
    pos = [q for sub in dones + paths(view, "done-rapid")[1] for q in sub]
    if len(pos) < 20:
        fail(f"{vid}: only {len(pos)} positions of the motors")
    worst = max(min(off(q, s) for s in cuts + rapids if len(s) > 1) for q in pos)
    worst_all = max(worst_all, worst)
    if worst > tol + 2 * step:
        fail(f"{vid}: a position {worst:.4f} mm off the planned path")
    if mode == "run":
        if paths(view, "done-rapid")[1][-1][-1] != done_end[vid]:
            fail(f"{vid}: the motors end at {paths(view, 'done-rapid')[1][-1][-1]}, not {done_end[vid]}")
        if notdone is not None or paths(view, "not-done")[0] is not None:
            fail(f"{vid}: a run to its end drew planned-but-not-done segments")
    else:  # aborted: what was not done, in its own colour, from the motors' stop to the end
        nd, nds = paths(view, "not-done")
        rest = [q for sub in nds + notdones for q in sub]
        cols = {cut.get("stroke"), done.get("stroke")}
        if not rest or any(p.get("stroke") in cols for p in (nd, notdone) if p is not None):
            fail(f"{vid}: no planned-but-not-done path in a colour of its own")
        elif ends[vid] not in rest:
            fail(f"{vid}: the not-done path does not reach the programmed end")
    print(f"{vid}: {len(planned)} planned points, {len(pos)} positions, worst {worst:.4f} off")
legend = root.find(".//s:g[@id='legend']", ns)
kinds = {} if legend is None else {g.get("data-kind"): g for g in legend.findall("s:g[@class='entry']", ns)}
want = {"cut", "rapid", "origin"} | ({"done", "not-done"} if mode in ("run", "aborted") else set())
if not want <= set(kinds) or any(kinds[k].find("s:line[@class='swatch']", ns) is None for k in want - {"origin"}):
    fail(f"the legend lacks swatches: has {sorted(kinds)}, wants {sorted(want)}")
elif kinds["rapid"].find("s:line", ns).get("stroke-dasharray") is None:
    fail("the legend's rapid swatch is solid")
dev = root.find(".//s:text[@id='deviation']", ns)
if mode in ("run", "aborted"):
    if dev is None:
        fail("no figure of the largest deviation")
    elif not (worst_all - 1e-6 <= float(dev.get("data-value")) <= tol + 2 * step):
        fail(f"the largest deviation says {dev.get('data-value')}, the positions are up to {worst_all:.5f} off")
elif dev is not None:
    fail("a deviation without a run")
for m in bad:
    print("FAIL " + m)
sys.exit(1 if bad else 0)
PY
}

"$x4ctl" --sim gcode --svg "$dir/run.svg" --machine "$dir/m.ini" "$dir/part.ngc" </dev/null >"$dir/out" 2>&1
st=$?
tail -1 "$dir/out"
[ $st -eq 0 ]
check "a run with --svg: exit 0" $?
check_svg "$dir/run.svg" run
check "the plot: cuts solid, rapids dashed, framed on the program, work zero marked, round grid labels, a legend; the motors' positions on the path, their end exact, the largest deviation" $?
"$x4ctl" gcode --check --svg "$dir/check.svg" --machine "$dir/m.ini" "$dir/part.ngc" >/dev/null 2>&1 &&
	check_svg "$dir/check.svg" check
check "--check --svg: the planned path only" $?
# Aborted after 1.5 s of a slower version: the rest stands out.
sed 's/F600/F30/' "$dir/part.ngc" >"$dir/slow.ngc"
X4STEP_SIM_TIME=real timeout --preserve-status -s INT 1.5 "$x4ctl" --sim gcode --svg "$dir/aborted.svg" --machine "$dir/m.ini" "$dir/slow.ngc" </dev/null >"$dir/out" 2>&1
st=$?
tail -1 "$dir/out"
[ $st -eq 1 ] && grep -q '^gcode: aborted at [1-9][0-9.]*% after' "$dir/out" && check_svg "$dir/aborted.svg" aborted
check "an aborted run: planned but not done in a colour of its own, from where the motors stopped to the end" $?
# A 0.3 mm engraving: Z on its own scale.
printf '%s\n' "G21 G90" "G0 X0 Y0 Z1" "G1 Z-0.3 F100" "G1 X30 F600" "G0 Z1" "M2" >"$dir/flat.ngc"
"$x4ctl" gcode --check --svg "$dir/flat.svg" --machine "$dir/m.ini" "$dir/flat.ngc" >/dev/null 2>&1 &&
	check_svg "$dir/flat.svg" flat
check "a flat part: the side view's Z on its own scale, said so" $?
"$x4ctl" --sim gcode --svg "$dir/no/such/dir.svg" --machine "$dir/m.ini" "$dir/part.ngc" </dev/null >"$dir/out" 2>&1
st=$?
cat "$dir/out"
[ $st -ne 0 ] && grep -q -- "--svg $dir/no/such/dir.svg: cannot write" "$dir/out" && ! grep -q '^gcode: done' "$dir/out"
check "an unwritable --svg file fails before anything moves" $?
exit $failed
