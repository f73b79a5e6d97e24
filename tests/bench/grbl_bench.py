#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""x4grbl's figures (issue 31): on the simulated port, a real CAM program
(tests/gcode/cam/fusion360-linuxcnc.ngc, its tool changes left out)
streamed with GRBL's character counting, as a sender does.
- lines/s accepted: the program three times (about 4 000 lines) in check
  mode ($C: interpreted and planned, nothing run), from the first byte to
  the last ok;
- while it runs at its own feeds (the first RUN_S seconds): the round trip
  of '?' (one every 50 ms), the bridge's CPU time over the wall time, and
  how often the path queue ran dry ("starved", from the bridge's log).
  grbl_bench.py X4GRBL PROGRAM [RUN_S]"""
import os
import statistics
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "grbl"))
import grbl_client  # noqa: E402

MACHINE = """[X4STEP]
ARC_TOLERANCE = 0.01
JUNCTION_DEVIATION = 0.02
[TRAJ]
COORDINATES = XYZ
LINEAR_UNITS = mm
""" + "".join("""[AXIS_%s]
MIN_LIMIT = -200
MAX_LIMIT = 200
MAX_VELOCITY = 50
MAX_ACCELERATION = 500
""" % a for a in "XYZ") + "".join("""[JOINT_%d]
MOTOR = %d
SCALE = 100
""" % (j, j + 1) for j in range(3))


def cpu_seconds(pid, tid=None):
    """CPU time of a process, or of one of its threads."""
    with open("/proc/%d/task/%d/stat" % (pid, tid) if tid else "/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def main():
    x4grbl, program = sys.argv[1], sys.argv[2]
    run_s = float(sys.argv[3]) if len(sys.argv) > 3 else 30
    with open(program) as f:
        body = [l.rstrip("\n") for l in f
                if l.strip() not in ("%", "M30", "M2") and "M6" not in l and l.strip()]
    b = grbl_client.Bridge(x4grbl, machine_text=MACHINE)
    try:
        c = b.connect()
        # Intake: check mode, three times the program.
        lines = body * 3
        c.command("$C")
        t0 = time.time()
        replies = c.stream(lines, timeout=600)
        dt = time.time() - t0
        bad = [r for r in replies if r != "ok"] + ["(no reply)"] * (len(lines) - len(replies))
        print("x4grbl: %d lines accepted with character counting in %.2f s: %.0f lines/s (check mode; %d errors)"
              % (len(lines), dt, len(lines) / dt, len(bad)))
        c.command("$C")
        c.greet()
        # The run: '?' every 50 ms while lines stream.
        rtts = []
        last_q = [time.time()]

        def poll_status(cl):
            now = time.time()
            if now - last_q[0] >= 0.05:
                t = time.time()
                cl.status()
                rtts.append(time.time() - t)
                last_q[0] = time.time()

        cpu0, main0, w0 = cpu_seconds(b.proc.pid), cpu_seconds(b.proc.pid, b.proc.pid), time.time()
        pending = list(body)
        end = time.time() + run_s
        while pending and time.time() < end:
            chunk, pending = pending[:20], pending[20:]
            c.stream(chunk, timeout=run_s + 60, on_wait=poll_status)
        while time.time() < end:
            t = time.time()
            c.status()
            rtts.append(time.time() - t)
            time.sleep(0.05)
        cpu = cpu_seconds(b.proc.pid) - cpu0
        main = cpu_seconds(b.proc.pid, b.proc.pid) - main0
        wall = time.time() - w0
        c.send("\x18")
        c.greet()
        c.close()
        time.sleep(0.5)
        rtts.sort()
        p = lambda q: rtts[min(len(rtts) - 1, int(q * len(rtts)))] * 1000
        print("x4grbl: '?' round trip while streaming at the program's feeds: p50 %.2f ms, p99 %.2f ms, max %.2f ms"
              " (%d reports; goal p99 <= 5 ms)" % (p(0.5), p(0.99), rtts[-1] * 1000, len(rtts)))
        print("x4grbl: CPU %.1f %% of one core over %.0f s of streaming (goal <= 5 %%); with the simulated port's"
              " engine thread, which the module's timer is on a real port: %.1f %%" % (100 * main / wall, wall,
                                                                                     100 * cpu / wall))
        starved = [l for l in b.log_text().splitlines() if "starved" in l]
        print("x4grbl: " + (starved[-1].split("x4grbl: ")[-1] if starved else "no starved count in the log"))
    finally:
        b.stop()


if __name__ == "__main__":
    main()
