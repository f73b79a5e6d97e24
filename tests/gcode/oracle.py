#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""The G-code interpreter against LinuxCNC's own (issue 20).

For each program of tests/gcode/programs.txt (paths inside the unpacked
linuxcnc-uspace package, or in tests/gcode/), runs LinuxCNC's rs274
(scripts/get-rs274.sh: its 9-decimal copy) and gcode_dump, and compares the
sequences of motions and dwells: every end point and arc centre within
1e-6 mm (or degree), the same planes and turns, the same dwell times. rs274 prints program coordinates in
the current length unit; they are turned into machine coordinates in mm
with the offsets it prints (SET_G5X_OFFSET, SET_G92_OFFSET,
USE_TOOL_LENGTH_OFFSET) and its USE_LENGTH_UNITS.
Programs marked "refuse" must be refused by ours with file:line:column;
the programs of probe/refusals.txt by both, on the same line.
Without rs274 the test fails: it never skips.
Usage: oracle.py GCODE_DUMP [CACHE]
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

TOL = 1e-6
here = os.path.dirname(os.path.abspath(__file__))
dump = sys.argv[1]
cache = sys.argv[2] if len(sys.argv) > 2 else os.environ.get(
    "X4_LINUXCNC_CACHE", "/var/cache/x4step/linuxcnc")
rs274 = os.path.join(cache, "rs274-9")
root = os.path.join(cache, "root")
if not os.path.isfile(os.path.join(cache, "complete")):
    print(f"FAIL: LinuxCNC's rs274 is not in {cache}: run scripts/deps.sh test as root "
          "(scripts/get-rs274.sh fetches Debian's linuxcnc-uspace)")
    sys.exit(1)
env = dict(os.environ, LD_LIBRARY_PATH=f"{root}/usr/lib:{root}/usr/lib/x86_64-linux-gnu")

CALL = re.compile(r"^\s*\d+ N\S*\s+(\w+)\((.*)\)\s*$")
PLANES = {"CANON_PLANE_XY": 0, "CANON_PLANE_XZ": 1, "CANON_PLANE_YZ": 2}
# Plane -> (first, second, normal) axis indices (LinuxCNC's ARC_FEED order).
PLANE_AXES = {0: (0, 1, 2), 1: (2, 0, 1), 2: (1, 2, 0)}


def nums(args):
    return [float(v) for v in re.split(r"[,\s]+", args.strip()) if v]


def oracle(path, tmp):
    var = os.path.join(tmp, "p.var")
    shutil.copy(os.path.join(cache, "empty.var"), var)
    r = subprocess.run([rs274, "-t", os.path.join(cache, "tool.tbl"), "-v", var, "-g", path],
                       stdin=subprocess.DEVNULL, capture_output=True, text=True, env=env, timeout=60)
    f = 1.0
    g5x = [0.0] * 6
    g92 = [0.0] * 6
    tlo = [0.0] * 6
    plane = 0
    out = []
    inch = False

    def machine(p):
        return [(p[i] * (f if i < 3 else 1.0)) + g5x[i] + g92[i] + tlo[i] for i in range(6)]

    for line in r.stdout.splitlines():
        m = CALL.match(line)
        if not m:
            continue
        name, args = m.groups()
        if name == "USE_LENGTH_UNITS":
            f = 25.4 if "INCH" in args else 1.0
            inch = inch or "INCH" in args
        elif name == "SELECT_PLANE":
            plane = PLANES[args.strip()]
        elif name in ("SET_G5X_OFFSET", "SET_G92_OFFSET", "USE_TOOL_LENGTH_OFFSET"):
            v = nums(args)
            if name == "SET_G5X_OFFSET":
                v = v[1:]
            v = [v[i] * (f if i < 3 else 1.0) for i in range(6)]
            {"SET_G5X_OFFSET": g5x, "SET_G92_OFFSET": g92, "USE_TOOL_LENGTH_OFFSET": tlo}[name][:] = v
        elif name == "DWELL":
            out.append(("DWELL", nums(args)[:1]))
        elif name in ("STRAIGHT_TRAVERSE", "STRAIGHT_FEED", "STRAIGHT_PROBE"):
            out.append((name.split("_")[1], machine(nums(args)[:6])))
        elif name == "ARC_FEED":
            v = nums(args)
            a1, a2, an = PLANE_AXES[plane]
            p = [0.0] * 6
            p[a1], p[a2], p[an] = v[0], v[1], v[5]
            p[3:6] = v[6:9]
            c1 = v[2] * f + g5x[a1] + g92[a1] + tlo[a1]
            c2 = v[3] * f + g5x[a2] + g92[a2] + tlo[a2]
            out.append(("ARC", machine(p) + [plane, c1, c2, int(v[4])]))
    return out, r, inch


