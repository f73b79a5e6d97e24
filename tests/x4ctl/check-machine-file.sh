#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# x4ctl machine check and import (issue 30): every mistake of a machine
# file in one pass; LinuxCNC's own settings accepted with a warning; a
# StepConf configuration (stepconf/router.ini and .hal, as StepConf 1.1
# writes them) made into a machine file that checks good, with its values.
#   check-machine-file.sh X4CTL MACHINES_DIR
# shellcheck disable=SC2181 # each check reads the status of the run just before it
set -u
x4ctl=$1
machines=$2
here=$(dirname "$0")
# shellcheck source=tests/x4ctl/check-lib.sh
. "$here/check-lib.sh"
run() { # run ARGS...: x4ctl ARGS, stdout in $dir/out, stderr in $dir/err, status returned
	timeout 60 "$x4ctl" "$@" </dev/null >"$dir/out" 2>"$dir/err"
}
# key FILE SECTION KEY: the value of [SECTION] KEY
key() { awk -v s="[$2]" -v k="$3" '/^\[/ { in_s = $0 == s } in_s && $1 == k && $2 == "=" { print $3; exit }' "$1"; }

# --- check ------------------------------------------------------------------------
run machine check "$machines/smc1500-mill.ini" "$machines/x4step-4axis.ini"
[ $? -eq 0 ] && diff - "$dir/out" <<EOF
$machines/smc1500-mill.ini: good: XYZ in mm, motors 1 2 3, homes X Y Z
$machines/x4step-4axis.ini: good: XYZA in inch, motors 1 2 3 4, homes X Y Z
EOF
check "machine check: the shipped files are good, and what they are" $?

# Five mistakes, each with its line and column, in one pass.
cat >"$dir/bad.ini" <<'EOF'
[X4STEP]
ARC_TOLERANCE = 0.01 # the chord's most
JUNCTION_DEVIATON = 0.02
OUTPUT_MODE = step-dir
[TRAJ]
COORDINATES = XZ
LINEAR_UNITS = mm ; as LinuxCNC
[AXIS_X]
MIN_LIMIT = 10
MAX_LIMIT = 5
MAX_VELOCITY = 20
MAX_ACCELERATION = 200
[AXIS_Z]
MIN_LIMIT = -50
MAX_LIMIT = 0
MAX_VELOCITY = 10
MAX_ACCELERATION = 100
[JOINT_0]
MOTOR = 1
SCALE = 8000
HOME_SERCH_VEL = -5
[JOINT_1]
MOTOR = 1
SCALE = -400
[DISPLAYS]
EOF
run machine check "$dir/bad.ini"
[ $? -eq 1 ] && diff - "$dir/out" <<EOF
$dir/bad.ini:3:1: [X4STEP] JUNCTION_DEVIATON: unknown key: did you mean JUNCTION_DEVIATION?
$dir/bad.ini:10:13: [AXIS_X] MAX_LIMIT: MAX_LIMIT 5 must be above MIN_LIMIT 10
$dir/bad.ini:20:9: [JOINT_0] SCALE: the axis' MAX_VELOCITY 20 would be 160000 steps/s at SCALE 8000: the port steps at most 100000
$dir/bad.ini:20:9: [JOINT_0] SCALE: the axis' MAX_ACCELERATION 200 would be 1600000 steps/s^2 at SCALE 8000: at most 1000000
$dir/bad.ini:21:1: [JOINT_0] HOME_SERCH_VEL: unknown key: did you mean HOME_SEARCH_VEL?
$dir/bad.ini:23:9: [JOINT_1] MOTOR: motor 1 drives another axis already (line 19): one axis per motor
$dir/bad.ini:25:1: [DISPLAYS]: unknown section: did you mean [DISPLAY]?
$dir/bad.ini: refused: 7 mistakes
EOF
check "machine check: every mistake in one pass, line:col, did you mean, the values, exit 1" $?

# The same mistakes stop gcode before anything moves, a line each.
printf 'G0 X1\nM2\n' >"$dir/p.ngc"
run gcode -m "$dir/bad.ini" --check "$dir/p.ngc"
[ $? -eq 2 ] && [ "$(grep -c "^x4ctl: gcode: $dir/bad.ini:[0-9]*:[0-9]*: " "$dir/err")" = 7 ]
check "gcode: the bad machine file refused, each of its 7 mistakes on its own line" $?

