#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-2.0
"""The GRBL 1.1 protocol of x4grbl on the simulated port (issue 31): every
command and real-time byte a sender uses, character counting, hold and
resume, jog and its cancel, soft reset mid-motion, alarms, settings and
their persistence, a second client, malformed input, a client that goes
away mid-program, the pseudo-terminal.
  check-grbl.py X4GRBL [TEST...]  (TEST: a test's name, to run only those)"""
import os
import re
import shutil
import subprocess
import time

from grbl_client import Bridge, Client, check, exit_status, field, mpos, state_of

X4GRBL = os.sys.argv[1]
HOME = [3.0, 1.0, -1.0]  # test-mill.ini's HOME of X Y Z


def near(a, b, eps=0.0005):
    return all(abs(x - y) <= eps for x, y in zip(a, b))


def homed(b):
    c = b.connect()
    c.command("$H", timeout=60)
    c.wait_state({"Idle"})
    return c


def test_connect_and_queries(b):
    c = b.connect(greeting=False)
    first = c.greet()
    check("welcome line, then the homing lock's hint (axes with switches not homed)",
          first == ["Grbl 1.1h ['$' for help]", "[MSG:'$H'|'$X' to unlock]"], first)
    s = c.status()
    check("status: Alarm, MPos, FS, WCO in the first report", state_of(s) == "Alarm" and field(s, "MPos") and
          field(s, "FS") == "0,0" and field(s, "WCO") == "0.000,0.000,0.000", s)
    s2 = c.status()
    check("Ov in the second report after a reset", field(s2, "Ov") == "100,100,100" and not field(s2, "WCO"), s2)
    r = c.command("G0 X1")
    check("G-code locked in Alarm: error:9", r == ["error:9"], r)
    r = c.command("$")
    check("$: the help line", r[0].startswith("[HLP:$$ $# $G $I $N") and r[-1] == "ok", r)
    r = c.command("$$")
    numbers = [int(re.match(r"\$(\d+)=", l).group(1)) for l in r[:-1]]
    want = [0, 1, 2, 3, 4, 5, 6, 10, 11, 12, 13, 20, 21, 22, 23, 24, 25, 26, 27, 30, 31, 32,
            100, 101, 102, 110, 111, 112, 120, 121, 122, 130, 131, 132]
    check("$$: GRBL's settings in order, then ok", numbers == want and r[-1] == "ok", r)
    check("$$: steps/mm, mm/min, mm/s^2, travel from the machine file",
          "$100=160.000" in r and "$101=200.000" in r and "$110=1200.000" in r and "$122=100.000" in r and
          "$130=105.000" in r, r)
    r = c.command("$I")
    check("$I: VER and OPT", r[0].startswith("[VER:1.1h.") and r[1].startswith("[OPT:") and r[2] == "ok", r)
    r = c.command("$G")
    check("$G: the modes", r == ["[GC:G80 G54 G17 G21 G90 G94 M5 M9 T0 F0 S0]", "ok"], r)
    r = c.command("$#")
    check("$#: offsets, G28, G30, G92, TLO, PRB", r[0] == "[G54:0.000,0.000,0.000]" and
          r[6].startswith("[G28:") and r[9] == "[TLO:0.000]" and r[10].startswith("[PRB:") and r[-1] == "ok", r)
    r = c.command("$N")
    check("$N: two startup blocks", r == ["$N0=", "$N1=", "ok"], r)
    r = c.command("$X")
    check("$X unlocks", r == ["[MSG:Caution: Unlocked]", "ok"] and state_of(c.status()) == "Idle", r)
    r = c.command("$Q")
    check("an unknown $ command: error:3", r == ["error:3"], r)
    r = c.command("")
    check("an empty line: ok", r == ["ok"], r)
    c.close()


def test_home_and_stream(b):
    c = b.connect()
    r = c.command("$H", timeout=60)
    s = c.wait_state({"Idle"})
    check("$H homes by the machine file: ok, Idle at HOME", r == ["ok"] and near(mpos(s), HOME), (r, s))
    program = ["G21 G90 G94", "G1 X10 Y5 F600", "G2 X20 Y5 I5 J0", "G1 Y15", "G3 X10 Y15 R5",
               "G0 Z-5", "G1 X12.5 Y7.25 Z-10 F300", "M2"]
    replies = c.stream(program)
    s = c.wait_state({"Idle"})
    check("a program streamed with character counting: one ok per line",
          replies == ["ok"] * len(program), replies)
    check("it ends where it ends: X12.5 Y7.25 Z-10", near(mpos(s), [12.5, 7.25, -10]), s)
    check("[MSG:Pgm End] for M2", "[MSG:Pgm End]" in c.lines, c.lines)
    c.lines.clear()
    c.close()


