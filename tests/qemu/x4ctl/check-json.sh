#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Host check (run-suite.sh hook) of x4ctl.sh: every line x4ctl printed
# with --json in the guest, marked "X4JSON " on the console, is one JSON
# object that a JSON parser takes (the guest has neither python3 nor jq),
# starts with "schema": 1, and keeps booleans as booleans.
# Usage: check-json.sh OUTDIR KVER
set -euo pipefail
out=$1
python3 - "$out/console.log" <<'PY'
import json, sys
lines = [l.rstrip("\r\n")[len("X4JSON "):] for l in open(sys.argv[1], errors="replace")
         if l.startswith("X4JSON ")]
bad = 0
bools = {"active", "loaded", "controlled", "inputs_stale", "stale", "running", "synced", "ambiguous",
         "signal1", "signal2", "boost", "aktiv", "high", "nc"}
def walk(v, where):
    global bad
    if isinstance(v, dict):
        for k, x in v.items():
            if k in bools and not isinstance(x, bool):
                print(f"FAIL {where}: {k} is {x!r}, not a boolean"); bad += 1
            walk(x, where)
    elif isinstance(v, list):
        for x in v: walk(x, where)
for l in lines:
    try:
        d = json.loads(l)
    except ValueError as e:
        print(f"FAIL not JSON ({e}): {l[:200]}"); bad += 1; continue
    if not isinstance(d, dict) or list(d)[:1] != ["schema"] or d["schema"] != 1:
        print(f"FAIL no leading schema 1: {l[:200]}"); bad += 1; continue
    walk(d, l[:60])
if len(lines) < 10:
    print(f"FAIL only {len(lines)} X4JSON lines"); bad += 1
print(("FAIL" if bad else "PASS") + f": {len(lines)} JSON lines from x4ctl --json, {bad} bad")
sys.exit(1 if bad else 0)
PY
