#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins x4ctl
#: flags --monitor @OUT@/mon.sock
#: seconds 46
#
# Guest script (busybox sh): x4ctl with a keyboard. Keys are typed on QEMU's
# emulated PS/2 keyboard ("X4MON sendkey ..." lines, which run-guest.sh
# forwards to QEMU's monitor), so this needs run-guest.sh --monitor:
#   run-guest.sh --kver K --out DIR --monitor SOCK --module x4step.ko \
#       --bin x4ctl tests/qemu/x4ctl-keys/x4ctl-keys.sh
# Covers: the module's brake keys ending x4ctl's moves (ESC, a code set
# with `x4ctl keys`), and an interactive session on the virtual console
# /dev/tty1: M+ and T until ESC, C with the cursor keys, E, I, Q; x4ctl gcode
# there: space holds and resumes the path, ESC aborts it.
# Prints PASS/FAIL lines, exits nonzero if anything failed.

mod=${X4MOD:-/lib/x4}/x4step.ko
dev=/dev/x4step0
tmp=${TMPDIR:-/tmp}/x4ctl-keys
out=$tmp/out
err=$tmp/err
failed=0
mkdir -p "$tmp"

pass() { echo "PASS $1"; }
fail() {
	echo "FAIL $1${2:+: $2}"
	failed=1
}
show() { tr '\r\033\n' '~~|' <"$1" | head -c 400; }
has() { # NAME FILE PATTERN
	if grep -q -e "$3" "$2"; then pass "$1"; else fail "$1" "lacks '$3': $(show "$2")"; fi
}
field() { x4ctl status --json | sed -n "s/.*\"$1\":\(\[[^]]*\]\|[a-z0-9]*\).*/\1/p"; }
settle() {
	n=0
	while [ "$n" -lt "${1:-50}" ]; do
		[ "$(field active)" = false ] && [ "$(field controlled)" = false ] && return 0
		usleep 100000
		n=$((n + 1))
	done
	return 1
}
# Waits up to 10 s until a move runs: a key that must brake it is typed
# then, not after a fixed sleep (without -icount a loaded host lets the
# guest do less in its time, and a fixed sleep may end before the move
# has started).
running() {
	n=0
	while [ "$n" -lt 100 ]; do
		[ "$(field active)" = true ] && return 0
		usleep 100000
		n=$((n + 1))
	done
	return 1
}
expect_field() { # NAME FIELD VALUE
	v=$(field "$2")
	if [ "$v" = "$3" ]; then pass "$1"; else fail "$1" "$2 is '$v', want '$3'"; fi
}

# key KEY [PAUSE_US]: press and release KEY (QEMU's names: esc, ret, right,
# shift-equal; "right 1000" holds it 1 s), then give the host time to send it.
key() {
	echo "X4MON sendkey $1"
	usleep "${2:-400000}"
}
# typ TEXT: type a command line on the keyboard, then Enter.
typ() {
	s=$1
	while [ -n "$s" ]; do
		c=${s%"${s#?}"}
		s=${s#?}
		case "$c" in
		+) k=shift-equal ;;
		-) k=minus ;;
		,) k=comma ;;
		' ') k=spc ;;
		*) k=$c ;;
		esac
		key "$k"
	done
	key ret
}

if ! grep -q '^x4step ' /proc/modules && ! insmod "$mod"; then
	fail setup "insmod $mod"
	exit 1
fi
for _ in 1 2 3 4 5 6 7 8 9 10; do [ -c "$dev" ] && break; usleep 100000; done
if [ ! -c "$dev" ] || [ ! -c /dev/tty1 ]; then
	fail setup "no $dev or /dev/tty1"
	exit 1
fi
pass setup

# ---- the module's brake keys end x4ctl's moves ----------------------------------
x4ctl jog 1 + --freq 1000 >/dev/null 2>&1
running || fail esc-jog-runs "no move"
key esc 1000000
if settle 50; then pass esc-brakes-background-jog; else fail esc-brakes-background-jog "still running"; fi
expect_field esc-brake-code last_brake_code 1

x4ctl keys 28 >/dev/null
x4ctl move 1000000 --freq 1000 --background >/dev/null 2>&1
running || fail enter-move-runs "no move"
key ret 1000000
if settle 50; then pass enter-brakes-background-move; else fail enter-brakes-background-move "still running"; fi
expect_field enter-brake-code last_brake_code 28
x4ctl keys >/dev/null

(
	x4ctl move 1000000 --freq 1000 --wait >"$out" 2>"$err"
	echo $? >"$tmp/rc"
) &
running || fail esc-move-wait-runs "no move"
key esc 1500000
wait
if [ "$(cat "$tmp/rc")" = 1 ]; then pass move-wait-esc-exit-1; else fail move-wait-esc-exit-1 "exit $(cat "$tmp/rc")"; fi
has move-wait-esc-message "$err" '^x4ctl: move: halted (ESC) at [0-9]* of 1000000 steps'
settle 30

# ---- an interactive session on the virtual console ------------------------------------
x4ctl </dev/tty1 >"$tmp/ia.out" 2>"$tmp/ia.err" &
pid=$!
sleep 1
typ s2
typ f500
typ r0
typ m+
running || fail interactive-M+-runs "no move"
key esc 1000000
# With no ramp the move may end before the ESC reaches the terminal: the
# ESC then lands in the next line, which x4ctl must ignore.
typ d20
typ g
sleep 1
typ d400
typ r200
typ t
running || fail interactive-T-runs "no move"
key esc 1500000
typ c
key "right 1000" 2000000
key esc
typ e
sleep 1
key esc
typ i
typ q
n=0
while kill -0 "$pid" 2>/dev/null && [ "$n" -lt 50 ]; do usleep 100000; n=$((n + 1)); done
if kill -0 "$pid" 2>/dev/null; then
	kill "$pid"
	fail interactive-quit "Q did not end x4ctl"