def test_buffer_and_status(b):
    c = homed(b)
    c.command("$10=3")
    # Many short moves: the planner fills, lines wait for room, '?' is still answered.
    program = ["G91 G1 F1200"] + ["X0.5" if i % 2 == 0 else "X-0.5" for i in range(400)] + ["G90"]
    seen = {"full": False}

    def on_ack(cl, _):
        if seen["full"] or len(cl.inflight) < 5:
            return
        s = cl.status()
        if field(s, "Bf") and state_of(s) == "Run":
            seen["full"] = s

    start = mpos(c.status())
    replies = c.stream(program, on_ack=on_ack)
    s = c.wait_state({"Idle"})
    check("'?' answered while lines wait for the planner, with Bf:blocks,bytes", bool(seen["full"]), seen)
    check("400 moves back and forth: every line ok, back at the start exactly",
          replies == ["ok"] * len(program) and near(mpos(s), start), (replies[-3:], s))
    c.command("$10=1")
    c.close()


def test_hold_resume(b):
    c = homed(b)
    c.command("G90 G1 X60 F600")
    c.wait_state({"Run"})
    time.sleep(0.5)
    c.send("!")
    s = c.wait_state({"Hold:0"}, timeout=10)
    p1 = mpos(s)
    time.sleep(0.5)
    p2 = mpos(c.status())
    check("! holds along the path: Hold:0, standing", p1 == p2 and 3 < p1[0] < 60, (p1, p2))
    c.send("~")
    s = c.wait_state({"Idle"})
    check("~ resumes: ends at X60 exactly", near(mpos(s), [60, HOME[1], HOME[2]]), s)
    c.close()


def test_hold_never_forgotten(b):
    """GRBL's protocol.c: a feed hold in Idle is Hold:0 at once, and every
    hold lasts until '~', whatever arrives or ends meanwhile."""
    c = homed(b)
    at = mpos(c.status())
    c.send("!")
    s = c.status()
    r = c.command("G90 G0 X20")
    time.sleep(0.5)
    s2 = c.status()
    check("'!' in Idle: Hold:0; a line sent then is planned (ok) but does not move",
          state_of(s) == "Hold:0" and r == ["ok"] and state_of(s2) == "Hold:0" and mpos(s2) == at, (s, r, s2))
    c.send("~")
    s = c.wait_state({"Idle"})
    check("... '~' runs it: X20", near(mpos(s)[:1], [20]), s)
    # The line and the hold in one write: the hold is not lost to the line.
    c.send("G90 G0 X30\n!")
    c.next_line()
    time.sleep(0.5)
    s = c.status()
    check("a line and '!' in one write: Hold:0, not moved", state_of(s) == "Hold:0" and near(mpos(s)[:1], [20]), s)
    c.send("~")
    c.wait_state({"Idle"})
    # A hold during a dwell that ends the backlog: the next line waits for '~'.
    r = c.command("G4 P0.6")
    time.sleep(0.2)
    c.send("!")
    time.sleep(0.8)
    s = c.status()
    r2 = c.command("G90 G0 X40")
    time.sleep(0.5)
    s2 = c.status()
    check("'!' during a dwell: still Hold after the dwell; the next line does not move",
          state_of(s) == "Hold:0" and r2 == ["ok"] and state_of(s2) == "Hold:0" and near(mpos(s2)[:1], [30]),
          (s, r2, s2))
    c.send("~")
    s = c.wait_state({"Idle"})
    check("... '~' runs it: X40", near(mpos(s)[:1], [40]), s)
    # M0 is a hold too: the lines after it wait for '~'.
    r = c.stream(["M0", "G90 G0 X50"])
    time.sleep(0.5)
    s = c.status()
    check("M0: Hold:0, the move after it waits", r == ["ok", "ok"] and state_of(s) == "Hold:0" and
          near(mpos(s)[:1], [40]), (r, s))
    c.send("~")
    s = c.wait_state({"Idle"})
    check("... '~' runs it: X50", near(mpos(s)[:1], [50]), s)
    c.close()


