#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Host check (run-suite.sh hook) for tests/qemu/config/config_test.cpp: in QEMU's
# port trace, between the guest's markers 0x58 0x43 CODE (a SET_CONFIG
# follows; CODE = clock_invert | output_mode << 4) and 0x58 0x4d (the next
# move), no data register write makes an edge that a driver wired for the
# NEW configuration counts as a step:
#   clock-dir: no clock pin (data bit 2i+1) changes to its active level,
#              HIGH, or LOW for an axis whose clock is inverted;
#   smc-phase: every write is a motor's "off" pattern (0x1b);
#   smc-hold:  every write is "off" or the hold pattern of the motor's last
#              position (its last running pattern at reduced current).
# Every announced change (the guest's "CONFIGS n") must be found.
# Usage: check-config.sh OUTDIR KVER
set -euo pipefail
out=${1:?usage: check-config.sh OUTDIR KVER}
python=$(command -v /usr/bin/python3 || command -v python3)
exec "$python" - "$out" <<'PY'
import re, sys

out = sys.argv[1]
with open(out + "/console.log", errors="replace") as f:
    want = [int(m.group(1)) for m in re.finditer(r"^CONFIGS (\d+)\r?$", f.read(), re.M)]
if not want:
    sys.exit("FAIL: no CONFIGS line from the guest")

RUN = [0x03, 0x09, 0x38, 0x29, 0x27, 0x2D, 0x1C, 0x0D]  # SMC half-step table


def hold(p):  # 100 % phases drop to 20 %
    if not p & 0x03:
        p |= 0x01
    if not p & 0x18:
        p |= 0x08
    return p


last = [RUN[0]] * 3  # each motor's last running pattern (the engine starts at index 0)
data, code, window, marker = 0, 0, False, 0
changes, bad = [], 0
write = re.compile(r"parallel_ioport_write write \[SW\] addr (0x[0-9a-f]+) val (0x[0-9a-f]+)")
for line in open(out + "/lpt-test.log"):
    m = write.search(line)
    if not m:
        continue
    addr, val = int(m.group(1), 16), int(m.group(2), 16)
    if addr == 1:  # markers: 0x58 0x43 CODE, 0x58 0x4d
        if marker == 2:
            code, window, marker = val, True, 0
            changes.append(0)
        elif marker == 1 and val == 0x43:
            marker = 2
        elif marker == 1 and val == 0x4D:
            window, marker = False, 0
        else:
            marker = 1 if val == 0x58 else 0
        continue
    if addr != 0:
        continue
    old, data = data, val
    motor, pat = val >> 6, val & 0x3F
    if not window:
        if motor < 3 and pat in RUN:
            last[motor] = pat
        continue
    changes[-1] += 1
    mode, n = code >> 4, len(changes)
    if mode == 0:
        for a in range(4):
            b = 1 << (2 * a + 1)
            inverted = bool(code & (1 << a))
            was, now = bool(old & b), bool(val & b)
            if was != now and now != inverted:
                print("BAD  change %d (code 0x%02x): data 0x%02x -> 0x%02x: axis %d clock to its active level (%s)"
                      % (n, code, old, val, a + 1, "LOW, inverted" if inverted else "HIGH"))
                bad += 1
    elif motor > 2 or (pat != 0x1B and not (mode == 2 and pat == hold(last[motor]))):
        print("BAD  change %d (code 0x%02x): data 0x%02x: not a rest pattern of motor %d (last 0x%02x)"
              % (n, code, val, motor, last[motor]))
        bad += 1
for i, k in enumerate(changes, 1):
    print("change %d: %d data writes checked" % (i, k))
if len(changes) != want[-1]:
    sys.exit("FAIL: %d changes framed in the trace, the guest made %d" % (len(changes), want[-1]))
if bad:
    sys.exit("FAIL: %d writes would step a driver wired for the new configuration" % bad)
print("PASS: %d wiring changes, no edge that steps a driver wired for the new configuration" % len(changes))
PY
