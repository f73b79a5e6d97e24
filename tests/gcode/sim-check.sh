#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# LinuxCNC's example programs run by x4ctl --sim gcode in virtual time
# (issue 20), checked from the VCD of every pin by sim_check: each axis
# ends at exactly round(programmed end x SCALE), and every step lies
# within ARC_TOLERANCE + 1 step of the ideal path. The programs are the
# "match" ones of programs.txt (gcode.oracle holds their motions to
# rs274's), run on a mm and on an inch machine; one that needs more than
# the port's 4 axes is named and not counted. Without the unpacked
# linuxcnc-uspace the test fails: it never skips.
#   sim-check.sh X4CTL SIM_CHECK GCODE_DUMP [CACHE]
set -u
x4ctl=$1 sim_check=$2 dump=$3
cache=${4:-${X4_LINUXCNC_CACHE:-/var/cache/x4step/linuxcnc}}
here=$(dirname "$(readlink -f "$0")")
if [ ! -f "$cache/complete" ]; then
	echo "FAIL: LinuxCNC's example programs are not in $cache: run scripts/deps.sh test as root" \
		"(scripts/get-rs274.sh fetches Debian's linuxcnc-uspace)"
	exit 1
fi
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
unset X4STEP_SIM X4STEP_SIM_KEYS X4STEP_SIM_MACHINE X4STEP_SIM_INPUTS

# machine NAME UNITS SCALE TOLERANCE LETTERS: a step/dir machine on LPT1,
# soft limits far away; Y's motor mounted the other way round (negative
# SCALE); rotary axes at 100 steps per degree.
machine() {
	local f=$dir/$1.ini l m=0
	printf '[EMC]\nMACHINE = sim check\n[X4STEP]\nPORT = LPT1\nOUTPUT_MODE = step-dir\n' >"$f"
	printf 'ARC_TOLERANCE = %s\nJUNCTION_DEVIATION = %s\n' "$4" "$4" >>"$f"
	printf '[TRAJ]\nCOORDINATES = %s\nLINEAR_UNITS = %s\nANGULAR_UNITS = degree\n' "$5" "$2" >>"$f"
	for l in $(echo "$5" | grep -o .); do
		printf '[AXIS_%s]\nMIN_LIMIT = -10000\nMAX_LIMIT = 10000\n' "$l" >>"$f"
		case $l in
		[XYZ]) printf 'MAX_VELOCITY = %s\nMAX_ACCELERATION = %s\n' "$(awk "BEGIN{print 5000/$3}")" \
			"$(awk "BEGIN{print 50000/$3}")" >>"$f" ;;
		*) printf 'MAX_VELOCITY = 50\nMAX_ACCELERATION = 500\n' >>"$f" ;;
		esac
	done
	for l in $(echo "$5" | grep -o .); do
		s=$3
		case $l in Y) s=-$3 ;; [ABC]) s=100 ;; esac
		printf '[JOINT_%d]\nMOTOR = %d\nSCALE = %s\n' $m $((m + 1)) "$s" >>"$f"
		m=$((m + 1))
	done
	echo "$f"
}

ran=0 failed=0
while read -r kind rel _; do
	[ "$kind" = match ] || continue
	case $rel in cam/* | probe/*) continue ;; esac # ours; this test is for programs nobody here wrote
	prog=$cache/root/$rel name=$(basename "$rel")
	if [ ! -f "$prog" ]; then
		echo "FAIL $name: $prog missing"
		failed=1
		continue
	fi
	# The axes it moves (XYZ always): rotary letters from the interpreter's motions.
	rot=$("$dump" "$prog" | awk '{ for (i = 5; i <= 7; i++) if ($i + 0 != 0) u[i] = 1 }
		END { for (i = 5; i <= 7; i++) if (u[i]) printf "%s", substr("ABC", i - 4, 1) }')
	if [ ${#rot} -gt 1 ]; then
		echo "not run: $name needs XYZ$rot, more than the port's 4 motors"
		continue
	fi
	for units in mm inch; do
		case $units in
		mm) m=$(machine "mm$rot" mm 100 0.01 "XYZ$rot") ;;
		inch) m=$(machine "inch$rot" inch 2000 0.0005 "XYZ$rot") ;;
		esac
		X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD=$dir/run.vcd timeout 120 \
			"$x4ctl" --sim gcode --no-pause --machine "$m" "$prog" </dev/null >"$dir/out" 2>&1
		st=$?
		if [ $st -ne 0 ] || ! grep -q '^gcode: done' "$dir/out"; then
			echo "FAIL $name ($units machine): x4ctl exit $st:"
			tail -3 "$dir/out"
			failed=1
			continue
		fi
		"$sim_check" "$m" "$prog" "$dir/run.vcd" | sed "s|^\(....\) $cache/root/|\1 ($units machine) |" ||
			failed=1
		[ "${PIPESTATUS[0]}" -eq 0 ] || failed=1
		ran=$((ran + 1))
	done
done <"$here/programs.txt"
echo "$ran runs checked from their steps"
if [ $ran -lt 10 ]; then
	echo "FAIL: only $ran runs (5 programs on 2 machines expected at least)"
	failed=1
fi
exit $failed