def ours(path, extra):
    r = subprocess.run([dump, "-t", os.path.join(cache, "tool.tbl"), "-i", path],
                       capture_output=True, text=True, timeout=60)
    out = []
    for line in r.stdout.splitlines():
        w = line.split()
        v = [float(x) for x in w[1:]]
        if w[0] == "ARC":
            v[6] = int(v[6])
            v[9] = int(v[9])
        out.append((w[0], v))
    return out, r


def compare(name, a, b):
    if len(a) != len(b):
        n = min(len(a), len(b))
        first = next((i for i in range(n) if a[i][0] != b[i][0]), n)
        return f"{len(b)} motions, rs274 {len(a)} (first difference at motion {first + 1})"
    worst = 0.0
    for i, ((ka, va), (kb, vb)) in enumerate(zip(a, b)):
        if ka != kb:
            return f"motion {i + 1}: {kb}, rs274 {ka}"
        if ka == "ARC" and (va[6] != vb[6] or va[9] != vb[9]):
            return f"motion {i + 1}: plane/turns {vb[6]}/{vb[9]}, rs274 {va[6]}/{va[9]}"
        for j, (x, y) in enumerate(zip(va, vb)):
            d = abs(x - y)
            worst = max(worst, d)
            if d > TOL:
                what = "seconds" if ka == "DWELL" else "XYZABC"[j] if j < 6 else ("centre 1", "", "centre 2")[j - 7]
                return f"motion {i + 1} ({ka}) {what}: {y:.9f}, rs274 {x:.9f} (off by {d:.3g})"
    return worst


def main():
    fails = 0
    passed = {"mm": 0, "inch": 0}
    with tempfile.TemporaryDirectory() as tmp:
        for line in open(os.path.join(here, "programs.txt")):
            line = line.split("#", 1)[0].split()
            if not line:
                continue
            kind, rel = line[0], line[1]
            path = os.path.join(here, rel) if rel.startswith(("cam/", "probe/")) else os.path.join(root, rel)
            name = os.path.basename(rel)
            if not os.path.isfile(path):
                print(f"FAIL {name}: {path} missing")
                fails += 1
                continue
            b, rb = ours(path, [])
            if kind == "refuse":
                msg = rb.stderr.strip().splitlines()[-1] if rb.stderr.strip() else ""
                ok = rb.returncode == 1 and re.match(re.escape(path) + r":\d+:\d+: \S", msg)
                print(f"{'PASS' if ok else 'FAIL'} {name} refused: {msg or 'accepted'}")
                fails += not ok
                continue
            if rb.returncode != 0:
                print(f"FAIL {name}: ours refused it: {rb.stderr.strip()}")
                fails += 1
                continue
            a, ra, inch = oracle(path, tmp)
            units = "inch" if inch else "mm"
            res = compare(name, a, b)
            if isinstance(res, str):
                print(f"FAIL {name} ({units}): {res}")
                fails += 1
            elif not a:
                print(f"FAIL {name}: rs274 gave no motion: {ra.stdout[-300:]} {ra.stderr[-300:]}")
                fails += 1
            else:
                arcs = sum(1 for k, _ in a if k == "ARC")
                dwells = sum(1 for k, _ in a if k == "DWELL")
                print(f"PASS {name} ({units}): {len(a) - dwells} motions ({arcs} arcs), {dwells} dwells, "
                      f"worst difference {res:.2g}")
                passed[units] += 1
        refused = 0
        for n, line in enumerate(open(os.path.join(here, "probe", "refusals.txt")), 1):
            if line.startswith("#") or not line.strip():
                continue
            text = line.strip().split("|")
            prog = os.path.join(tmp, "t.ngc")
            with open(prog, "w") as f:
                f.write("\n".join(text) + "\n")
            _, rb = ours(prog, [])
            _, ra, _ = oracle(prog, tmp)
            msg = rb.stderr.strip().splitlines()[-1] if rb.stderr.strip() else ""
            at = re.match(re.escape(prog) + r":(\d+):\d+: \S", msg)
            theirs = ra.stderr.strip().splitlines()[-1] if ra.stderr.strip() else ""
            if ra.returncode == 0:
                print(f"FAIL refusals.txt:{n}: rs274 accepts it")
            elif not at or rb.returncode != 1:
                print(f"FAIL refusals.txt:{n}: ours {msg or 'accepts it'}; rs274 refuses {theirs}")
            elif text[int(at.group(1)) - 1] != theirs:
                print(f"FAIL refusals.txt:{n}: ours refuses line {at.group(1)}, rs274 the line {theirs}")
            else:
                refused += 1
                continue
            fails += 1
    print(f"{passed['mm']} mm and {passed['inch']} inch programs equal rs274's; "
          f"{refused} probe lines refused by both; {fails} failures")
    return 1 if fails else 0


sys.exit(main())