def test_after_program_end(b):
    """M2 planned while the program's last moves still run: the next
    program starts from where this one ends, not from where the machine
    stood when M2 was planned (G0 X5 ended at X35)."""
    c = homed(b)
    r = c.stream(["G90 G1 X30 F600", "M2", "G90 G0 X5"])
    s = c.wait_state({"Idle"})
    check("M2 while moving, then G0 X5: ends at X5", r == ["ok"] * 3 and near(mpos(s)[:1], [5]), (r, s))
    c.close()


def test_jog(b):
    c = homed(b)
    at = mpos(c.status())
    r = c.command("$J=G91 X5 F600")
    c.wait_state({"Jog"}, timeout=5)
    s = c.wait_state({"Idle"})
    check("$J=G91 X5 F600 jogs 5 mm", r == ["ok"] and near(mpos(s), [at[0] + 5, at[1], at[2]]), (r, s))
    r = c.command("$J=G53 X500 F600")
    check("a jog beyond the soft limits: error:15", r == ["error:15"], r)
    r = c.command("$J=G91 X5")
    check("a jog without F: error:22", r == ["error:22"], r)
    r = c.command("$J=G91 G1 X5 F100")
    check("a jog with a motion word: error:16", r == ["error:16"], r)
    r = c.command("$J=G90 X90 F300")
    c.wait_state({"Jog"}, timeout=5)
    time.sleep(0.3)
    c.send("\x85")
    s = c.wait_state({"Idle"}, timeout=10)
    x = mpos(s)[0]
    check("0x85 cancels the jog: it stops short of X90", r == ["ok"] and x < 89, s)
    r = c.command("G90 G0 X20")
    s = c.wait_state({"Idle"})
    check("after the cancel the program goes on from where it stood: X20 exactly",
          r == ["ok"] and near(mpos(s)[:1], [20]), (r, s))
    c.close()


def test_soft_reset(b):
    c = homed(b)
    c.command("G90 G1 X80 F900")
    c.wait_state({"Run"})
    time.sleep(0.4)
    c.send("\x18")
    line = c.next_line(timeout=10)
    s = c.wait_state({"Idle"}, timeout=10)
    p1 = mpos(s)
    time.sleep(0.3)
    check("0x18 mid-motion: welcome, Idle, stopped short of X80, no alarm (no step lost)",
          line == "Grbl 1.1h ['$' for help]" and p1 == mpos(c.status()) and p1[0] < 79.9, (line, s))
    r = c.command("G90 G0 X30")
    s = c.wait_state({"Idle"})
    check("after the reset a move ends exactly: X30", r == ["ok"] and near(mpos(s)[:1], [30]), (r, s))
    c.close()


def test_alarms(b):
    c = homed(b)
    r = c.stream(["G90 G0 X10", "G0 X200", "G0 X0"])
    check("a soft limit in a stream: ALARM:2, [MSG:Reset to continue]",
          "ALARM:2" in r and "[MSG:Reset to continue]" in c.next_line(), (r, c.lines))
    c.lines.clear()
    time.sleep(0.2)
    check("the alarm holds the rest of the stream", c.lines == [] and state_of(c.status()) == "Alarm")
    c.send("\x18")
    lines = [c.next_line(), c.next_line()]
    check("reset: welcome, still Alarm until $X", lines[0].startswith("Grbl") and state_of(c.status()) == "Alarm",
          lines)
    r = c.command("$X")
    s = c.wait_state({"Idle"})
    check("$X: Idle (GRBL halts the motion before the alarm too)", "ok" in r and state_of(s) == "Idle", (r, s))
    c.inflight.clear()
    c.close()


