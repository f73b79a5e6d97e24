#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# x4ctl home and jog in machine units on the simulated port: test-mill.ini's
# machine with test-mill.sim's switches. Where the motors really went comes
# from the pins (the VCD, vcd-steps.awk); where the engine's coordinates
# stand from x4ctl's own report.
#   check-machine-ops.sh X4CTL
set -u
x4ctl=$1
here=$(dirname "$0")
machine=$here/test-mill.ini
# shellcheck source=tests/x4ctl/check-lib.sh
. "$(dirname "$0")/check-lib.sh"
export X4STEP_SIM_MACHINE=$here/test-mill.sim
steps() { # steps VCD MOTOR: its net steps; "MOTOR STEPS FIRST LAST" with -v line=1
	[ -f "$1" ] || { echo "$2 0 - -"; return; }
	awk -f "$here/vcd-steps.awk" "$1" | awk -v m="$2" '$1 == m'
}
net() { steps "$1" "$2" | awk '{ print $2 }'; }

# --- homing -----------------------------------------------------------------------
# Z (sequence 0) first, then X and Y (sequence 1) together. Each switch's
# edge becomes HOME_OFFSET, then the axis goes to HOME: on the pins, X
# stands at -999 + (3 - -2) x 160 = -199, Y at 699 + (1 - 0.5) x -200 = 599,
# Z at 899 + (-1 - 0) x 400 = 499.
sim_run "$dir/home.vcd" home --machine "$machine"
st=$?
[ $st -eq 0 ] && grep -qx 'home: done, at Z-1 X3 Y1 (mm)' "$dir/out"
check "home: exit 0, the engine's coordinates at HOME" $?
[ "$(net "$dir/home.vcd" 1) $(net "$dir/home.vcd" 2) $(net "$dir/home.vcd" 3)" = "-199 599 499" ]
check "home: the motors stand at HOME from the switches' edges (X -199, Y 599, Z 499 steps)" $?
read -r _ _ _ zlast < <(steps "$dir/home.vcd" 3)
read -r _ _ xfirst xlast < <(steps "$dir/home.vcd" 1)
read -r _ _ yfirst ylast < <(steps "$dir/home.vcd" 2)
[ "$zlast" -lt "$xfirst" ] && [ "$zlast" -lt "$yfirst" ]
check "home: Z (HOME_SEQUENCE 0) ends before X and Y start" $?
[ $((xfirst - yfirst)) -lt 1000000 ] && [ $((yfirst - xfirst)) -lt 1000000 ] && [ "$xfirst" -lt "$ylast" ] &&
	[ "$yfirst" -lt "$xlast" ]
check "home: X and Y (HOME_SEQUENCE 1) home at the same time" $?
[ "$(sed -n 's/^home: \([XYZ]\) (sequence.*/\1/p' "$dir/out" | tr -d '\n')" = ZXY ]
check "home: reported in sequence order" $?

sim_run "$dir/homez.vcd" home --machine "$machine" z &&
	grep -qx 'home: done, at Z-1 (mm)' "$dir/out" &&
	[ "$(net "$dir/homez.vcd" 1) $(net "$dir/homez.vcd" 2) $(net "$dir/homez.vcd" 3)" = "0 0 499" ]
check "home z: only Z moves" $?
X4STEP_MACHINE=$machine sim_run "$dir/homeenv.vcd" home &&
	grep -qx 'home: done, at Z-1 X3 Y1 (mm)' "$dir/out" &&
	[ "$(net "$dir/homeenv.vcd" 1) $(net "$dir/homeenv.vcd" 2) $(net "$dir/homeenv.vcd" 3)" = "-199 599 499" ]
check "home with \$X4STEP_MACHINE and no -m or letters: all its axes (as panel and gcode)" $?

# The shipped SMC1500 mill: every switch on input 1, homed one sequence
# after the other, each axis off its switch (at HOME) before the next
# search. In step-dir mode here: the simulated machine follows clock and
# direction pins only. Z at 299 + -2 x 320 = -341, X at -499 + 2 x 320 =
# 141, Y at -699 + 640 = -59.
sed 's/^OUTPUT_MODE = smc-phase/OUTPUT_MODE = step-dir/' "$here/../../machines/smc1500-mill.ini" >"$dir/smc.ini"
printf 'ref 1 below -500 pin15 no\nref 2 below -700 pin15 no\nref 3 above 300 pin15 no\n' >"$dir/smc.sim"
X4STEP_SIM_MACHINE=$dir/smc.sim sim_run "$dir/smc.vcd" home --machine "$dir/smc.ini" &&
	grep -qx 'home: done, at Z-2 X2 Y2 (mm)' "$dir/out" &&
	[ "$(net "$dir/smc.vcd" 1) $(net "$dir/smc.vcd" 2) $(net "$dir/smc.vcd" 3)" = "141 -59 -341" ]
check "home the SMC1500 mill: three switches on one input, Z, X, Y in turn" $?

# A switch that is not there: the search gives up after 1.25 x the travel,
# and the later sequence does not start.
printf 'ref 1 below -1000 pin15 no\nref 2 above 700 pin13 no\n' >"$dir/noz.sim"
X4STEP_SIM_MACHINE=$dir/noz.sim sim_run "$dir/noz.vcd" home --machine "$machine"
st=$?
[ $st -eq 1 ] && grep -q 'Z: the home switch (input 3) did not become active, or change again, within 37.5 mm' "$dir/out" &&
	grep -q 'the later sequences did not start' "$dir/out" &&
	[ "$(net "$dir/noz.vcd" 1) $(net "$dir/noz.vcd" 2) $(net "$dir/noz.vcd" 3)" = "0 0 15000" ]
