#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# The hobbyist's workflow through CNCjs (issue 31's "done when"), headless:
# x4grbl on the simulated test mill with its home switches and a touch
# probe; CNCjs homes, jogs, probes Z, zeroes the work there, runs part.ngc
# with a feed override and a hold/resume, and must end Idle at the
# program's end in work coordinates.
#   workflow.sh X4GRBL
set -u
here=$(cd "$(dirname "$0")" && pwd)
mill=$here/../../x4ctl
tmp=$(mktemp -d "${TMPDIR:-/tmp}/x4-workflow.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# The test mill with a probe on input 4 (pin 10) at Z motor step -2000.
sed 's/^\[X4STEP\]$/[X4STEP]\nPROBE_INPUT = 4/' "$mill/test-mill.ini" >"$tmp/mill.ini"
{
	cat "$mill/test-mill.sim"
	echo "probe 3 below -2000 pin10 no"
} >"$tmp/mill.sim"
X4STEP_SIM_MACHINE=$tmp/mill.sim X4_CNCJS_WORKFLOW=1 \
	"$here/run.sh" -t 120 "$here/part.ngc" 12.5,7.25,-3 -- "$1" --sim --machine "$tmp/mill.ini" --link @PTY@
