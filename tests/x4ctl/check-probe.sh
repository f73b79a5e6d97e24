#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# G38.x in x4ctl mdi on the simulated port (issue 31): a touch probe on
# input 4 (pin 10) active at Z step -2000 and below (-5 mm at SCALE 400):
# the trip exact to the step, the program going on from where the probe
# braked, G38.2 without contact an error that stops the program, G38.3
# without one none, and a machine without PROBE_INPUT refused before
# anything moves.
#   check-probe.sh X4CTL
set -u
x4ctl=$1
here=$(dirname "$0")
# shellcheck source=tests/x4ctl/check-lib.sh
. "$here/check-lib.sh"
sed 's/^\[X4STEP\]$/[X4STEP]\nPROBE_INPUT = 4/; s/^LINEAR_UNITS = mm$/LINEAR_UNITS = mm\nNO_FORCE_HOMING = 1/' \
	"$here/test-mill.ini" >"$dir/probe.ini"
{
	cat "$here/test-mill.sim"
	echo "probe 3 below -2000 pin10 no"
} >"$dir/probe.sim"
export X4STEP_SIM_MACHINE=$dir/probe.sim
steps_of() { awk -f "$here/vcd-steps.awk" "$2" | awk -v m="$1" '$1 == m { print $2 }'; } # steps_of MOTOR VCD
z_steps() { steps_of 3 "$1"; }

for feed in 60 300; do
	sim_run "$dir/a.vcd" mdi --machine "$dir/probe.ini" "G38.2 Z-10 F$feed" "G91 G0 Z1" &&
		grep -qx 'probe: tripped at X0 Y0 Z-5 (mm)' "$dir/out"
	check "G38.2 at F$feed trips at Z-5 exactly (step -2000)" $?
	braked=$(($(z_steps "$dir/a.vcd") - 400 + 2000))
	[ "$braked" -le 0 ] && [ "$braked" -gt -200 ]
	check "then the program goes on from where it braked (G91 Z1 from $braked steps past the trip)" $?
done
sim_run "$dir/a.vcd" mdi --machine "$dir/probe.ini" "G38.2 Z-3 F60" "G0 X1"
[ $? -eq 2 ] && grep -q '^x4ctl: mdi:1:1: G38.2 move finished without making contact; mdi: aborted' "$dir/out" &&
	[ "$(z_steps "$dir/a.vcd")" = -1200 ] && [ "$(steps_of 1 "$dir/a.vcd")" = 0 ]
check "G38.2 without contact: an error, the program stops there (X does not move)" $?
sim_run "$dir/a.vcd" mdi --machine "$dir/probe.ini" "G38.3 Z-3 F60" "G0 X1" &&
	grep -q 'done in .* at X1 Y0 Z-3 (mm)' "$dir/out"
check "G38.3 without contact: no error, the program goes on" $?
sed '/^PROBE_INPUT/d' "$dir/probe.ini" >"$dir/noprobe.ini"
sim_run "$dir/a.vcd" mdi --machine "$dir/noprobe.ini" "G0 X1" "G38.2 Z-10 F60"
[ $? -eq 2 ] && grep -q 'G38.2 needs a touch probe: give its input in the machine file (\[X4STEP\] PROBE_INPUT)' "$dir/out" &&
	[ "$(steps_of 1 "$dir/a.vcd")" = 0 ]
check "no PROBE_INPUT: refused before anything moves" $?
exit $failed