check "home without Z's switch: exit 1, named, Z gave up at 37.5 mm, X and Y did not move" $?

# A bad homing key: file:line, exit 2, nothing moves.
sed 's/^HOME_LATCH_VEL = 1$/HOME_LATCH_VEL = 0/' "$machine" >"$dir/bad.ini"
line=$(grep -n '^HOME_LATCH_VEL = 0$' "$dir/bad.ini" | head -1 | cut -d: -f1)
sim_run "$dir/bad.vcd" home --machine "$dir/bad.ini"
st=$?
[ $st -eq 2 ] && grep -q "^x4ctl: home: $dir/bad.ini:$line:[0-9]*: \[JOINT_0\] HOME_LATCH_VEL: must not be 0" "$dir/out" &&
	[ "$(net "$dir/bad.vcd" 1)$(net "$dir/bad.vcd" 2)$(net "$dir/bad.vcd" 3)" = "000" ]
check "home: HOME_LATCH_VEL 0 refused as file:line, nothing moves" $?
# Two axes on one input in one sequence: which switch would it be?
sed 's/^HOME_INPUT = 2$/HOME_INPUT = 1/' "$machine" >"$dir/shared.ini"
line=$(awk '/^\[JOINT_1\]/ { j = 1 } j && /^HOME_SEQUENCE/ { print NR; exit }' "$dir/shared.ini")
sim_run "$dir/shared.vcd" home --machine "$dir/shared.ini"
st=$?
[ $st -eq 2 ] && grep -q "^x4ctl: home: $dir/shared.ini:$line:[0-9]*: \[JOINT_1\] HOME_SEQUENCE: joint 0 homes on input 1 in sequence 1 too" "$dir/out"
check "home: two axes on one input in one sequence refused as file:line" $?
sim_run "$dir/bad.vcd" home --machine "$machine" W
[ $? -eq 2 ] && grep -q "'W': give axis letters" "$dir/out"
check "home W: refused" $?

# --- jog ------------------------------------------------------------------------------
# By a distance: exactly round(position x SCALE); Y's SCALE is negative.
sim_run "$dir/jx.vcd" jog X+ --machine "$machine" --distance 1.2345 &&
	grep -qx 'jog: X at 1.238 mm (198 steps)' "$dir/out" && [ "$(net "$dir/jx.vcd" 1)" = 198 ]
check "jog X+ --distance 1.2345: 198 steps (1.2345 x 160 = 197.52)" $?
sim_run "$dir/jy.vcd" jog y+ --machine "$machine" --distance 0.3333 --feed 60 &&
	grep -qx 'jog: Y at 0.335 mm (-67 steps)' "$dir/out" && [ "$(net "$dir/jy.vcd" 2)" = -67 ]
check "jog y+ --distance 0.3333: -67 steps (0.3333 x -200 = -66.66)" $?
# Continuously: to the soft limit, and not a step beyond.
sim_run "$dir/jlim.vcd" jog Y+ --machine "$machine" --feed 1200 &&
	grep -qx 'jog: Y at 50 mm (-10000 steps)' "$dir/out" && [ "$(net "$dir/jlim.vcd" 2)" = -10000 ]
check "jog Y+: stops at MAX_LIMIT 50 mm (-10000 steps)" $?
sim_run "$dir/jmin.vcd" jog X- --machine "$machine" --feed 1200 &&
	[ "$(net "$dir/jmin.vcd" 1)" = -800 ]
check "jog X-: stops at MIN_LIMIT -5 mm (-800 steps)" $?
# Braked by a key (the module's ESC) on its way: short of the limit.
X4STEP_SIM_KEYS=500ms:esc sim_run "$dir/jkey.vcd" jog X+ --machine "$machine" --feed 600
st=$?
n=$(net "$dir/jkey.vcd" 1)
[ $st -eq 0 ] && grep -q '^jog: X at .*, braked' "$dir/out" && [ "$n" -gt 0 ] && [ "$n" -lt 1000 ]
check "jog X+ braked by ESC after 0.5 s: stands short of the limit ($n steps)" $?
# Refusals: beyond a soft limit (exit 2, nothing moves), at the limit already (exit 1).
sim_run "$dir/jbad.vcd" jog X- --machine "$machine" --distance 6
[ $? -eq 2 ] && grep -q '^x4ctl: jog: X -6 is beyond the soft limit \[AXIS_X\] MIN_LIMIT -5' "$dir/out" &&
	[ "$(net "$dir/jbad.vcd" 1)" = 0 ]
check "jog X- --distance 6: beyond MIN_LIMIT, exit 2, no step" $?
sim_run "$dir/jat.vcd" jog Y- --machine "$machine"
[ $? -eq 1 ] && grep -q 'Y is at 0 mm, at or beyond its soft limit MIN_LIMIT 0' "$dir/out" &&
	[ "$(net "$dir/jat.vcd" 2)" = 0 ]
check "jog Y- at MIN_LIMIT: exit 1, no step" $?
# The steps form is still there.
sim_run "$dir/jsteps.vcd" jog 2 - --time 100 &&
	[ "$(net "$dir/jsteps.vcd" 2)" -lt 0 ]
check "jog 2 - (steps) still runs" $?
exit $failed
