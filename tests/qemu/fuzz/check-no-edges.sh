#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Host check (run-suite.sh hook) for tests/qemu/fuzz/fuzz.sh: between the guest's
# markers 0x58 0x49 and 0x58 0x4a (written to the status register around the
# invalid-calls-only fuzz run) QEMU's port trace shows no clock edge and no
# step: no invalid call moved a motor. Usage: check-no-edges.sh OUTDIR KVER
# (needs $X4TRACE, as run-suite.sh sets it).
set -euo pipefail
out=${1:?usage: check-no-edges.sh OUTDIR KVER}
: "${X4TRACE:?X4TRACE not set (run-suite.sh builds tests/tools/x4trace)}"
seg=$out/lpt-invalid.log
awk '/parallel_ioport_write/ {
	if (prev58 && / addr 0x01 val 0x49$/) { on = 1; seen_start = 1 }
	else if (prev58 && / addr 0x01 val 0x4a$/) { on = 0; seen_end = 1 }
	else if (on) print
	prev58 = / addr 0x01 val 0x58$/
}
END { if (!seen_start || !seen_end) exit 3 }' "$out/lpt-test.log" >"$seg" || {
	echo "FAIL: markers of the invalid-only phase (0x58 0x49 .. 0x58 0x4a) not found in $out/lpt-test.log"
	exit 1
}
echo "invalid-only phase: $(grep -c parallel_ioport_write "$seg" || true) port writes"
"$X4TRACE" summary "$seg" | tee "$out/lpt-invalid.summary"
# Clock pins 3, 5, 7, 9 (data bits 1, 3, 5, 7): no edge at all.
edges=$(awk '$1 ~ /^(3|5|7|9)$/ && ($3 != 0 || $4 != 0)' "$out/lpt-invalid.summary")
steps=$(grep -E '^axis [1-4] ' "$out/lpt-invalid.summary" | grep -v ': 0 steps' || true)
if [ -n "$edges$steps" ]; then
	echo "FAIL: clock edges during the invalid-only fuzz run:"
	printf '%s\n' "$edges" "$steps" | sed '/^$/d'
	exit 1
fi
echo "PASS: no clock edge from any invalid call"