# A good file with LinuxCNC's own sections and keys: accepted, listed once.
{
	printf '[EMC]\nVERSION = 1.1\n[HAL]\nHALFILE = mill.hal\nHALFILE = custom.hal\n'
	sed -e '/^JUNCTION_DEVIATON/s/DEVIATON/DEVIATION/' -e 's/^MIN_LIMIT = 10$/MIN_LIMIT = 0/' \
		-e 's/^SCALE = 8000$/SCALE = 800\nFERROR = 1\nSTEPGEN_MAXACCEL = 250/' -e '/^HOME_SERCH_VEL/d' \
		-e 's/^\[DISPLAYS\]$/[DISPLAY]\nDISPLAY = axis/' -e '/^\[JOINT_1\]/,$s/^MOTOR = 1$/MOTOR = 3/' "$dir/bad.ini"
} >"$dir/good.ini"
run machine check "$dir/good.ini"
[ $? -eq 0 ] && diff - "$dir/out" <<EOF
$dir/good.ini: good: XZ in mm, motors 1 3, no homing
$dir/good.ini: LinuxCNC sections x4step does not use, ignored: [HAL] [DISPLAY]
$dir/good.ini: LinuxCNC keys x4step does not use, ignored: [EMC] VERSION; [JOINT_0] FERROR STEPGEN_MAXACCEL
EOF
check "machine check: LinuxCNC's sections and keys accepted, listed once; inline comments; step-dir" $?
run gcode -m "$dir/good.ini" --check "$dir/p.ngc"
[ $? -eq 0 ] && [ "$(grep -c 'warning' "$dir/err")" = 2 ] &&
	grep -qx "x4ctl: gcode: warning: $dir/good.ini: LinuxCNC sections x4step does not use, ignored: \[HAL\] \[DISPLAY\]" "$dir/err"
check "gcode: runs on it, the two warnings on stderr" $?

# A StepConf INI as it is: what it lacks, and where to go.
run machine check "$here/stepconf/router.ini"
[ $? -eq 1 ] && grep -q "router.ini: \[X4STEP\]: no \[X4STEP\] section: .*'x4ctl machine import' makes a machine file" "$dir/out" &&
	grep -q 'router.ini: refused: 9 mistakes$' "$dir/out"
check "machine check of a StepConf INI: all 9 mistakes, and import named" $?

run machine
[ $? -eq 2 ] && grep -q 'give check or import' "$dir/err"
check "machine without an action: usage, exit 2" $?
run machine check "$dir/none.ini"
[ $? -eq 1 ] && grep -qx "$dir/none.ini: cannot read the machine file" "$dir/out"
check "machine check of no file: exit 1" $?

# --- import -----------------------------------------------------------------------
run machine import -o "$dir/router.ini" "$here/stepconf/router.ini"
st=$?
cp "$dir/out" "$dir/report"
[ $st -eq 0 ] && grep -qx "$dir/router.ini: good: XYZ in mm, motors 1 2 3, homes X Y Z" "$dir/report"
check "import: exit 0, the file made checks good" $?
run machine check "$dir/router.ini"
[ $? -eq 0 ]
check "import: machine check of the file made: good" $?
f=$dir/router.ini
got="$(key "$f" TRAJ COORDINATES) $(key "$f" TRAJ LINEAR_UNITS) $(key "$f" TRAJ MAX_LINEAR_VELOCITY) $(key "$f" X4STEP OUTPUT_MODE) $(key "$f" X4STEP SPINDLE_PIN) $(key "$f" EMC MACHINE)"
[ "$got" = "XYZ mm 50.00 clock-dir 14 router" ]
check "import: axes, units, path speed, mode, spindle on pin 14, name ($got)" $?
got=
for a in X Y Z; do
	got="$got $(key "$f" AXIS_$a MIN_LIMIT)..$(key "$f" AXIS_$a MAX_LIMIT)@$(key "$f" AXIS_$a MAX_VELOCITY)/$(key "$f" AXIS_$a MAX_ACCELERATION)"
done
[ "$got" = " -0.01..600.0@50.0/750.0 -0.01..400.0@50.0/750.0 -100.0..0.01@25.0/500.0" ]
check "import: soft limits, velocities, accelerations ($got)" $?
got=
for j in 0 1 2; do
	got="$got $(key "$f" JOINT_$j MOTOR):$(key "$f" JOINT_$j SCALE):$(key "$f" JOINT_$j HOME_INPUT):$(key "$f" JOINT_$j HOME_SEARCH_VEL):$(key "$f" JOINT_$j HOME_LATCH_VEL):$(key "$f" JOINT_$j HOME_SEQUENCE)"
done
[ "$got" = " 1:320.0:4:-10.000000:1.5625:1 2:-320.0:5:-10.000000:1.562500:2 3:400.0:3:5.000000:-1.25:0" ]
check "import: motors, scales, home inputs from the HAL (pins 10 11 12), latch signs x4step's ($got)" $?
[ "$(key "$f" EMCIO TOOL_TABLE)" = "$(cd "$here/stepconf" && pwd -P)/tool.tbl" ]
check "import: the tool table beside the INI, by its absolute path" $?
grep -q '^changed: \[JOINT_0\] HOME_LATCH_VEL -1.5625 made 1.5625: ' "$dir/report" &&
	grep -q '^not carried: pin map: estop-out pin 1, xstep pin 2, xdir pin 3, .*spindle-pwm pin 16, xenable pin 17 (x4step' "$dir/report" &&
	grep -qx 'not carried: limit switches (the port.s setting, which the module keeps): x4ctl limits 1 --minus 2' "$dir/report" &&
	grep -q '^not carried: step timing: stepgen.0.steplen 1, ' "$dir/report" &&
	grep -qx 'not carried: LinuxCNC.s sections: \[DISPLAY\] \[KINS\] \[FILTER\] \[TASK\] \[RS274NGC\] \[EMCMOT\] \[HAL\]' "$dir/report" &&
	grep -qx 'not carried: \[JOINT_0\] TYPE = LINEAR, STEPGEN_MAXACCEL = 937.5, FERROR = 1, MIN_FERROR = .25, HOME_IGNORE_LIMITS = YES' "$dir/report"
