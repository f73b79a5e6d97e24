#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Host check (run-suite.sh hook): the guest test must not have produced a
# single step pulse: opening, closing and unloading x4step must leave the
# motors alone. Usage: check-no-steps.sh OUTDIR KVER  (needs $X4TRACE)
set -euo pipefail
out=$1
: "${X4TRACE:?X4TRACE not set (run-suite.sh builds tests/tools/x4trace)}"
"$X4TRACE" summary "$out/lpt-test.log" | tee "$out/lpt-test.summary"
steps=$(grep -E '^axis [1-4] ' "$out/lpt-test.summary" | grep -v ': 0 steps' || true)
if [ -n "$steps" ]; then
	echo "FAIL: step pulses on the connector:"
	echo "$steps"
	exit 1
fi
echo "PASS: no step pulses"
