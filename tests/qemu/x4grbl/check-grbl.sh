#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Host check (run-suite.sh hook) of x4grbl.sh: the program the sender
# streamed over x4grbl's pseudo-terminal, against the edges. From QEMU's
# port trace (lpt-test.log, x4trace summary) each motor's steps, signed by
# its direction pin, must add up to round(programmed end x SCALE) of its
# axis (grbl-part.nc's last motion line, grbl-mill.ini's SCALEs; the module
# starts at 0), on every axis, despite the hold and resume mid-path; every
# line of the program got its `ok`; the MPos x4grbl reported at the end is
# that end (3 decimals, as GRBL prints it).
# Usage: check-grbl.sh OUTDIR KVER   (needs $X4TRACE)
set -euo pipefail
out=${1:?}
here=$(cd "$(dirname "$0")" && pwd)
: "${X4TRACE:?X4TRACE not set (run-suite.sh builds tests/tools/x4trace)}"
"$X4TRACE" summary "$out/lpt-test.log" --json >"$out/lpt-test.summary.json"
python3 - "$here/grbl-mill.ini" "$here/grbl-part.nc" "$out/lpt-test.summary.json" "$out/console.log" <<'PY'
import json, re, sys
ini, prog, summary, console = sys.argv[1:]
bad = 0
def check(name, ok, detail=""):
    global bad
    print(("PASS " if ok else "FAIL ") + name + ("" if ok else ": " + detail))
    bad += not ok

# The machine: joint n is the n-th letter of COORDINATES, its motor and SCALE.
section, axes, joints = None, "", {}
for line in open(ini):
    line = line.split("#")[0].strip()
    m = re.match(r"\[(\w+)\]$", line)
    if m:
        section = m.group(1)
        continue
    if "=" not in line:
        continue
    k, v = (s.strip() for s in line.split("=", 1))
    if section == "TRAJ" and k == "COORDINATES":
        axes = v
    m = re.match(r"JOINT_(\d)$", section or "")
    if m:
        joints.setdefault(int(m.group(1)), {})[k] = v
# The programmed end: the last line of absolute coordinates (G90), every axis.
end = None
lines = [l.strip() for l in open(prog) if l.strip()]
for l in lines:
    if l.startswith("G90") and all(re.search(a + r"-?[0-9.]", l) for a in axes):
        end = {a: float(re.search(a + r"(-?[0-9.]+)", l).group(1)) for a in axes}
check("program-end", end is not None, "no G90 line with every axis in " + prog)
seen = {a["axis"]: a["steps_dir_high"] - a["steps_dir_low"] for a in json.load(open(summary))["axes"]}
for j, a in enumerate(axes):
    motor, scale = int(joints[j]["MOTOR"]), float(joints[j]["SCALE"])
    want = round(end[a] * scale)
    check(f"edges-{a}", seen[motor] == want,
          f"motor {motor}: {seen[motor]} steps from the trace, want round({end[a]} x {scale:g}) = {want}")
    print(f"    {a}: motor {motor} at {seen[motor]} steps (programmed {end[a]} x {scale:g})")

text = open(console, errors="replace").read().replace("\r", "")
m = re.search(r"^X4GRBL lines (\d+) ok (\d+) error (\d+)$", text, re.M)
check("every-line-ok", bool(m) and int(m.group(1)) == len(lines) == int(m.group(2)) and m.group(3) == "0",
      m.group(0) if m else "no X4GRBL lines line")
m = re.search(r"^X4GRBL final MPos:(\S+)$", text, re.M)
mpos = [float(v) for v in m.group(1).split(",")] if m else []
check("final-mpos", len(mpos) == len(axes) and
      all(abs(mpos[j] - round(end[a] * float(joints[j]["SCALE"])) / float(joints[j]["SCALE"])) < 0.0015
          for j, a in enumerate(axes)),
      f"MPos {m.group(1) if m else None}, programmed end {end}")
check("held-mid-path", re.search(r"^X4GRBL hold MPos:", text, re.M) is not None, "no hold position")
m = re.search(r"^X4GRBL guest-seconds ([0-9.]+) ([0-9.]+)$", text, re.M)
if m:
    print(f"guest time from the bridge's start to Idle: {float(m.group(2)) - float(m.group(1)):.2f} s")
print(("FAIL" if bad else "PASS") + f": x4grbl on QEMU's port, {bad} bad")
sys.exit(1 if bad else 0)
PY