def test_settings(b):
    c = homed(b)
    r = c.command("$110=900")
    check("$110=900: ok", r == ["ok"], r)
    with open(b.machine) as f:
        text = f.read()
    check("$110 is the machine file's [AXIS_X] MAX_VELOCITY = 15 (mm/s)",
          re.search(r"\[AXIS_X\][^\[]*MAX_VELOCITY = 15\n", text) is not None, text)
    check("$$ shows it", "$110=900.000" in c.command("$$"))
    r = c.command("$100=-5")
    check("$100=-5: error:4 (negative)", r == ["error:4"], r)
    r = c.command("$0=2")
    check("$0=2: error:6 (pulse under 3 us)", r == ["error:6"], r)
    r = c.command("$32=1")
    check("$32=1: error:17 (laser mode needs PWM)", r[-1] == "error:17", r)
    r = c.command("$999=1")
    check("$999: error:3", r == ["error:3"], r)
    r = c.command("$100=2000")
    check("$100=2000 (20 mm/s x 2000 = 40000 steps/s ok)", r == ["ok"], r)
    r = c.command("$110=60000")
    check("a rate beyond the port (1000 mm/s x 2000 steps/mm): error:12, the file unchanged",
          r[-1] == "error:12" and "MAX_VELOCITY = 15\n" in open(b.machine).read(), r)
    c.command("$100=160")
    r = c.command("$13=1")
    s = c.status()
    check("$13=1 reports inches: 4 decimals", r == ["ok"] and re.match(r"-?\d+\.\d{4}$", field(s, "MPos").split(",")[0]),
          s)
    c.command("$13=0")
    r = c.command("$N0=G21 G90")
    check("$N0=G21 G90 kept (without blanks, as GRBL keeps it)", r == ["ok"] and "$N0=G21G90" in c.command("$N"), r)
    r = c.command("$N1=G1 X")
    check("$N1 with a bad block: its error, not kept", r[-1].startswith("error:") and "$N1=" in c.command("$N"), r)
    c.close()
    c = b.connect(greeting=False)
    lines = c.greet()
    check("on the next connection the startup block runs: >G21G90:ok", ">G21G90:ok" in lines, lines)
    check("$110 and $N0 persist", "$110=900.000" in c.command("$$"))
    c.command("$N0=")
    c.command("$110=1200")
    c.close()


def test_offsets(b):
    c = homed(b)
    r = c.command("G10 L20 P1 X0 Y0")
    s = c.status()
    check("G10 L20: ok, WCO at once", r == ["ok"] and field(s, "WCO") == "3.000,1.000,0.000", s)
    with open(os.path.join(b.dir, "mill.var")) as f:
        var = f.read()
    check("kept in the parameter file (5221 G54 X)", "5221\t3.000000" in var, var)
    # Another tool (x4ctl touch-off) changes the file: the next line sees it.
    with open(os.path.join(b.dir, "mill.var"), "w") as f:
        f.write(var.replace("5221\t3.000000", "5221\t4.000000"))
    c.command("G90")
    r = c.command("$#")
    check("an offset another tool wrote is what $# shows", r[0] == "[G54:4.000,1.000,0.000]", r)
    c.command("G10 L2 P1 X0 Y0 Z0")
    c.close()


def test_check_mode_and_overrides(b):
    c = homed(b)
    at = mpos(c.status())
    r = c.command("$C")
    r2 = c.command("G0 X50")
    s = c.status()
    check("$C: Enabled, lines checked, nothing moves", r == ["[MSG:Enabled]", "ok"] and r2 == ["ok"] and
          state_of(s) == "Check" and mpos(s) == at, (r, r2, s))
    r = c.command("G5 X1")
    check("check mode reports errors: G5 error:20 with x4step's message",
          r[-1] == "error:20" and r[0].startswith("[MSG:"), r)
    r = c.command("$C")
    check("$C again: Disabled, then a reset", r[:2] == ["[MSG:Disabled]", "ok"] and c.next_line().startswith("Grbl"),
          r)
    c.send("\x91\x91\x93")
    c.status()
    ov = None
    for _ in range(30):
        ov = field(c.status(), "Ov")
        if ov:
            break
    check("feed override +10 +10 +1: Ov:121", ov == "121,100,100", ov)
    c.send("\x90\x96")
    for _ in range(30):
        ov = field(c.status(), "Ov")
        if ov:
            break
    check("0x90 resets the feed, 0x96 rapids 50 %", ov == "100,50,100", ov)
    c.send("\x95")
    # Coolant toggles: A:F (flood), A:FM with mist, with the Ov field.
    c.send("\xa0")
    acc = None
    for _ in range(30):
        s = c.status()
        if field(s, "Ov"):
            acc = field(s, "A")
            break
    check("0xA0 toggles flood: A:F", acc == "F", s)
    c.send("\xa1")
    for _ in range(30):
        s = c.status()
        if field(s, "Ov"):
            acc = field(s, "A")
            break
    check("0xA1 toggles mist: A:FM", acc == "FM", s)
    c.send("\xa0\xa1")
    r = c.command("$SLP")
    s = c.status()
    check("$SLP: [MSG:Sleeping], state Sleep, G-code locked", r == ["[MSG:Sleeping]", "ok"] and
          state_of(s) == "Sleep" and c.command("G0 X1") == ["error:9"], (r, s))
    c.send("\x18")
    c.greet()
    check("a reset wakes it: Idle", state_of(c.status()) == "Idle")
    c.command("$10=3")
    r = c.command("$RST=$")
    lines = c.greet()
    r2 = c.command("$$")
    check("$RST=$: [MSG:Restoring defaults], a reset, x4grbl's own settings back to GRBL's ($10=1)",
          r == ["[MSG:Restoring defaults]", "ok"] and lines[0].startswith("Grbl") and "$10=1" in r2, (r, lines))
    c.close()