check "import: the report lists the changes and what was not carried (pin map, limits, timing, keys)" $?
printf 'G21 G90\nG0 Z-1\nG0 X300 Y200\nG1 Z-5 F300\nG2 X310 Y200 I5 J0\nG0 Z-1\nM2\n' >"$dir/part.ngc"
run gcode -m "$dir/router.ini" --check "$dir/part.ngc"
check "import: gcode --check runs a program on the file made" $?

# To standard output, the report on standard error; an existing file is not overwritten.
run machine import "$here/stepconf/router.ini" "$here/stepconf/router.hal"
[ $? -eq 0 ] && cmp -s <(sed 1,2d "$dir/out") <(sed 1,2d "$dir/router.ini") && grep -q '^not carried: pin map' "$dir/err"
check "import INI HAL: the same file on stdout, the report on stderr" $?
run machine import -o "$dir/router.ini" "$here/stepconf/router.ini"
[ $? -eq 2 ] && grep -q "router.ini exists: remove it or name another" "$dir/err"
check "import -o an existing file: refused, exit 2" $?
ln -s "$dir/elsewhere.ini" "$dir/link.ini"
run machine import -o "$dir/link.ini" "$here/stepconf/router.ini"
[ $? -eq 2 ] && grep -q "link.ini exists: remove it or name another" "$dir/err" && [ ! -e "$dir/elsewhere.ini" ]
check "import -o a dangling symbolic link: refused, nothing written where it points" $?

# A gantry (X Y Y Z: LinuxCNC's joint 3 is Z): Z's settings come from
# [JOINT_3], not from the second Y's [JOINT_2].
python3 - "$here/stepconf/router.ini" "$here/stepconf/router.hal" "$dir" <<'EOF'
import re, sys
ini, hal, out = sys.argv[1:]
t = open(ini).read().replace("COORDINATES =  X Y Z", "COORDINATES =  X Y Y Z")
y2 = re.search(r"\[JOINT_1\]\n(?:[^[].*\n|\n)*", t).group(0)
t = t.replace("[JOINT_2]", "[JOINT_3]").replace("[AXIS_Z]", y2.replace("[JOINT_1]", "[JOINT_2]").replace("SCALE = -320.0", "SCALE = -321.0") + "[AXIS_Z]")
open(out + "/gantry.ini", "w").write(t)
open(out + "/gantry.hal", "w").write(open(hal).read().replace("joint.2.", "joint.3."))
EOF
run machine import -o "$dir/gantry-x4.ini" "$dir/gantry.ini" "$dir/gantry.hal"
[ $? -eq 0 ] && [ "$(key "$dir/gantry-x4.ini" TRAJ COORDINATES)" = XYZ ] &&
	[ "$(key "$dir/gantry-x4.ini" JOINT_2 SCALE)" = 400.0 ] && [ "$(key "$dir/gantry-x4.ini" JOINT_1 SCALE)" = -320.0 ] &&
	grep -q "not carried: \[TRAJ\] COORDINATES = X Y Y Z: axes Y " "$dir/out"
check "import of a gantry (X Y Y Z): Z is LinuxCNC's joint 3, the second Y is not carried" $?

# Without the HAL file: no home switch inputs, so no homing, said so.
mkdir "$dir/nohal" && cp "$here/stepconf/router.ini" "$dir/nohal/"
run machine import -o "$dir/nohal.ini" "$dir/nohal/router.ini"
[ $? -eq 0 ] && grep -qx "$dir/nohal.ini: good: XYZ in mm, motors 1 2 3, no homing" "$dir/out" &&
	[ "$(grep -c '^not carried: \[JOINT_[012]\] homing: no HAL file to find the home switch.s input in' "$dir/out")" = 3 ] &&
	[ -z "$(key "$dir/nohal.ini" EMCIO TOOL_TABLE)" ]
check "import without a HAL file: no homing (3 joints listed), no tool table (none beside it)" $?

# A StepConf file x4step's port cannot step: written, and the check says why.
sed 's/^SCALE = 320.0$/SCALE = 3200.0/' "$here/stepconf/router.ini" >"$dir/nohal/fast.ini"
run machine import -o "$dir/fast.ini" "$dir/nohal/fast.ini" "$here/stepconf/router.hal"
[ $? -eq 1 ] && [ -f "$dir/fast.ini" ] &&
	grep -q "^$dir/fast.ini:[0-9]*:9: \[JOINT_0\] SCALE: the axis' MAX_VELOCITY 50 would be 160000 steps/s at SCALE 3200" "$dir/out"
check "import of a machine too fast for the port: written, refused by the check, exit 1" $?
exit $failed
