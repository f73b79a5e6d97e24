#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# x4ctl mdi on the simulated port: blocks run as a program (the steps
# checked by gcode_sim_check from the VCD), nothing persists between
# invocations, and a bad block is named by line and column before
# anything moves.
#   check-mdi.sh X4CTL SIM_CHECK MACHINES_DIR
set -u
x4ctl=$1 sim_check=$2 machine=$3/x4step-4axis.ini
# shellcheck source=tests/x4ctl/check-lib.sh
. "$(dirname "$0")/check-lib.sh"
mdi() { # mdi VCD BLOCK...: x4ctl --sim mdi on the inch machine, output in $dir/out
	local vcd=$1
	shift
	rm -f "$vcd"
	X4STEP_SIM_VCD=$vcd timeout 30 "$x4ctl" --sim mdi -m "$machine" "$@" </dev/null >"$dir/out" 2>&1
}
rising_clocks() { # rising_clocks VCD: the steps in it (0 if there is no file)
	[ -f "$1" ] || { echo 0; return; }
	awk '$1 == "$var" && $5 ~ /_clk/ { clk[$4] = 1 }
		/^[01]/ { id = substr($0, 2); if (id in clk) { if ($0 ~ /^1/ && last[id] == "0") n++; last[id] = substr($0, 1, 1) } }
		END { print n + 0 }' "$1"
}

# Three blocks (a feed, a relative rapid, an arc) as one program.
blocks=("G1 X1 Y0.5 F30" "G91 G0 Z-0.25" "G90 G2 X2 Y0.5 I0.5 J0 F20")
mdi "$dir/run.vcd" "${blocks[@]}"
st=$?
cat "$dir/out"
[ $st -eq 0 ] && grep -qxE 'mdi: done in [0-9:]+, estimated [0-9:]+, at X2 Y0\.5 Z-0\.25 A0 \(inch\)' "$dir/out"
check "three blocks run to their end" $?
printf '%s\n' "${blocks[@]}" M2 >"$dir/blocks.ngc"
"$sim_check" "$machine" "$dir/blocks.ngc" "$dir/run.vcd"
check "their steps: exact end, within ARC_TOLERANCE + 1 step of the path" $?

# (MSG,...) and (DEBUG,...) in program order, each shown once the path
# reaches its line (the planner's message_at, not when it is planned).
mdi "$dir/msg.vcd" "G1 X0.5 F30" "(MSG,first cut done)" "G1 X1" "(DEBUG,second cut done)" "G0 X0"
st=$?
cat "$dir/out"
[ $st -eq 0 ] && [ "$(grep -E '^(MSG|DEBUG): ' "$dir/out" | tr '\n' '|')" = "MSG: first cut done|DEBUG: second cut done|" ]
check "messages in program order, DEBUG named as such" $?

# Nothing persists: G21 (mm) in one invocation, X1 in the next is 1 inch.
mdi "$dir/units.vcd" "G21" && mdi "$dir/units.vcd" "G0 X1"
st=$?
cat "$dir/out"
[ $st -eq 0 ] && grep -qxE 'mdi: done in [0-9:]+, estimated [0-9:]+, at X1 Y0 Z0 A0 \(inch\)' "$dir/out"
check "the modal state of one invocation does not reach the next" $?
"$x4ctl" mdi --help | grep -q "The modal state"
check "--help says so" $?

# A bad word: its line and column, nothing moves.
mdi "$dir/bad.vcd" "G1 X1 F30" "  G0 Y0.5 Q3"
st=$?
cat "$dir/out"
[ $st -eq 2 ] && grep -q '^x4ctl: mdi:2:11: ' "$dir/out" && [ "$(rising_clocks "$dir/bad.vcd")" -eq 0 ]
check "a bad word in block 2 at column 11: exit 2, named, no step" $?
mdi "$dir/bad.vcd" "G1 X1 F30 W2"
st=$?
cat "$dir/out"
[ $st -eq 2 ] && grep -q '^x4ctl: mdi:1:11: W' "$dir/out" && [ "$(rising_clocks "$dir/bad.vcd")" -eq 0 ]
check "an unknown word at column 11: exit 2, named, no step" $?
# A soft limit in the last block: refused before the first block moves.
mdi "$dir/limit.vcd" "G0 X1" "G0 X30"
st=$?
cat "$dir/out"
[ $st -eq 2 ] && grep -q '^x4ctl: mdi:2:1: X 30 is beyond the soft limit \[AXIS_X\] MAX_LIMIT 24' "$dir/out" &&
	[ "$(rising_clocks "$dir/limit.vcd")" -eq 0 ]
check "a soft limit in block 2: exit 2, named, block 1 does not move either" $?
# The clock counter itself counts: the good run above had steps.
[ "$(rising_clocks "$dir/run.vcd")" -gt 1000 ]
check "the step counter sees the good run's steps" $?
mdi "$dir/nl.vcd" $'G0 X1\nG0 X2'
st=$?
cat "$dir/out"
[ $st -eq 2 ] && grep -q 'no line break' "$dir/out"
check "a block with a line break is refused" $?
exit $failed