def test_second_client_and_garbage(b):
    c = homed(b)
    d = b.connect(greeting=False)
    line = d.next_line()
    check("a second client: a refusal line, then closed", line.startswith("[MSG:x4grbl: another sender"), line)
    try:
        d.next_line(2)
        closed = False
    except EOFError:
        closed = True
    check("... and the connection closed", closed)
    check("the first client is undisturbed", state_of(c.status()) == "Idle")
    at = mpos(c.status())
    # Every byte but the line ends and the reset (0x18, which answers with the welcome).
    c.send(bytes(b for b in range(1, 256) if b not in (10, 13, 0x18)))
    r = c.command("")
    check("binary garbage: one error (x4step's message with it), the machine still",
          len(r) == 2 and r[0].startswith("[MSG:") and r[1].startswith("error:") and mpos(c.status()) == at, r)
    c.send("G" + "1" * 10000 + "\n")
    r = c.next_line()
    time.sleep(0.2)
    c.pump(0.2)
    check("a 10000-byte line: error:11 once", r == "error:11" and not c.lines, (r, c.lines))
    c.send("G0 X40")  # no newline: never executed
    c.close()
    time.sleep(0.3)
    c = b.connect()
    s = c.status()
    check("a line without newline before a disconnect does not run", mpos(s) == at, s)
    c.close()


def test_disconnect_mid_program(b):
    c = homed(b)
    c.stream(["G90 G1 X90 F600"])
    c.wait_state({"Run"})
    time.sleep(0.3)
    c.close()
    time.sleep(1.5)
    c = b.connect()
    s1 = c.status()
    time.sleep(0.5)
    s2 = c.status()
    check("a client gone mid-program: the machine held and flushed (standing short of X90)",
          state_of(s2) == "Idle" and mpos(s1) == mpos(s2) and mpos(s2)[0] < 80, (s1, s2))
    c.close()


def test_probe(b):
    c = homed(b)
    # Z: 0 mm is motor step 899 (test-mill.sim), the probe trips at step -2000: Z -7.2475.
    r = c.command("G21 G90 G38.2 Z-20 F100")
    s = c.wait_state({"Idle"})
    check("G38.2: [PRB:] at the trip, exact to the step (Z -7.2475: -7.247 to 3 decimals), then ok",
          r == ["[PRB:3.000,1.000,-7.247:1]", "ok"], r)
    z = mpos(s)[2]
    check("... the machine braked just past it", -7.35 < z <= -7.2475, s)
    r = c.command("G90 G53 G0 Z-5")
    s = c.wait_state({"Idle"})
    check("the next move ends where it is programmed: Z-5", r == ["ok"] and near(mpos(s)[2:], [-5]), (r, s))
    r = c.command("$#")
    check("$# keeps the probe", "[PRB:3.000,1.000,-7.247:1]" in r, r)
    c.command("G0 Z-1")
    r = c.command("G38.2 Z-5 F100")
    check("G38.2 without contact: [PRB:...:0], ALARM:5, then ok",
          r[0] == "[PRB:3.000,1.000,-5.000:0]" and "ALARM:5" in r and r[-1] == "ok", r)
    r = c.command("G0 Z-2")
    check("... then Alarm: G-code locked (error:9)", r == ["error:9"], r)
    c.command("$X")
    c.command("G0 Z-10")
    c.wait_state({"Idle"})
    r = c.command("G38.2 Z-12 F100")
    check("G38.2 with the probe already touching: ALARM:4", "ALARM:4" in r and r[-1] == "ok", r)
    c.command("$X")
    r = c.command("G38.4 Z-1 F100")
    c.wait_state({"Idle"})
    check("G38.4 stops where the probe lets go (Z -7.245)", r[0] == "[PRB:3.000,1.000,-7.245:1]" and r[-1] == "ok", r)
    c.command("G0 Z-1")
    c.close()


