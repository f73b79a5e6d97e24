#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# The everyday workflow (issue 30) rehearsed on the simulated port with
# separate x4ctl runs, as a user would: the port's state kept in a file
# (X4STEP_SIM_STATE), the work offsets in the machine's parameter file
# ([RS274NGC] PARAMETER_FILE). Home on test-mill.sim's switches, jog to the
# stock, touch off, check, run an unchanged CAM-style program (Z0 on the
# stock, clearance above it) that the soft limits refuse without a work
# offset. Also: unhomed axes refused, NO_FORCE_HOMING, a stepped jog back
# after an overrun, mdi's G10 L20 kept.
#   check-workflow.sh X4CTL PROGRAM
set -u
x4ctl=$1 program=$2
here=$(dirname "$0")
# shellcheck source=tests/x4ctl/check-lib.sh
. "$here/check-lib.sh"
export X4STEP_SIM_MACHINE=$here/test-mill.sim X4STEP_SIM_STATE=$dir/sim.state
sed 's/^\[X4STEP\]$/[RS274NGC]\nPARAMETER_FILE = mill.var\n[X4STEP]/' "$here/test-mill.ini" >"$dir/mill.ini"
machine=$dir/mill.ini
steps() { # steps VCD: the steps of every motor, "N N N N"
	[ -f "$1" ] || { echo "0 0 0 0"; return; }
	awk -f "$here/vcd-steps.awk" "$1" | awk '{ printf "%s%s", sep, $2; sep = " " } END { print "" }'
}
coordinate() { # coordinate AXIS: the engine's coordinate the state file keeps
	sed -n "s/^sim:0 axis $1 coordinate \([-0-9]*\) synced \([01]\) .*/\1 \2/p" "$dir/sim.state"
}

# --- not homed: refused, saying how to home ------------------------------------------
sim_run "$dir/a.vcd" gcode --machine "$machine" "$program"
[ $? -eq 2 ] && grep -q 'Z 15 is beyond the soft limit \[AXIS_Z\] MAX_LIMIT 0; but X, Y and Z are not homed: home first: x4ctl --sim home --machine ' "$dir/out"
check "gcode before homing: the soft limit, and how to home" $?
sim_run "$dir/a.vcd" mdi --machine "$machine" "G0 X1"
[ $? -eq 1 ] && grep -q "^x4ctl: mdi: X is not homed: home first: x4ctl --sim home --machine $machine X " "$dir/out" &&
	grep -q 'NO_FORCE_HOMING = 1' "$dir/out" && [ "$(steps "$dir/a.vcd")" = "0 0 0 0" ]
check "mdi moving an unhomed axis with a home switch: refused, nothing moves" $?

# --- home, kept for the next command -------------------------------------------------
sim_run "$dir/home.vcd" home --machine "$machine" && grep -qx 'home: done, at Z-1 X3 Y1 (mm)' "$dir/out"
check "home on the simulated switches" $?
[ "$(coordinate 1) / $(coordinate 2) / $(coordinate 3)" = "480 1 / -200 1 / -400 1" ]
check "the state file keeps the coordinates at HOME, synchronized" $?
sim_run "$dir/a.vcd" status && grep -q '^axis 3 *-400, synchronized, idle$' "$dir/out"
check "a later x4ctl --sim status sees the homed axes" $?

# --- the unchanged program, Z0 on the stock: refused without a work offset ------------
sim_run "$dir/a.vcd" gcode --check --machine "$machine" "$program"
[ $? -eq 2 ] && grep -q ':22:1: Z 15 is beyond the soft limit \[AXIS_Z\] MAX_LIMIT 0$' "$dir/out"
check "without a work offset the program's clearance Z15 is beyond MAX_LIMIT 0" $?

# --- jog to the stock's corner and top, touch off -----------------------------------
sim_run "$dir/a.vcd" jog Z- --machine "$machine" --distance 19 && sim_run "$dir/a.vcd" jog X+ --machine "$machine" --distance 7 &&
	sim_run "$dir/a.vcd" jog Y+ --machine "$machine" --distance 4 && grep -qx 'jog: Y at 5 mm (-1000 steps)' "$dir/out"
check "jogs from separate commands add up (Y at 5)" $?
sim_run "$dir/a.vcd" touch-off --machine "$machine" X=0 Y=0 Z=0 &&
	grep -qx 'touch-off: G54 Z -20: Z stands at work 0, machine -20 (mm)' "$dir/out"
check "touch-off X=0 Y=0 Z=0" $?
grep -qx '5220	1.000000' "$dir/mill.var" && grep -qx '5221	10.000000' "$dir/mill.var" &&
	grep -qx '5222	5.000000' "$dir/mill.var" && grep -qx '5223	-20.000000' "$dir/mill.var"
check "the parameter file holds G54 (5221..5223) in LinuxCNC's format" $?
sim_run "$dir/a.vcd" jog X- --machine "$machine" --distance 1 && grep -qx 'jog: X at 9 mm (1440 steps), work X-1' "$dir/out" &&
	sim_run "$dir/a.vcd" jog X+ --machine "$machine" --distance 1
check "jog shows work coordinates" $?

# --- check and run the unchanged program --------------------------------------------
sim_run "$dir/a.vcd" gcode --check --machine "$machine" "$program" &&
	grep -q '^extents (mm, work coordinates): X -10\.\.43 Y -5\.\.33 Z -6\.\.20; machine: X 0\.\.53 Y 0\.\.38 Z -26\.\.0$' "$dir/out"
