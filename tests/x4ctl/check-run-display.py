#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""x4ctl gcode's run display on the simulated port (test-mill.ini): the
progress line through a pseudo-terminal 40 and 80 columns wide (and one
that reports no size, with COLUMNS), the keys, the progress within a long
move, hold, abort and the end line; in virtual time the end line's machine
time, a dwell on the port's clock, and the --json records (summary first,
one time base, units in the result).

    check-run-display.py X4CTL
"""
import fcntl
import json
import os
import pty
import re
import select
import signal
import struct
import subprocess
import sys
import tempfile
import termios
import time

from pycheck import HERE, MACHINE, X4CTL, check, exit_status


tmp = tempfile.mkdtemp()
# 100 comment lines (the moves' line numbers have 3 digits), a 50 s move
# (X 0 to 50 at F60), then 20 short cuts: about 17 minutes at the top speeds.
prog = os.path.join(tmp, "long.ngc")
with open(prog, "w") as f:
    f.write("(a run longer than ten minutes)\n" * 100)
    f.write("G21 G90 G94\nG1 X50 F60\n")
    for i in range(20):
        f.write(f"G1 Y{(i % 2) * 2 + 1} F2\n")
    f.write("G0 X0 Y0\nM2\n")


def env(extra):
    e = {k: v for k, v in os.environ.items() if not k.startswith("X4STEP") and k != "COLUMNS"}
    e.update({"TERM": "xterm"})
    e.update(extra)
    return e


class Run:
    """x4ctl --sim gcode on a pty of the given width (0: no size)."""

    def __init__(self, cols, extra=None):
        self.pid, self.fd = pty.fork()
        if self.pid == 0:
            os.execve(X4CTL, [X4CTL, "--sim", "gcode", "--machine", MACHINE, prog], env(extra or {}))
        if cols:
            fcntl.ioctl(self.fd, termios.TIOCSWINSZ, struct.pack("HHHH", 24, cols, 0, 0))
        self.out = b""

    def read_for(self, seconds):
        end = time.time() + seconds
        while time.time() < end:
            r, _, _ = select.select([self.fd], [], [], 0.1)
            if r:
                try:
                    data = os.read(self.fd, 65536)
                except OSError:
                    return
                if not data:
                    return
                self.out += data

    def send(self, keys):
        os.write(self.fd, keys.encode())

    def finish(self):
        self.read_for(10)
        try:
            _, st = os.waitpid(self.pid, os.WNOHANG)
            if st == 0 and not os.WIFEXITED(st):
                os.kill(self.pid, signal.SIGKILL)
                os.waitpid(self.pid, 0)
        except ChildProcessError:
            pass
        return self.out.decode(errors="replace")

    def redraws(self):
        """The progress lines as drawn: each between a carriage return and
        its erase-to-end-of-line."""
        text = self.out.decode(errors="replace")
        return [m.group(1) for m in re.finditer(r"\r([^\r\n\x1b]*)\x1b\[K", text) if m.group(1)]


def percents(lines):
    return [float(m.group(1)) for m in (re.search(r" ([0-9.]+)%", l) for l in lines) if m]


def live(cols, extra, limit):
    r = Run(cols, extra)
    r.read_for(2.5)
    running = r.redraws()
    r.send(" ")
    r.read_for(0.8)
    held = r.redraws()[len(running):]
    r.send("\x1b")
    out = r.finish()
    lines = r.redraws()
    wide = [l for l in lines if len(l) > limit]
    check(f"{cols or 'no size'} columns: every progress line fits in {limit} characters",
          len(lines) >= 5 and not wide, f"{len(lines)} lines, too wide: {wide[:3]}")
    p = percents(running)
    check(f"{cols or 'no size'} columns: the percent grows within the first (50 s) move",
          len(set(p)) >= 3 and p == sorted(p) and p[-1] < 10, f"percents: {p}")
    return running, held, out


# A pty 80 columns wide: the line number (3 digits), remaining time, keys.
running, held, out = live(80, {}, 79)
check("80 columns: line, remaining time and the keys while it runs",
      any(re.search(r"running [0-9.]+% \| line 102 \|.* [0-9]+:[0-9]{2} left \| spc hold ESC abort \+-$", l)
          for l in running), "\n".join(running[-3:]))
check("80 columns: held, the keys to resume or abort", any(l.startswith("held ") and "spc resume ESC abort" in l
                                                          for l in held), "\n".join(held[-3:]))
check("80 columns: the end line says how far and how long, and the estimate",
      re.search(r"\x1b\[Kgcode: aborted at [0-9.]+% after 0:0[0-9], estimated 20:[0-9]{2}, at X[0-9.]+ Y0 Z0 "
                r"\(mm\)\r?\n", out) is not None, out[-300:])
check("80 columns: the progress line is cleared for the end line",
      re.search(r"\r\x1b\[Kgcode: aborted", out) is not None, repr(out[-200:]))

# 40 columns: state, percent, remaining, the keys in short.
running, held, out = live(40, {}, 39)
check("40 columns: state, percent, remaining time and keys",
      any(re.fullmatch(r"running [0-9.]+% \| 20:[0-9]{2} left \| spc/ESC/\+-", l) for l in running),
      "\n".join(running[-3:]))

# A terminal that reports no size: COLUMNS.
live(0, {"COLUMNS": "50"}, 49)

# Virtual time: a dwell passes on the port's clock, the end line gives
# machine time (far more than the wall time), close to the estimate.
dwell = os.path.join(tmp, "dwell.ngc")
with open(dwell, "w") as f:
    f.write("G21 G90\nG1 X20 F120\nG4 P30\n(MSG,dwelled)\nG1 X0\nM2\n")
t0 = time.time()
r = subprocess.run([X4CTL, "--sim", "gcode", "--machine", MACHINE, dwell], env=env({"X4STEP_SIM_TIME": "virtual"}),
                   stdin=subprocess.DEVNULL, capture_output=True, text=True, timeout=60)
wall = time.time() - t0
m = re.search(r"^gcode: done in ([0-9]+):([0-9]{2}), estimated ([0-9]+):([0-9]{2}), at X0 Y0 Z0 \(mm\)$",
              r.stdout, re.M)
machine = int(m.group(1)) * 60 + int(m.group(2)) if m else -1
estimate = int(m.group(3)) * 60 + int(m.group(4)) if m else -1
check("virtual time: a 30 s dwell takes no wall time",
      r.returncode == 0 and wall < 10, f"exit {r.returncode}, {wall:.1f} s\n{r.stdout}{r.stderr}")
check("virtual time: the end line's machine time (dwell included) is the estimate's, give or take the ramps",
      estimate == 50 and estimate <= machine <= estimate + 3, r.stdout)

r = subprocess.run([X4CTL, "--sim", "gcode", "--json", "--machine", MACHINE, dwell],
                   env=env({"X4STEP_SIM_TIME": "virtual"}), stdin=subprocess.DEVNULL, capture_output=True, text=True,
                   timeout=60)
msg = [x for x in map(json.loads, r.stdout.splitlines()) if "message" in x]
check("--json: a message with its time on the same clock (after the 10 s move and the 30 s dwell)",
      len(msg) == 1 and msg[0]["message"] == "MSG: dwelled" and 40 <= msg[0].get("elapsed", -1) < 42, r.stdout[-400:])

# --json in virtual time: the summary first, progress on the port's clock,
# the result with units and times.
r = subprocess.run([X4CTL, "--sim", "gcode", "--json", "--machine", MACHINE, prog],
                   env=env({"X4STEP_SIM_TIME": "virtual"}), stdin=subprocess.DEVNULL, capture_output=True,
                   text=True, timeout=120)
recs = [json.loads(l) for l in r.stdout.splitlines()]
check("--json: the summary record first", recs and recs[0].get("file") == prog and recs[0].get("units") == "mm"
      and recs[0].get("seconds", 0) > 600, r.stdout[:300])
prog_recs = [x for x in recs if "state" in x]
el = [x["elapsed"] for x in prog_recs]
first_move = [x["percent"] for x in prog_recs if x["line"] == 102]
check("--json: progress every 0.2 s of machine time, within the long move too",
      len(prog_recs) > 3000 and el == sorted(el) and len(set(first_move)) > 100, f"{len(prog_recs)} records")
res = recs[-1] if recs else {}
check("--json: the result last, with units, elapsed and estimated seconds on the same clock",
      res.get("result") == "done" and res.get("units") == "mm" and res.get("estimated") == recs[0].get("seconds")
      and res.get("elapsed", 0) >= el[-1] and res["elapsed"] >= res["estimated"], json.dumps(res))
sys.exit(exit_status())
