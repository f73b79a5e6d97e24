#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# make demo: x4step on an emulated parallel port, then the same simulated.
# Boots Debian's kernel in QEMU with x4step loaded (one boot) and runs
#  1. the X4Step manual's first example:
#       x4ctl move 1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400
#     (load, start, preload the way back, start it when the first move ends);
#  2. a part program, machines/examples/x4step-demo.ngc, on the machine
#     machines/x4step-4axis.ini: x4ctl gcode --svg on the module's path engine.
# Then shows what the pins did, from QEMU's own trace of the port writes
# (steps per axis, VCD files, the first example's step rate plot), the
# toolpath plot (planned against the positions the engine reported), and
# runs both once more on libx4step's simulated port, in one line each.
# Everything it writes is in build/demo/.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/build/demo
mkdir -p "$out"
cd "$top"
rm -f "$out/demo.vcd" "$out/demo.svg" "$out/sim.vcd" # an older make demo's
rel=build/demo # $out as the commands below are shown: from the top of the tree

machine=machines/x4step-4axis.ini
program=machines/examples/x4step-demo.ngc
move_args="1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400"
gcode_args="--machine $machine --svg part.svg --no-pause $program"
x4trace=$top/build/tests/x4trace
x4ctl=build/tools/x4ctl/x4ctl
started=$(date +%s)

fail() { # MESSAGE [LOG]: the message, the log's end, exit 1
	echo "make demo: $1" >&2
	[ -z "${2:-}" ] || tail -n 30 "$2" >&2
	exit 1
}

echo "== building the module, libx4step, x4ctl and x4trace (log: $rel/build.log)"
make -s userspace >"$out/build.log" 2>&1 || fail "the build failed" "$out/build.log"
kver=$(for k in /boot/vmlinuz-*-amd64; do
	k=${k#/boot/vmlinuz-}
	case $k in *-rt-amd64) ;; *) echo "$k" ;; esac
done | sort -V | head -n 1) # the oldest non-RT Debian kernel
[ -r "/boot/vmlinuz-$kver" ] || fail "no Debian kernel in /boot (scripts/deps.sh installs one)"
src=$out/src
rm -rf "$src"
mkdir -p "$src"
cp -r Kbuild kmod include "$src/"
make -s -C "/usr/src/linux-headers-$kver" M="$src" modules >>"$out/build.log" 2>&1 ||
	fail "the module did not build" "$out/build.log"
# The guest's x4ctl (static: the guest has no libc), rebuilt when a source is newer.
guest_x4ctl=$top/build/guest/x4ctl
if [ ! -x "$guest_x4ctl" ] || [ -n "$(find tools/x4ctl lib include kmod/engine build/lib/libx4step.a \
	-newer "$guest_x4ctl" -type f -print -quit)" ]; then
	echo "   (the guest's static x4ctl: a minute or two)"
	tests/qemu/build.sh "$top/build/guest" x4ctl >>"$out/build.log" 2>&1 ||
		fail "the guest's x4ctl did not build" "$out/build.log"
fi
# The kernel unpacked for a faster boot (run-guest.sh --kernel), kept.
kernel=()
pvh=$out/vmlinux-pvh-$kver
if [ "$pvh" -nt "/boot/vmlinuz-$kver" ] || tests/qemu/pvh-kernel.sh "/boot/vmlinuz-$kver" "$pvh" >/dev/null 2>&1; then
	kernel=(--kernel "$pvh")
fi

# The guest: the files of the tree it uses, then both runs. Its console is
# no terminal for x4ctl: output goes through files (no progress bar), and
# the plot comes back gzipped and base64-encoded between markers.
{
	# shellcheck disable=SC2016 # expanded in the guest
	echo 'insmod "$X4MOD/x4step.ko" || exit 1'
	echo 'mkdir -p /x4step/machines/examples && cd /x4step || exit 1'
	for f in "$machine" "${machine%.ini}.tbl" "$program"; do
		echo "cat >$f <<'X4DEMO-EOF'"
		# shellcheck disable=SC1003 # sed's command to end the file with a newline
		sed -e '$a\' "$f"
		echo "X4DEMO-EOF"
	done
	echo "move_args='$move_args' gcode_args='$gcode_args'"
	cat <<'GUEST'
echo X4DEMO-MOVE
# shellcheck disable=SC2086 # the arguments are words
x4ctl move $move_args --wait </dev/null >/tmp/move.out 2>&1
echo "X4DEMO-RC $?"
cat /tmp/move.out
# QEMU's port has no home switches: the axes are referenced where they
# stand (stop and zero), as gcode asks of axes that home (issue 30).
x4ctl zero 1 2 3 4 >/dev/null
# Marks the trace (writes to the status register change no pin): the part
# program's writes follow.
for v in 107 103; do printf "\\$v" | dd of=/dev/port bs=1 seek=889 2>/dev/null; done
echo X4DEMO-GCODE
# shellcheck disable=SC2086
x4ctl gcode $gcode_args </dev/null >/tmp/gcode.out 2>&1
rc=$?
echo "X4DEMO-RC $rc"
cat /tmp/gcode.out
echo X4DEMO-SVG
[ -f part.svg ] && gzip -c part.svg | base64
echo X4DEMO-END
exit $rc
GUEST
} >"$out/guest.sh"

echo "== booting Linux $kver in QEMU with an emulated parallel port and x4step (log: $rel/qemu.log)"
qemu_start=$(date +%s)
tests/qemu/run-guest.sh --kver "$kver" --out "$out/qemu" ${kernel[@]+"${kernel[@]}"} --timeout 240 \
	--module "$src/kmod/x4step.ko" --bin "$guest_x4ctl" "$out/guest.sh" >"$out/qemu.log" 2>&1 ||
	fail "the guest failed (its console: $rel/qemu/console.log)" "$out/qemu.log"
