#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# The simulated port never touches /dev/port or any real device (issue
# 19, "Checks"): x4ctl --sim (moves, outputs, inputs, homing, a path, the
# interactive mode) and a program of the manual's C API under X4STEP_SIM=1
# run under strace, which records every file they name and any ioperm or
# iopl. Only /dev/null and /dev/tty may be opened under /dev, nothing under
# /sys. strace is a test dependency (scripts/deps.sh): without it, or if it
# cannot trace here, this fails.
#   check-sim-nodev.sh X4CTL SIM_CAPI_PROBE
set -u
x4ctl=$1 probe=$2
# shellcheck source=tests/x4ctl/check-lib.sh
. "$(dirname "$0")/check-lib.sh"
if ! command -v strace >/dev/null; then
	echo "FAIL strace is missing: install it (scripts/deps.sh test, Debian package strace)"
	exit 1
fi
cat >"$dir/m.machine" <<'EOF'
ref 1 below -300 pin10 no
position 1 200
input 10 pin15=1
EOF
printf '100 0\n0 100\n' >"$dir/path.txt"
n=0
traced() { # traced NAME COMMAND...: COMMAND under strace, its VCD $dir/N.vcd
	local name=$1 vcd=$dir/$n.vcd log=$dir/$n.strace
	shift
	X4STEP_SIM_VCD=$vcd X4STEP_SIM_MACHINE=$dir/m.machine timeout 60 \
		strace -f -qq -o "$log" -e trace=%file,ioperm,iopl "$@" <"$dir/stdin" >"$dir/out" 2>&1
	local st=$?
	sed 's/^/    | /' "$dir/out"
	# The trace works: it has the VCD's open.
	grep -q "open.*\"$vcd\"" "$log"
	check "$name: exit 0, traced (the VCD's open is in the trace)" $((st + $?))
	# Any /dev path but /dev/null and /dev/tty, any /sys path, ioperm, iopl.
	grep -E '"/dev/|"/sys/|ioperm\(|iopl\(' "$log" | grep -vE '"/dev/(null|tty)"' >"$dir/bad"
	sed 's/^/    ! /' "$dir/bad"
	[ ! -s "$dir/bad" ]
	check "$name: no device, no /sys, no ioperm or iopl" $?
	n=$((n + 1))
}
: >"$dir/stdin"
traced "move" "$x4ctl" --sim move 300 -200 -f 5000
traced "jog --time" "$x4ctl" --sim jog 2 + -t 100
traced "out" "$x4ctl" --sim out 2 on -t 10
traced "in" "$x4ctl" --sim in
traced "home" "$x4ctl" --sim home 1
traced "path" "$x4ctl" --sim path "$dir/path.txt"
traced "status" "$x4ctl" --sim status
traced "list" "$x4ctl" --sim list
printf 'D500\nG\nO1,1\nE\nQ\n' >"$dir/stdin"
traced "interactive" "$x4ctl" --sim
X4STEP_SIM=1 traced "C API (X4STEP_SIM=1)" "$probe"
grep -qx 'steps 500 -250 inputs 1' "$dir/out"
check "C API: the move ran, the scripted input reads HIGH" $?
exit $failed