check "gcode --check passes it, extents in work coordinates (from machine zero)" $?
sim_run "$dir/run.vcd" gcode --machine "$machine" "$program" &&
	grep -q '^extents (mm, work coordinates): X -3\.\.43 Y -3\.\.33 Z -6\.\.15; machine: X 7\.\.53 Y 2\.\.38 Z -26\.\.-5$' "$dir/out" &&
	grep -qx 'gcode: done in [0-9:]*, estimated [0-9:]*, at X30 Y20 Z-5 (mm)' "$dir/out"
check "gcode runs it to its end: work X20 Y15 Z15 is machine X30 Y20 Z-5" $?
# From the pins: the motors moved from the touch-off point (X10 Y5 Z-20) to the end.
[ "$(steps "$dir/run.vcd")" = "$((20 * 160)) $((15 * -200)) $((15 * 400)) 0" ]
check "the pins moved the motors by the program's work coordinates" $?
[ "$(coordinate 1) / $(coordinate 2) / $(coordinate 3)" = "4800 1 / -4000 1 / -2000 1" ]
check "the state file keeps where the program ended" $?
sim_run "$dir/a.vcd" mdi --machine "$machine" "G0 X0 Y0" "G1 Z-1 F100" && grep -qx 'mdi: done in [0-9:]*, estimated [0-9:]*, at X10 Y5 Z-21 (mm)' "$dir/out"
check "mdi in work coordinates from the parameter file" $?

# --- mdi's G10 L20 kept, its modal state not ----------------------------------------
sim_run "$dir/a.vcd" mdi --machine "$machine" "G10 L20 P2 Z5" && grep -qx '5243	-26.000000' "$dir/mill.var" &&
	grep -qx '5223	-20.000000' "$dir/mill.var"
check "mdi G10 L20 P2 Z5 sets G55 Z in the parameter file (5243), G54 stays" $?
sim_run "$dir/a.vcd" touch-off --machine "$machine" --system G55 X=2 &&
	grep -qx 'touch-off: G55 X 8: X stands at work 2, machine 10 (mm)' "$dir/out" && grep -qx '5241	8.000000' "$dir/mill.var" &&
	grep -qx '5221	10.000000' "$dir/mill.var" && grep -qx '5220	1.000000' "$dir/mill.var"
check "touch-off --system G55 X=2 sets G55 (5241); G54 and the active system stay" $?
sim_run "$dir/a.vcd" touch-off --machine "$machine" --system G60 X=2
[ $? -eq 2 ] && grep -q 'use G54, G55, G56, G57, G58, G59, G59.1, G59.2 or G59.3' "$dir/out"
check "touch-off --system G60: refused" $?
sim_run "$dir/a.vcd" mdi --machine "$machine" "G91 G0 Z1" && sim_run "$dir/a.vcd" mdi --machine "$machine" "G0 Z1" &&
	grep -qx 'mdi: done in [0-9:]*, estimated [0-9:]*, at X10 Y5 Z-19 (mm)' "$dir/out"
check "mdi's G91 ends with the command (G90 again), offsets do not" $?

# --- NO_FORCE_HOMING and an overrun --------------------------------------------------
rm -f "$dir/sim.state"
sed 's/^LINEAR_UNITS = mm$/LINEAR_UNITS = mm\nNO_FORCE_HOMING = 1/' "$machine" >"$dir/nfh.ini"
sim_run "$dir/a.vcd" mdi --machine "$dir/nfh.ini" "G53 G0 X1" && [ "$(steps "$dir/a.vcd")" = "160 0 0 0" ]
check "[TRAJ] NO_FORCE_HOMING = 1: unhomed axes move" $?
sim_run "$dir/a.vcd" zero 3 --at 4000 >/dev/null && sim_run "$dir/a.vcd" jog Z- --machine "$dir/nfh.ini" --distance 1 &&
	grep -qx 'jog: Z at 9 mm (3600 steps), work Z29' "$dir/out" && [ "$(steps "$dir/a.vcd")" = "0 0 -400 0" ]
check "Z beyond MAX_LIMIT (an overrun): a stepped jog back toward the range is allowed" $?
sim_run "$dir/a.vcd" jog Z+ --machine "$dir/nfh.ini" --distance 1
[ $? -eq 2 ] && grep -q 'Z 10 is beyond the soft limit \[AXIS_Z\] MAX_LIMIT 0: nothing moved' "$dir/out" &&
	[ "$(steps "$dir/a.vcd")" = "0 0 0 0" ]
check "... and one further out refused" $?
# A program that only read the port (a monitor) and closes after another
# program's move does not put back the state it read.
X4STEP_SIM_STATE=$dir/watch.state timeout -s INT 30 "$x4ctl" --sim in --watch >"$dir/watch.out" 2>&1 &
watcher=$!
for _ in $(seq 300); do # until it runs (it read the state as its port was made)
	[ -s "$dir/watch.out" ] && break
	sleep 0.1
done
X4STEP_SIM_STATE=$dir/watch.state "$x4ctl" --sim move 500 >/dev/null 2>&1
kill -INT "$watcher"
wait "$watcher"
grep -q '^sim:0 axis 1 coordinate 500 synced 0 machine 500$' "$dir/watch.state"
check "a monitor that closes after another program's move keeps that move in X4STEP_SIM_STATE" $?
exit $failed
