# SPDX-License-Identifier: GPL-2.0
# shellcheck shell=bash
# shellcheck disable=SC2034 # failed: read by the caller
# Sourced by the host check scripts here: a scratch directory $dir (removed
# at exit), `check NAME STATUS` (a PASS or FAIL line; a FAIL sets $failed),
# and a clean environment: no simulator setting or machine file of the
# caller's, virtual time (a script sets what it tests); `sim_run` runs the
# caller's $x4ctl on the simulated port.
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
failed=0
check() { # check NAME STATUS: PASS if STATUS is 0
	if [ "$2" -eq 0 ]; then echo "PASS $1"; else echo "FAIL $1"; failed=1; fi
}
unset X4STEP_SIM X4STEP_SIM_VCD X4STEP_SIM_KEYS X4STEP_SIM_MACHINE X4STEP_SIM_INPUTS X4STEP_SIM_STATE X4STEP_MACHINE
export X4STEP_SIM_TIME=virtual
# shellcheck disable=SC2154 # x4ctl: the caller's
sim_run() { # sim_run VCD ARGS...: x4ctl --sim ARGS, output in $dir/out, status returned
	local vcd=$1
	shift
	rm -f "$vcd"
	X4STEP_SIM_VCD=$vcd timeout 60 "$x4ctl" --sim "$@" </dev/null >"$dir/out" 2>&1
	local st=$?
	cat "$dir/out"
	return $st
}