def test_pty(x4grbl):
    b = Bridge(x4grbl, link=True)
    try:
        fd = os.open(b.link, os.O_RDWR | os.O_NOCTTY)
        c = Client(fd=fd)
        line = c.greet()
        check("the pseudo-terminal: welcome on open", line[0] == "Grbl 1.1h ['$' for help]", line)
        s = c.status()
        check("the pseudo-terminal: status", state_of(s) == "Alarm", s)
        try:
            os.close(os.open(b.link, os.O_RDWR | os.O_NOCTTY))
            busy = False
        except OSError as e:
            busy = e.errno == 16
        check("a second open of the pseudo-terminal: device busy", busy or os.geteuid() == 0)
        c.close()
    finally:
        b.stop()


def test_status_flood(b):
    """8 MB of '?' from a client that reads nothing: GRBL answers a burst
    of '?' with one report (a flag, protocol.c); x4grbl must not queue
    a report a byte, which grew it by hundreds of MB."""
    def peak_kb():
        with open("/proc/%d/status" % b.proc.pid) as f:
            return int(next(l for l in f if l.startswith("VmHWM")).split()[1])
    c = b.connect()
    try:
        c.send(b"?" * (8 << 20))
    except OSError:
        pass  # dropped for not reading: fine
    c.close()
    time.sleep(0.5)
    c = b.connect()
    s = c.status()
    check("8 MB of '?' unread: x4grbl stays small (peak RSS under 64 MB) and serves the next client",
          peak_kb() < 64 * 1024 and state_of(s), (peak_kb(), s))
    c.close()


def test_settings_coordinates_with_blanks(x4grbl):
    """COORDINATES = X Y Z is as good a machine file as XYZ (the reader
    skips blanks): $101 is Y's joint, JOINT_1, not JOINT_2 (Z's)."""
    b = Bridge(x4grbl, replace=[("COORDINATES = XYZ", "COORDINATES = X Y Z")])
    try:
        c = b.connect()
        r = c.command("$101=250")
        with open(b.machine) as f:
            text = f.read()
        y = re.search(r"\[JOINT_1\][^\[]*SCALE = (\S+)", text).group(1)
        z = re.search(r"\[JOINT_2\][^\[]*SCALE = (\S+)", text).group(1)
        check("COORDINATES = X Y Z: $101=250 sets Y's SCALE (-250, its sign kept), Z's stays 400",
              r == ["ok"] and y == "-250" and z == "400", (r, y, z))
        c.close()
    finally:
        b.stop()


def test_port_opens_later(x4grbl):
    """A port that could not be opened for one client (x4ctl had it, say)
    is tried again for the next; once open, the machine is no longer
    locked for it."""
    sim = os.path.join(os.environ.get("TMPDIR", "/tmp"), "x4grbl-test-%d.sim" % os.getpid())
    if os.path.exists(sim):
        os.unlink(sim)
    b = Bridge(x4grbl, sim_machine=sim)
    try:
        c = b.connect(greeting=False)
        lines = c.greet()
        s = c.status()
        check("a port that cannot be opened: a [MSG:] line, Alarm", state_of(s) == "Alarm" and
              any(l.startswith("[MSG:x4grbl:") for l in lines), (lines, s))
        c.close()
        shutil.copy(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "x4ctl", "test-mill.sim"), sim)
        time.sleep(0.3)
        c = b.connect()
        r = c.command("$X")
        r2 = c.command("G91 G0 X1")
        s = c.wait_state({"Idle", "Alarm"})
        check("the next client, the port open: $X unlocks, G-code runs", r[-1] == "ok" and r2 == ["ok"] and
              state_of(s) == "Idle", (r, r2, s))
        c.close()
    finally:
        b.stop()
        if os.path.exists(sim):
            os.unlink(sim)