echo "   QEMU ran $(($(date +%s) - qemu_start)) s"
console=$out/qemu/console.txt
tr -d '\r' <"$out/qemu/console.log" >"$console"
section() { # FROM TO: the console's lines between two markers, indented
	sed -n "/$1\$/,/^$2\$/p" "$console" | sed -e '1d' -e '$d' -e '/^X4DEMO-RC /d' -e 's/^/   /'
}

# The trace in two: the first example, and the part program after its marker.
trace=$out/qemu/lpt-test.log
awk -v move="$out/qemu/move-trace.log" -v part="$out/qemu/part-trace.log" '
	!part_on && prev && / addr 0x01 val 0x43$/ { part_on = 1; next }
	{ prev = / addr 0x01 val 0x47$/ }
	/parallel_ioport_write/ { print > (part_on ? part : move) }' "$trace"
[ -s "$out/qemu/part-trace.log" ] || fail "QEMU's trace has no part program (see $rel/qemu/console.log)"

# steps TRACE: the steps per axis (rising clock edges), one line; motors 1..4
# drive X Y Z A in machines/x4step-4axis.ini
steps() {
	"$x4trace" summary "$1" | awk '
		/^axis [1-4] / { n = $2; sub(/^[^:]*: /, ""); s[n] = $1 }
		END { printf "X %d, Y %d, Z %d, A %d", s[1], s[2], s[3], s[4] }'
}
seconds() { # TRACE: the duration of its writes, s
	"$x4trace" summary "$1" | sed -n 's/.*duration \([0-9.]*\) us$/\1/p' | awk '{ printf "%.1f", $1 / 1e6 }'
}

echo
echo "1. The X4Step manual's first example: two moves of four axes, the second loaded while the first runs"
echo "   \$ x4ctl move $move_args"
section X4DEMO-MOVE X4DEMO-GCODE
grep -q '^done: -1000 -800 -600 -400$' "$console" || fail "x4ctl move did not end where it should in QEMU"
echo "   the pins, from QEMU's trace of the port writes (host time: timing under TCG is approximate):"
"$x4trace" moves "$out/qemu/move-trace.log" | sed 's/^/   /'
"$x4trace" vcd "$out/qemu/move-trace.log" "$out/move.vcd"
"$x4trace" svg "$out/qemu/move-trace.log" "$out/move-rate.svg"
echo "   steps per axis: $(steps "$out/qemu/move-trace.log")"
echo "   every pin (VCD: GTKWave, PulseView):  $rel/move.vcd"
echo "   step rate per axis over time (SVG):   $rel/move-rate.svg"

echo
echo "2. A part program: \"X4\" engraved in a frame, $program, on $machine"
echo "   \$ x4ctl gcode $gcode_args"
section X4DEMO-GCODE X4DEMO-SVG
grep -q '^gcode: done' "$console" || fail "x4ctl gcode did not run to its end in QEMU"
sed -n '/^X4DEMO-SVG$/,/^X4DEMO-END$/p' "$console" | sed -e '1d' -e '$d' | base64 -d | gzip -dc >"$out/part.svg" ||
	fail "the plot did not come back from the guest"
for c in planned "done"; do
	grep -q "class=\"$c\"[^>]* points=\"[-0-9]" "$out/part.svg" || fail "$rel/part.svg has no $c path"
done
"$x4trace" vcd "$out/qemu/part-trace.log" "$out/part.vcd"
qemu_steps=$(steps "$out/qemu/part-trace.log")
[ "$qemu_steps" != "X 0, Y 0, Z 0, A 0" ] || fail "QEMU's trace of the part program has no step"
qemu_secs=$(seconds "$out/qemu/part-trace.log")
echo "   the pins: $qemu_secs s of port writes; steps (rising clock edges) per axis: $qemu_steps"
echo "   the toolpath, planned (blue) and done by the motors (red):  $rel/part.svg"
echo "   every pin (VCD):                                           $rel/part.vcd"

echo
echo "3. The same on libx4step's simulated port: no QEMU, module or root; virtual time, in one line each"
sim() { # VCD ARGS...: x4ctl --sim in virtual time, shown and run
	local vcd=$1
	shift
	echo "   \$ X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD=$vcd $x4ctl --sim $*"
	X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD=$vcd "$x4ctl" --sim "$@" 2>&1 | sed 's/^/   /'
	[ "${PIPESTATUS[0]}" = 0 ] || fail "x4ctl --sim $1 failed"
}
# shellcheck disable=SC2086 # the arguments are words
sim $rel/sim-move.vcd move $move_args --wait
echo
sim $rel/sim-part.vcd gcode --machine "$machine" --svg $rel/sim-part.svg "$program"
sim_steps=$(steps "$out/sim-part.vcd")
if [ "$sim_steps" = "$qemu_steps" ]; then
	echo "   steps per axis: $sim_steps: the same as the module's in QEMU"
	sim_secs=$(seconds "$out/sim-part.vcd")
	if awk "BEGIN { exit !($qemu_secs > 1.1 * $sim_secs) }"; then
		echo "   (in $sim_secs s, as planned; in QEMU $qemu_secs s: its emulated CPU is slow, and the module"
		echo "   runs late steps later rather than shorten a pulse or a space)"
	fi
else
	echo "   steps per axis: $sim_steps (in QEMU: $qemu_steps)"
fi
echo "   plot: $rel/sim-part.svg, VCDs: $rel/sim-move.vcd, $rel/sim-part.vcd"
echo
echo "make demo: done in $(($(date +%s) - started)) s"