else
	wait "$pid"
	rc=$?
	if [ "$rc" = 0 ]; then pass interactive-quit; else fail interactive-quit "exit $rc"; fi
fi
has interactive-help-at-start "$tmp/ia.out" '^Commands of the test program'
has interactive-M+-esc "$tmp/ia.out" '^halted (ESC): 0 [1-9][0-9]* 0 0$'
has interactive-esc-ignored "$tmp/ia.out" 'done: 0 20 0 0$'
has interactive-T-esc "$tmp/ia.out" 'T: [0-9]* moves, then halted (ESC)'
has interactive-C "$tmp/ia.out" 'C: axis 2 ended [1-9][0-9]* steps from where C began'
has interactive-E "$tmp/ia.out" 'E: pin15=[01] pin13=[01]'
has interactive-I "$tmp/ia.out" '^> 2  *400  *500  *200  leader$'
if [ -s "$tmp/ia.err" ]; then fail interactive-no-errors "$(show "$tmp/ia.err")"; else pass interactive-no-errors; fi
settle 30

# ---- x4ctl gcode on the virtual console: space holds and resumes, ESC aborts ----
# (ESC also reaches the module's key handler, which holds the path first.)
pos1() { x4ctl status --json | sed -n 's/.*"axis":1,"position":\(-*[0-9]*\).*/\1/p'; }
cat >"$tmp/keys.ini" <<-EOF
	[X4STEP]
	PORT = LPT1
	ARC_TOLERANCE = 0.01
	JUNCTION_DEVIATION = 0.02
	[TRAJ]
	COORDINATES = X
	LINEAR_UNITS = mm
	[AXIS_X]
	MIN_LIMIT = -1000
	MAX_LIMIT = 1000
	MAX_VELOCITY = 20
	MAX_ACCELERATION = 200
	[JOINT_0]
	MOTOR = 1
	SCALE = 100
EOF
printf 'G21 G91 G1 X40 F300\nM2\n' >"$tmp/keys.ngc" # 4000 steps at 500 steps/s
p0=$(pos1)
x4ctl gcode -m "$tmp/keys.ini" "$tmp/keys.ngc" </dev/tty1 >"$tmp/g.out" 2>"$tmp/g.err" &
pid=$!
# Counts, not fixed sleeps (a loaded host's guest may be slow to start, and
# keys may take their time through QEMU's monitor): space once the path
# moves; then held = two readings half a second apart agree, short of the
# path's end (a path that did not hold also stands still once at its end);
# resumed = it moves on. Up to 10 s each.
n=0
while [ "$(pos1)" = "$p0" ] && [ "$n" -lt 100 ]; do usleep 100000; n=$((n + 1)); done
key spc 1000000
p1=$(pos1) p2=
n=0
while [ "$n" -lt 20 ]; do
	usleep 500000
	p2=$(pos1)
	[ "$p1" = "$p2" ] && break
	p1=$p2
	n=$((n + 1))
done
if [ "$p1" = "$p2" ] && [ "$p1" -gt "$p0" ] && [ "$p1" -lt $((p0 + 4000)) ]; then pass gcode-space-holds; else
	fail gcode-space-holds "at $p0, then $p1 and $p2 half a second apart (the end: $((p0 + 4000)))"
fi
key spc 1000000
p3=$(pos1)
n=0
while [ "$p3" = "$p2" ] && [ "$n" -lt 100 ]; do
	usleep 100000
	p3=$(pos1)
	n=$((n + 1))
done
if [ "$p3" -gt "$p2" ]; then pass gcode-space-resumes; else fail gcode-space-resumes "at $p2, then $p3"; fi
key esc 1000000
n=0
while kill -0 "$pid" 2>/dev/null && [ "$n" -lt 50 ]; do usleep 100000; n=$((n + 1)); done
if kill -0 "$pid" 2>/dev/null; then
	kill "$pid"
	fail gcode-esc-aborts "x4ctl gcode still runs"
else
	wait "$pid"
	rc=$?
	if [ "$rc" = 1 ]; then pass gcode-esc-aborts; else fail gcode-esc-aborts "exit $rc"; fi
fi
has gcode-esc-message "$tmp/g.out" '^gcode: aborted at [0-9.]*% after [0-9:]*, estimated [0-9:]*, at X[0-9.]* (mm)$'
p4=$(pos1)
usleep 300000
p5=$(pos1)
if [ "$p4" = "$p5" ] && [ "$p4" -gt "$p3" ] && [ "$p4" -lt $((p0 + 4000)) ]; then
	pass gcode-abort-stops-on-path
else
	fail gcode-abort-stops-on-path "from $p0 (end $((p0 + 4000))): $p3, then $p4 and $p5"
fi
if [ -s "$tmp/g.err" ]; then fail gcode-keys-no-errors "$(show "$tmp/g.err")"; else pass gcode-keys-no-errors; fi
settle 30

if [ "$failed" = 0 ]; then echo "x4ctl key tests: all passed"; else echo "x4ctl key tests: FAILED"; fi
exit "$failed"