def test_settings_unwritable(x4grbl):
    """A setting that cannot be written (the machine file's directory
    read-only, a lock file that cannot be made) is an error line with the
    reason, not the end of x4grbl. Directories in the files' places stand
    for it, as root writes anywhere."""
    b = Bridge(x4grbl)
    try:
        os.mkdir(os.path.join(b.dir, "mill.grbl"))
        os.mkdir(os.path.join(b.dir, "mill.ini.lock"))
        c = b.connect()
        r = c.command("$10=0")
        r2 = c.command("$110=900")
        s = c.status()
        check("settings that cannot be written: error lines with their reason, x4grbl alive",
              r[-1].startswith("error:") and r[0].startswith("[MSG:") and r2[-1].startswith("error:") and
              b.proc.poll() is None and field(s, "MPos") is not None and "MAX_VELOCITY = 20\n" in
              open(b.machine).read(), (r, r2, s, b.log_text()[-300:]))
        c.close()
    finally:
        b.stop()


def homing_from_afar(b):
    """A client whose $H runs: unlocked, sent to X80, far from the switch,
    so that the homing takes seconds."""
    c = b.connect()
    c.command("$X")
    c.command("G53 G0 X80")
    c.wait_state({"Idle"})
    c.send("$H\n")
    c.wait_state({"Home"}, timeout=10)
    return c


def test_sigterm_while_homing(x4grbl):
    """SIGTERM during $H: x4grbl stops the homing and ends at once, as it
    does mid-program, rather than when the homing is done."""
    b = Bridge(x4grbl)
    try:
        c = homing_from_afar(b)
        t0 = time.time()
        b.proc.terminate()
        try:
            b.proc.wait(20)
        except subprocess.TimeoutExpired:
            pass
        took = time.time() - t0
        check("SIGTERM during $H: x4grbl ends within 5 s (the homing, from X80 at 10 mm/s, takes 8 s or more)",
              b.proc.poll() is not None and took < 5,
              (took, b.log_text()[-300:]))
        c.close()
    finally:
        b.stop()


def test_disconnect_while_homing(x4grbl):
    """A sender that goes away during $H: the homing brakes, as on a
    reset, rather than going on for nobody (and the port, on a real one,
    is released only once the homing let go of it)."""
    b = Bridge(x4grbl)
    try:
        c = homing_from_afar(b)
        c.close()
        time.sleep(1.0)
        c = b.connect(greeting=False)
        lines = c.greet()
        s = c.status()
        check("a client gone during $H: the homing stopped, the next client finds Alarm (not homed)",
              state_of(s) == "Alarm" and not near(mpos(s), HOME) and "[MSG:'$H'|'$X' to unlock]" in lines,
              (lines, s, b.log_text()[-500:]))
        c.close()
    finally:
        b.stop()


def main():
    tests = (test_connect_and_queries, test_home_and_stream, test_buffer_and_status, test_hold_resume,
             test_hold_never_forgotten, test_probe,
             test_after_program_end, test_jog, test_soft_reset, test_alarms, test_settings, test_offsets,
             test_check_mode_and_overrides, test_second_client_and_garbage, test_disconnect_mid_program,
             test_status_flood)
    wanted = set(os.sys.argv[2:])
    if wanted:
        tests = tuple(t for t in tests if t.__name__ in wanted)
    b = Bridge(X4GRBL)
    try:
        for t in tests:
            try:
                t(b)
            except Exception as e:  # a test that broke off: its failure, and the rest go on
                check(t.__name__ + " ran to its end", False, repr(e) + "\n" + b.log_text()[-2000:])
    finally:
        b.stop()
    # Each on a bridge of its own.
    for t in (test_port_opens_later, test_settings_coordinates_with_blanks, test_settings_unwritable,
              test_disconnect_while_homing, test_sigterm_while_homing, test_pty):
        if wanted and t.__name__ not in wanted:
            continue
        try:
            t(X4GRBL)
        except Exception as e:
            check(t.__name__ + " ran to its end", False, repr(e))
    return exit_status()


if __name__ == "__main__":
    os.sys.exit(main())
