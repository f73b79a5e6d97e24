# SPDX-License-Identifier: GPL-2.0
"""What the Python checks of x4ctl share: the program under test (argv[1]),
the test machine, and PASS/FAIL lines that decide the exit status."""
import os
import sys

X4CTL = sys.argv[1]
HERE = os.path.dirname(os.path.abspath(__file__))
MACHINE = os.path.join(HERE, "test-mill.ini")
_failed = False


def check(name, ok, detail=""):
    global _failed
    print(("PASS " if ok else "FAIL ") + name + ("" if ok else "\n" + detail))
    _failed |= not ok


def exit_status():
    return 1 if _failed else 0
