#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins x4ctl
#: flags --module @FIXTURES@/x4vport.ko
#: check check-json.sh
#: seconds 65
#
# Guest script (busybox sh): scripted sessions of every x4ctl subcommand and
# of `x4ctl run` with every command of the test program, against
# /dev/x4step0, plus bad input (unknown commands, out-of-range values, a
# missing port) checking messages and exit status. Prints PASS/FAIL lines,
# exits nonzero if anything failed.
#
# Needs a (static) x4ctl on PATH, parport0 as the only port, and x4step
# loaded or $X4MOD/x4step.ko. With $X4MOD/x4vport.ko too, it ends with the
# positioning commands on the virtual port's machine (switches). Run by
# tests/qemu/run-guest.sh:
#   run-guest.sh --kver K --out DIR --module x4step.ko [--module x4vport.ko] --bin x4ctl #     tests/qemu/x4ctl/x4ctl.sh
# shellcheck disable=SC2317 # helpers are called indirectly

mod=${X4MOD:-/lib/x4}/x4step.ko
dev=/dev/x4step0
tmp=${TMPDIR:-/tmp}/x4ctl-test
out=$tmp/out
err=$tmp/err
failed=0
mkdir -p "$tmp"

pass() { echo "PASS $1"; }
fail() {
	echo "FAIL $1${2:+: $2}"
	failed=1
}
show() { tr '\r\033\n' '~~|' <"$1" | head -c 400; } # a file's start, on one console line

# check NAME RC OUT ERR CMD...: run CMD; PASS if it exits with RC, its stdout
# has a line matching the basic regex OUT and its stderr one matching ERR
# (empty: not checked).
check() {
	name=$1 want=$2 opat=$3 epat=$4
	shift 4
	"$@" >"$out" 2>"$err" </dev/null
	rc=$?
	if [ "$rc" != "$want" ]; then
		fail "$name" "exit $rc, want $want; stdout: $(show "$out"); stderr: $(show "$err")"
	elif [ -n "$opat" ] && ! grep -q -e "$opat" "$out"; then
		fail "$name" "stdout lacks '$opat': $(show "$out")"
	elif [ -n "$epat" ] && ! grep -q -e "$epat" "$err"; then
		fail "$name" "stderr lacks '$epat': $(show "$err")"
	else
		pass "$name"
	fi
}

# script NAME RC OUT ERR TEXT [OPTIONS...]: `x4ctl run` on a script
# (printf format TEXT), echoing the commands.
script() {
	name=$1 want=$2 opat=$3 epat=$4 text=$5
	shift 5
	# shellcheck disable=SC2059 # TEXT is a format on purpose
	printf "$text" >"$tmp/script.x4"
	check "$name" "$want" "$opat" "$epat" x4ctl run --echo "$@" "$tmp/script.x4"
}

# The value of a JSON field of `x4ctl status --json` (numbers, booleans, arrays).
field() { x4ctl status --json | sed -n "s/.*\"$1\":\(\[[^]]*\]\|[a-z0-9]*\).*/\1/p"; }

# Waits up to $1 tenths of a second until no move runs and no x4ctl holds the port.
settle() {
	n=0
	while [ "$n" -lt "${1:-50}" ]; do
		[ "$(field active)" = false ] && [ "$(field controlled)" = false ] && return 0
		usleep 100000
		n=$((n + 1))
	done
	return 1
}

has() { # NAME FILE PATTERN: PASS if a line of FILE matches the basic regex
	if grep -q -e "$3" "$2"; then pass "$1"; else fail "$1" "lacks '$3': $(show "$2")"; fi
}
lacks() { # NAME FILE PATTERN: PASS if no line of FILE matches
	if grep -q -e "$3" "$2"; then fail "$1" "has '$3': $(show "$2")"; else pass "$1"; fi
}

expect_field() { # NAME FIELD VALUE
	v=$(field "$2")
	if [ "$v" = "$3" ]; then pass "$1"; else fail "$1" "$2 is '$v', want '$3'"; fi
}

# Without -icount the guest's time follows the host's clock, and a loaded
# host lets the guest do less in it: the script waits for states, not for
# fixed times, before the step that needs them (up to 10 s each).
# eventually FIELD VALUE [FIELD VALUE]: until status --json shows them.
eventually() {
	n=0
	while [ "$n" -lt 100 ]; do
		[ "$(field "$1")" = "$2" ] && { [ $# -lt 4 ] || [ "$(field "$3")" = "$4" ]; } && return 0
		usleep 100000
		n=$((n + 1))
	done
	return 1
}
# port_open PID: until the process has the port open (a watcher or monitor
# gets the events from its open on).
port_open() {
	n=0
	while [ "$n" -lt 100 ]; do
		for f in "/proc/$1/fd"/*; do
			case $(readlink "$f" 2>/dev/null) in /dev/x4step*) return 0 ;; esac
		done
		usleep 100000
		n=$((n + 1))
	done
	return 1
}

if ! command -v x4ctl >/dev/null; then
	fail setup "no x4ctl on PATH"
	exit 1
fi
if ! grep -q '^x4step ' /proc/modules; then
	if ! insmod "$mod"; then
		fail setup "insmod $mod"
		exit 1
	fi
fi
for _ in 1 2 3 4 5 6 7 8 9 10; do [ -c "$dev" ] && break; usleep 100000; done
if [ ! -c "$dev" ]; then
	fail setup "no $dev"
	exit 1
fi
pass setup

# ---- help and usage: no device needed -------------------------------------
check help 0 '^Usage: x4ctl \[' '' x4ctl --help
check help-version 0 '^x4ctl [0-9]' '' x4ctl --version
for c in move jog brake stop status in out keys sweep monitor run timing mode profile goto home zero limits halt watch list; do
	check "help-$c" 0 "^Usage: x4ctl $c " '' x4ctl "$c" --help
	check "help-cmd-$c" 0 "^Usage: x4ctl $c " '' x4ctl help "$c"
done
check help-run-lists-commands 0 'Ax,y,z' '' x4ctl run --help
check usage-unknown-command 2 '' "unknown command 'bogus'" x4ctl bogus
check usage-unknown-option 2 '' "move: unknown option '--fast'" x4ctl move 100 --fast
check usage-missing-value 2 '' "option '--freq' needs a value" x4ctl move 100 --freq
check usage-port-range 2 '' 'port 5 out of range: use 1 to 4' x4ctl -p 5 status
check usage-try-help 2 '' "Try 'x4ctl move --help'" x4ctl move

# ---- no such port: -p 4 when only parport0 exists ----------------------------
check noport-status 1 '' 'status: /dev/x4step3: port not found' x4ctl -p 4 status
check noport-move 1 '' 'move: /dev/x4step3: port not found' x4ctl -p 4 move 100 --wait
check noport-interactive 1 '' 'port not found' x4ctl 4
check noport-device 1 '' '/dev/nonexistent: port not found' x4ctl -d /dev/nonexistent in
script noport-run 1 '' 'run: /dev/x4step3: port not found' 's1\nd100\ng\n' -p 4
script noport-run-check 0 'no errors' '' 's1\nd100\ng\n' -p 4 --check

# ---- read-only commands -------------------------------------------------------
check status 0 '^state *idle' '' x4ctl status
check status-json 0 '^{"schema":1,"device":"/dev/x4step0","active":false,' '' x4ctl status --json
# --json: every reading command, one object a line, each with the schema; errors too (on stdout).
for c in status in timing mode limits list "profile 1"; do
	# shellcheck disable=SC2086 # "profile 1" is two words
	check "json-$c" 0 '^{"schema":1,' '' x4ctl $c --json
done
check json-error 1 '^{"schema":1,"error":{"message":"/dev/x4step3: port not found: .*","errno":2}}$' '' \
	x4ctl -p 4 status --json
check json-usage-error 2 '^{"schema":1,"error":{"message":"watch: count 0 out of range: use 1 or more","errno":22}}$' '' \
	x4ctl watch --json -n 0
# Every --json output once more, marked for tests/qemu/x4ctl/check-json.sh, which
# parses them on the host (this guest has neither python3 nor jq).
for c in status in timing mode limits list "profile 1" "watch -n 2" "monitor -n 1"; do
	case $c in
	watch* | monitor*)
		# shellcheck disable=SC2086
		x4ctl $c --json >"$tmp/json.out" 2>&1 &
		jpid=$!
		port_open "$jpid"
		x4ctl move 20 --freq 2000 --ramp 5 --wait >/dev/null 2>&1
		wait "$jpid"
		;;
	*)
		# shellcheck disable=SC2086
		x4ctl $c --json >"$tmp/json.out" 2>&1
		;;
	esac
	sed 's/^/X4JSON /' "$tmp/json.out"
done
x4ctl -p 4 status --json | sed 's/^/X4JSON /'
check json-in-booleans 0 '"input_pins":{"15":\(true\|false\),"13":\(true\|false\),' '' x4ctl in --json
# ---- list: the ports, their module, who holds them -----------------------------------
check list 0 '^/dev/x4step0  parport0  ABI [0-9]*  free$' '' x4ctl list
check list-library 0 '^library      libx4step [0-9]' '' x4ctl list
check list-json 0 '^{"schema":1,"library":"[0-9.]*","ports":\[{"device":"/dev/x4step0","parport":0,"abi":[0-9]*,"controlled":false,"controller":null,' '' \
	x4ctl list --json
check status-lpt1 0 '^device *\/dev\/x4step0' '' x4ctl -p 1 status
check in 0 '^pin15=[01] pin13=[01] pin12=[01] pin10=[01] pin11=[01] ([0-9]*)$' '' x4ctl in
# The module reads the port only while it has claimed it: read-only, with no
# controller, the levels are the last ones read, and x4ctl says so.
check in-read-only 0 '^pin15=[01] .* ([0-9]*) (stale: no controller has the port; read [0-9.]* s ago)$' '' \
	x4ctl in --read-only
check status-stale 0 '^inputs *pin15=[01] .* (stale: no controller has the port; read ' '' x4ctl status

# ---- move --------------------------------------------------------------------------
check move-wait 0 '^done: 200 100 50 -25$' '' x4ctl move 200 100 50 -25 --freq 2000 --ramp 20 --wait
expect_field move-wait-steps steps '[200,100,50,-25]'
expect_field move-wait-released controlled false
check move-one-axis 0 '^done: -120 0 0 0$' '' x4ctl move -120 --freq 3000 --ramp 0 --wait
# In the foreground by default (issue 17): one move after the other.
check move-foreground 0 '^done: 100 0 0 0$' '' x4ctl move 100 --freq 2000 --ramp 0
check move-foreground-back 0 '^done: -100 0 0 0$' '' x4ctl move -100 --freq 2000 --ramp 0
check move-background 0 'running in the background as PID' '' x4ctl move 80 --freq 2000 --ramp 10 --background
if settle 100; then pass move-background-ends; else fail move-background-ends "still running"; fi
expect_field move-background-steps steps '[80,0,0,0]'

check bad-move-freq 2 '' '^x4ctl: move: frequency too high: use at most 20000 Hz$' x4ctl move 100 --freq 30000
check bad-move-freq-low 2 '' 'move: frequency too low: use at least 10 Hz' x4ctl move 100 --freq 5
check bad-move-ramp 2 '' 'move: ramp too long: use at most 1000 ms' x4ctl move 100 --ramp 2000
check bad-move-ramp-freq 2 '' 'move: ramp too long for the frequency' x4ctl move 100 --freq 100 --ramp 200
check bad-move-steps 2 '' 'move: path too long: at most 16777216 steps' x4ctl move 16777217
check bad-move-nosteps 2 '' 'move: no steps' x4ctl move 0 0 0 0
check bad-move-number 2 '' "move: steps 'abc' is not a whole number" x4ctl move abc
check bad-move-axes 2 '' "move: unexpected argument '5'" x4ctl move 1 2 3 4 5
check move-default-ramp 0 'at 20 Hz, ramp 20 ms' '' x4ctl move 1 --freq 20 --wait

# ---- move --then: the X4Step manual's first example (X4Load, X4Start, X4Load while
# the move runs, X4Start when it ends), and longer sequences ------------------------------
ended=$(field moves_ended)
check move-then 0 '^done: -1000 -800 -600 -400$' '' \
	x4ctl move 1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400 --wait
has move-then-first "$out" '^done: 1000 800 600 400$'
has move-then-header "$out" '^move 1 of 2: 1000 800 600 400 at 1000 Hz, ramp 50 ms$'
has move-then-second "$out" '^move 2 of 2: -1000 -800 -600 -400 at 1000 Hz, ramp 50 ms$'
expect_field move-then-steps steps '[-1000,-800,-600,-400]'
expect_field move-then-two-moves moves_ended "$((ended + 2))"
expect_field move-then-released controlled false
expect_field move-then-nothing-loaded loaded false
ended=$(field moves_ended)
check move-then-two 0 '^done: -100 -50 0 0$' '' \
	x4ctl move 200 --freq 4000 --ramp 10 --then -100 50 --then -100 -50 --wait
has move-then-two-first "$out" '^done: 200 0 0 0$'
has move-then-two-second "$out" '^done: -100 50 0 0$'
has move-then-two-third "$out" '^move 3 of 3: -100 -50 0 0 at 4000 Hz, ramp 10 ms$'
expect_field move-then-two-steps steps '[-100,-50,0,0]'
expect_field move-then-two-moves moves_ended "$((ended + 3))"
# In the background: the second move is loaded while the first runs, and started by the holder.
# (The first move lasts 2 s, so that slower debug kernels also see it running.)
ended=$(field moves_ended)
check move-then-background 0 'running in the background as PID' '' \
	x4ctl move 2000 --freq 1000 --ramp 20 --then -2000 0 0 7 --background
has move-then-background-second "$out" '^move 2 of 2: -2000 0 0 7 at 1000 Hz, ramp 20 ms$'
eventually active true loaded true
expect_field move-then-background-active active true
expect_field move-then-background-preloaded loaded true
if settle 100; then pass move-then-background-ends; else fail move-then-background-ends "still running"; fi
expect_field move-then-background-steps steps '[-2000,0,0,7]'
expect_field move-then-background-moves moves_ended "$((ended + 2))"
# Bad values after --then: exit 2 before the port is opened, nothing moves.
ended=$(field moves_ended)
check bad-move-then-number 2 '' "^x4ctl: move: --then steps 'x' is not a whole number$" \
	x4ctl move 100 --then x --wait
check bad-move-then-second 2 '' "move: --then steps '1.5' is not a whole number" \
	x4ctl move 100 --then -100 --then 1.5 --wait
check bad-move-then-steps 2 '' 'move: --then path too long: at most 16777216 steps' \
	x4ctl move 100 --then 16777217 --wait
check bad-move-then-nosteps 2 '' 'move: --then no steps' x4ctl move 100 --then 0 0
check bad-move-then-axes 2 '' "move: --then: unexpected argument '5'" x4ctl move 100 --then 1 2 3 4 5
check bad-move-then-missing 2 '' "move: option '--then' needs a value" x4ctl move 100 --then
expect_field bad-move-then-nothing-moved moves_ended "$ended"
expect_field bad-move-then-idle active false

# ---- brake and stop from another shell ---------------------------------------------
check brake-idle 1 '' '^x4ctl: brake: no move is running$' x4ctl brake
check stop-idle 1 '' '^x4ctl: stop: no move is running$' x4ctl stop
check brake-start 0 'running in the background' '' x4ctl move 1000000 --freq 1000 --ramp 50 -b
eventually active true
expect_field brake-running active true
check brake-busy 1 '' 'move: /dev/x4step0: port busy: PID [0-9]* (x4ctl) controls it' x4ctl move 10 --wait
check brake 0 '^braked: [1-9][0-9]* 0 0 0$' '' x4ctl brake
if settle 50; then pass brake-released; else fail brake-released "port still held"; fi
# A braked move of a sequence ends it: the moves after it do not start, exit 1.
ended=$(field moves_ended)
x4ctl move 1000000 --freq 1000 --ramp 50 --then -10 --then 10 --wait >"$tmp/seq.out" 2>"$tmp/seq.err" &
pid=$!
usleep 500000
x4ctl brake >/dev/null 2>&1
wait "$pid"
rc=$?
if [ "$rc" = 1 ] &&
	grep -q '^x4ctl: move: move 1 of 3: halted (brake request) at [0-9]* of 1000000 steps: [0-9]* 0 0 0; moves 2 to 3 not started$' "$tmp/seq.err" &&
	! grep -q '^done' "$tmp/seq.out"; then
	pass then-braked-ends-sequence
else
	fail then-braked-ends-sequence "exit $rc: $(show "$tmp/seq.err")"
fi
settle 50
expect_field then-braked-one-move moves_ended "$((ended + 1))"
steps=$(field steps)
case "$steps" in \[[1-9]*,0,0,0\]) pass then-braked-steps ;; *) fail then-braked-steps "$steps" ;; esac
# The same in the background: 'x4ctl brake' ends the sequence the holder runs.
ended=$(field moves_ended)
check then-brake-start 0 'running in the background' '' x4ctl move 1000000 --freq 1000 --then -10 -b
usleep 300000
check then-brake 0 '^braked: [1-9][0-9]* 0 0 0$' '' x4ctl brake
if settle 50; then pass then-brake-released; else fail then-brake-released "port still held"; fi
expect_field then-brake-one-move moves_ended "$((ended + 1))"
steps=$(field steps)
case "$steps" in \[[1-9]*,0,0,0\]) pass then-brake-steps ;; *) fail then-brake-steps "$steps" ;; esac
check stop-start 0 'running in the background' '' x4ctl jog 4 - --freq 1000
usleep 300000
check stop 0 '^stopped: 0 0 0 -[1-9][0-9]*$' '' x4ctl stop
if settle 50; then pass stop-released; else fail stop-released "port still held"; fi

# ---- the emergency halt reaches another program's controller ---------------------------
# The same binary under another name is "another program" to x4ctl: no
# request by signal, only the module's emergency halt (a read-only open).
cp "$(command -v x4ctl)" "$tmp/mover"
"$tmp/mover" jog 2 + --freq 1000 >"$out" 2>&1
mpid=$(sed -n 's/.*background as PID \([0-9]*\).*/\1/p' "$out")
usleep 300000
check estop-list-holder 0 "^/dev/x4step0  parport0  ABI [0-9]*  controlled by PID $mpid (mover)\$" '' x4ctl list
check estop-list-holder-json 0 "\"controlled\":true,\"controller\":{\"pid\":$mpid,\"name\":\"mover\"}" '' x4ctl list --json
x4ctl watch --json -n 3 >"$tmp/estop.watch" 2>&1 &
wpid=$!
port_open "$wpid"
check estop-other-program 0 '^stopped: 0 [1-9][0-9]* 0 0$' '' x4ctl stop
wait "$wpid"
has estop-event "$tmp/estop.watch" '^{"schema":1,"seq":[0-9]*,"time_ns":[0-9]*,"type":"brake","axes":\[2\],"how":"emergency","value":1,'
has estop-ended-stopped "$tmp/estop.watch" '"type":"move_ended","axes":\[2\],"how":"stopped"'
steps=$(field steps)
usleep 200000
expect_field estop-no-step-after steps "$steps"
kill "$mpid" 2>/dev/null
if settle 50; then pass estop-released; else fail estop-released "port still held"; fi
"$tmp/mover" jog 2 - --freq 1000 --ramp 100 >"$out" 2>&1
mpid=$(sed -n 's/.*background as PID \([0-9]*\).*/\1/p' "$out")
usleep 300000
check ebrake-other-program 0 '^braked: 0 [0-9-]* 0 0$' '' x4ctl brake
kill "$mpid" 2>/dev/null
if settle 50; then pass ebrake-released; else fail ebrake-released "port still held"; fi

# A background controller killed with SIGTERM brakes, and lets go of the port.
x4ctl jog 1 + --freq 1000 >"$out" 2>&1
pid=$(sed -n 's/.*background as PID \([0-9]*\).*/\1/p' "$out")
usleep 300000
if [ -n "$pid" ] && kill "$pid" && settle 50; then pass sigterm-brakes; else fail sigterm-brakes "pid '$pid'"; fi

# ---- jog ------------------------------------------------------------------------------
check jog-wait 0 '^halted (time up): 0 [1-9][0-9]* 0 0$' '' x4ctl jog 2 + --freq 1000 --ramp 10 --time 300 --wait
check jog-background 0 'jog: axis 1 - at 1000 Hz, ramp 20 ms, for 300 ms' '' \
	x4ctl jog 1 - --ramp 20 --time 300
if settle 50; then pass jog-background-ends; else fail jog-background-ends "still running"; fi
steps=$(field steps)
case "$steps" in \[-[1-9]*,0,0,0\]) pass jog-background-steps ;; *) fail jog-background-steps "$steps" ;; esac
check bad-jog-dir 2 '' "jog: direction 'x': use + or -" x4ctl jog 1 x
check bad-jog-axis 2 '' 'jog: axis 5 out of range: use 1 to 4' x4ctl jog 5 +
check bad-jog-freq 2 '' 'jog: frequency too high' x4ctl jog 1 + --freq 20001
check bad-jog-args 2 '' "jog: '1': give an axis letter and a sign" x4ctl jog 1

# ---- keys, out ------------------------------------------------------------------------
check keys 0 '^brake keys: 28 156 and ESC$' '' x4ctl keys 28 156
check keys-clear 0 '^brake keys: ESC only$' '' x4ctl keys
check bad-keys-zero 2 '' 'keys: key code 0 out of range' x4ctl keys 0
check bad-keys-high 2 '' 'keys: key code 300 out of range' x4ctl keys 300
check bad-keys-many 2 '' 'keys: unexpected argument' x4ctl keys 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20 21

x4ctl out 1 on --time 2000 >"$tmp/out1" 2>&1 &
pid=$!
eventually signal1 true
expect_field out-on signal1 true
wait "$pid"
rc=$?
if [ "$rc" = 0 ] && grep -q 'signal 1 (pin 1) on; holding the port for 2000 ms' "$tmp/out1"; then
	pass out-time
else
	fail out-time "exit $rc: $(show "$tmp/out1")"
fi
settle 20
expect_field out-released signal1 false
x4ctl out 2 on >"$tmp/out2" 2>&1 &
pid=$!
eventually signal2 true
expect_field out2-on signal2 true
kill "$pid"
wait "$pid"
rc=$?
if [ "$rc" = 0 ] && grep -q 'released the port' "$tmp/out2"; then pass out-sigterm; else fail out-sigterm "exit $rc"; fi
check bad-out-signal 2 '' 'out: signal 3: use 1 (pin 1) or 2 (pin 14)' x4ctl out 3 on
check bad-out-level 2 '' "out: level 'maybe': use on or off" x4ctl out 1 maybe

# ---- sweep --------------------------------------------------------------------------------
check sweep 0 '^A: 3000 Hz 100 steps done$' '' x4ctl sweep 2 100 2000 3000 500
has sweep-alternates "$out" '^A: 2500 Hz -100 steps done$'
check sweep-down 0 '^A: 2000 Hz -50 steps done$' '' x4ctl sweep 1 50 3000 2000 1000
check bad-sweep-ramp 2 '' 'sweep: ramp too long for the frequency' x4ctl sweep 1 100 20 40 10 --ramp 30
check bad-sweep-step 2 '' 'sweep: frequency step 0 out of range' x4ctl sweep 1 100 200 400 0
check bad-sweep-nosteps 2 '' 'sweep: no steps' x4ctl sweep 1 0 200 400 100

# Start WATCHER... (an x4ctl that ends by itself once it has seen enough),
# its output in OUT, run 'x4ctl ACTION' meanwhile, and give the watcher 5 s
# to end; false (the watcher killed) if it did not.
follow() { # OUT "ACTION" WATCHER...
	f_out=$1 f_action=$2
	shift 2
	"$@" >"$f_out" 2>&1 &
	f_pid=$!
	port_open "$f_pid"
	# shellcheck disable=SC2086
	x4ctl $f_action >/dev/null 2>&1
	f_n=0
	while kill -0 "$f_pid" 2>/dev/null && [ "$f_n" -lt 50 ]; do usleep 100000; f_n=$((f_n + 1)); done
	f_st=0
	kill -0 "$f_pid" 2>/dev/null && kill "$f_pid" && f_st=1
	wait "$f_pid" 2>/dev/null
	return $f_st
}

# ---- monitor follows another controller ---------------------------------------------------
if ! follow "$tmp/mon" "move 300 0 -30 --freq 3000 --ramp 10 --wait" x4ctl monitor --moves 1; then
	fail monitor "did not end after one move: $(show "$tmp/mon")"
elif grep -q '^move ended: steps 300 0 -30 0$' "$tmp/mon"; then
	pass monitor
else
	fail monitor "$(show "$tmp/mon")"
fi

# ---- watch: the port's events, as text and JSON ----------------------------------------------
# A move from another x4ctl: its controller opens, the move starts and ends,
# the controller closes and releases the port: five events.
if follow "$tmp/watch" "move 40 0 -20 --freq 2000 --ramp 10 --wait" x4ctl watch -n 5; then
	pass watch
else
	fail watch "did not end after 5 events: $(show "$tmp/watch")"
fi
has watch-opened "$tmp/watch" '^#[0-9]* [0-9]*\.[0-9]\{6\} controller: opened; at '
has watch-started "$tmp/watch" '^#[0-9]* [0-9.]* move started: axes 1 3, X4Step move; at '
has watch-ended "$tmp/watch" '^#[0-9]* [0-9.]* move ended: axes 1 3, completed; at '
has watch-released "$tmp/watch" '^#[0-9]* [0-9.]* controller: released the port; at '
follow "$tmp/watch" "out 1 on --time 10" x4ctl watch --json -n 3
has watch-json "$tmp/watch" '^{"schema":1,"seq":[0-9]*,"time_ns":[0-9]*,"type":"controller","axes":\[\],"how":"released","value":0,"ambiguous":false,"position":\[[-0-9,]*\]}$'
check bad-watch-count 2 '' 'watch: count 0 out of range' x4ctl watch -n 0

# ---- x4ctl run: every command of the test program -------------------------------------------
script run-go 0 '^done: 300 0 0 0$' '' 's1\nd300\nf3000\nr20\ng\n'
has run-echo "$out" '^1-> g$'
# The manual's second example: axes 1..3 interpolated, at axis 1's frequency and ramp.
script run-interpolated 0 '^done: 1000 500 100 0$' '' 's1\nd1000\nf10000\nr100\ns2\nd500\ns3\nd100\ng\n'
has run-leader "$out" '^G: 1000 500 100 0 at 10000 Hz, ramp 100 ms (leader axis 1)$'
script run-I 0 '^> 2  *-700  *1000  *50  leader$' '' 's1\nd300\nS2\nD-700\ni\n'
has run-I-leader "$out" 'axis 2, 1000 Hz, 50 ms'
script run-M+ 0 '^halted (time up): 0 0 [1-9][0-9]* 0$' '' 's3\nf2000\nr10\nm+ 300\n'
script run-M- 0 '^halted (time up): 0 0 -[1-9][0-9]* 0$' '' 's3\nf2000\nr10\nM- 300\n'
script run-T 0 '^T: [0-9]* moves' '' 's1\nd40\nf4000\nr0\nt 800\n'
script run-A 0 '^A: 2500 Hz -60 steps done$' '' 's2\nd60\nr0\na2000,2500,500\n'
script run-E 0 '^E: pin15=[01] pin13=[01] pin12=[01] pin10=[01] pin11=[01]$' '' 'e\n'
script run-E-time 0 '^E: pin15=' '' 'E 300\n'
script run-H 0 '^Commands of the test program' '' 'h\n'
script run-? 0 '^  Ax,y,z ' '' '?\n'
script run-Q 0 '^1-> q$' '' 's1\nd100\nq\ng\n'
lacks run-Q-stops "$out" '^G:'
script run-O 0 '^O: signal 2 (pin 14) on$' '' 'o2,1\nw200\no2,0\n'
script run-K 0 '^K: brake keys 28 156 and ESC$' '' 'k28,156\nK\n'
script run-W 0 '^1-> w100$' '' 'w100\n'
script run-semicolons 0 '^done: 0 50 0 0$' '' 's2; d50; f5000; r0; g  # a comment\n'
script run-case 0 '^done: 0 0 0 25$' '' 'S4\nD25\nF5000\nR0\nG\n'
script run-C 2 '' 'run: .*:2: C: C needs a terminal' 's1\nc\n'
printf 's1\nd10\nf5000\ng\n' >"$tmp/stdin.x4"
check run-stdin 0 '^done: 10 0 0 0$' '' sh -c "x4ctl run - <$tmp/stdin.x4"

# ---- x4ctl run: bad input, and nothing moves ---------------------------------------------------
ended=$(field moves_ended)
script bad-run-unknown 2 '' 'run: .*:2: x: unknown command: H shows the commands' 's1\nx\nd100\ng\n'
script bad-run-freq 2 '' 'run: .*:3: f30000: frequency too high: use at most 20000 Hz' 's1\nd100\nf30000\ng\n'
script bad-run-freq-low 2 '' 'f9: frequency too low: use at least 10 Hz' 'f9\n'
script bad-run-ramp 2 '' 'r1001: ramp too long: use at most 1000 ms' 'r1001\n'
script bad-run-ramp-freq 2 '' ':5: G: ramp too long for the frequency.*leader axis 1: F20 R50' 's1\nd100\ng\nf20\ng\n'
script bad-run-nosteps 2 '' ':1: G: no steps' 'g\n'
script bad-run-steps 2 '' 'd16777217: path too long' 'd16777217\n'
script bad-run-axis 2 '' 's5: axis 5 out of range: use 1 to 4' 's5\n'
script bad-run-number 2 '' "dx: steps 'x' is not a whole number" 'dx\n'
script bad-run-sweep 2 '' 'a200,500: A needs 3 numbers' 'd100\na200,500\n'
script bad-run-sweep-ramp 2 '' 'A: ramp too long for the frequency' 'd100\nr300\na200,500,20\n'
script bad-run-M 2 '' 'm: M needs a direction' 'm\n'
script bad-run-T 2 '' 'T: no steps' 't 100\n'
script bad-run-G-arg 2 '' 'g1: G takes no argument' 'g1\n'
script bad-run-O 2 '' 'o3,1: signal 3' 'o3,1\n'
script bad-run-K 2 '' 'k0: key code 0 out of range' 'k0\n'
check bad-run-file 1 '' 'run: cannot read /nonexistent.x4' x4ctl run /nonexistent.x4
expect_field bad-run-nothing-moved moves_ended "$ended"

# A move halted in a script ends the script: the commands after it do not run.
printf 's1\nd1000000\nf1000\ng\nd10\ng\n' >"$tmp/long.x4"
x4ctl run "$tmp/long.x4" >"$tmp/long.out" 2>"$tmp/long.err" &
pid=$!
usleep 500000
x4ctl brake >/dev/null 2>&1
wait "$pid"
rc=$?
if [ "$rc" = 1 ] && grep -q 'run: .*:4: G: halted (brake request) at [0-9]* of 1000000 steps' "$tmp/long.err" &&
	! grep -q '^done' "$tmp/long.out"; then
	pass run-halted-ends-script
else
	fail run-halted-ends-script "exit $rc: $(show "$tmp/long.err")"
fi
settle 50

# ---- interactive mode from a pipe: errors are reported, the session goes on ----------------------
printf 's1\nd50\nf5000\nr0\nf30000\nd60;f40000;g\ng\nq\n' >"$tmp/session"
check interactive 0 '^done: 50 0 0 0$' 'error: f30000: frequency too high: use at most 20000 Hz' \
	sh -c "x4ctl <$tmp/session"
lacks interactive-line-dropped "$out" '^done: 60'
has interactive-error "$err" 'f40000: frequency too high'
check interactive-lpt-arg 0 '^1-> q$' '' sh -c "echo q | x4ctl 1"

settle 50

# ---- timing and mode: per-port settings the module keeps after x4ctl exits ---------------------
check timing-show 0 '^dir setup *[0-9]* ns$' '' x4ctl timing
check timing-set 0 '^pulse *5000 ns$' '' x4ctl timing --pulse 5000 --space 95000 --hold 3000
has timing-set-space "$out" '^space *95000 ns$'
has timing-set-max "$out" '^max freq *10000 Hz$'
check timing-kept 0 '^space *95000 ns$' '' x4ctl timing
has timing-kept-hold "$out" '^dir hold *3000 ns$'
check timing-partial 0 '^dir setup *20000 ns$' '' x4ctl timing --setup 20000
has timing-partial-pulse "$out" '^pulse *5000 ns$'
has timing-partial-hold "$out" '^dir hold *3000 ns$'
check timing-json 0 \
	'^{"schema":1,"device":"/dev/x4step0","pulse_ns":5000,"space_ns":95000,"dir_setup_ns":20000,"dir_hold_ns":3000,"mode":"clock-dir","max_freq_hz":10000}$' \
	'' x4ctl timing --json
check timing-move-fits 0 '^done: 50 0 0 0$' '' x4ctl move 50 --freq 10000 --ramp 0 --wait
check timing-move-too-fast 1 '' \
	'^x4ctl: move: frequency too high for the step timing: 12000 Hz, .* allow at most 10000 Hz' \
	x4ctl move 50 --freq 12000 --ramp 0 --wait
check timing-jog-too-fast 1 '' 'jog: frequency too high for the step timing' x4ctl jog 1 + --freq 15000 --time 100
check bad-timing-pulse 2 '' 'timing: pulse 500 out of range: use 0 (symmetric clock) or 1000 to 1000000 ns' \
	x4ctl timing --pulse 500
check bad-timing-pulse-high 2 '' 'timing: pulse 1000001 out of range' x4ctl timing --pulse 1000001
check bad-timing-space 2 '' 'timing: space 1000001 out of range: use 0 to 1000000 ns' x4ctl timing --space 1000001
check bad-timing-setup 2 '' 'timing: setup -1 out of range: use 0 to 1000000 ns' x4ctl timing --setup -1
check bad-timing-hold 2 '' "timing: hold 'x' is not a whole number" x4ctl timing --hold x
check bad-timing-arg 2 '' "timing: unexpected argument '5000'" x4ctl timing 5000
check bad-timing-unchanged 0 '^pulse *5000 ns$' '' x4ctl timing
has bad-timing-unchanged-space "$out" '^space *95000 ns$'

check mode-show 0 '^clock-dir: ' '' x4ctl mode
check mode-set 0 '^smc-phase: ' '' x4ctl mode smc-phase
check mode-kept 0 '^smc-phase: ' '' x4ctl mode
check mode-timing-json 0 '"mode":"smc-phase","max_freq_hz":20000}$' '' x4ctl timing --json
check phase-move 0 '^done: 3 -2 0 0$' '' x4ctl move 3 -2 0 0 --freq 1000 --ramp 0 --wait
expect_field phase-move-steps steps '[3,-2,0,0]'
# Pulse and space do not apply to phase patterns.
check phase-move-fast 0 '^done: 0 0 40 0$' '' x4ctl move 0 0 40 --freq 12000 --ramp 0 --wait
ended=$(field moves_ended)
check phase-axis4 1 '' '^x4ctl: move: axis 4 cannot move in smc-phase mode: the SMC800/SMC1500 boards drive axes 1 to 3' \
	x4ctl move 0 0 1 5 --freq 1000 --ramp 0 --wait
check phase-axis4-background 1 '' 'move: axis 4 cannot move in smc-phase mode' x4ctl move 0 0 0 5 -b
check phase-jog-axis4 1 '' 'jog: axis 4 cannot move in smc-phase mode' x4ctl jog 4 + --time 100
script phase-run-axis4 1 '' 'run: .*:3: axis 4 cannot move in smc-phase mode' 's4\nd5\ng\n'
expect_field phase-axis4-nothing-moved moves_ended "$ended"
check mode-hold 0 '^smc-hold: ' '' x4ctl mode smc-hold
check phase-hold-move 0 '^done: 0 -20 0 0$' '' x4ctl move 0 -20 --freq 2000 --ramp 0 --wait
check bad-mode 2 '' "mode: no mode 'smc': use clock-dir, smc-phase, smc-hold" x4ctl mode smc
check bad-mode-args 2 '' "mode: unexpected argument 'smc-hold'" x4ctl mode clock-dir smc-hold
check bad-mode-unchanged 0 '^smc-hold: ' '' x4ctl mode

# Back to X4Step's settings for whatever runs next.
check mode-restore 0 '^clock-dir: ' '' x4ctl mode clock-dir
check timing-restore 0 '^pulse *0 ns (symmetric clock)$' '' \
	x4ctl timing --pulse 0 --space 0 --setup 100000 --hold 0
has timing-restore-space "$out" '^space *0 ns$'
has timing-restore-setup "$out" '^dir setup *100000 ns$'
has timing-restore-max "$out" '^max freq *20000 Hz$'
check mode-restore-axis4 0 '^done: 0 0 0 5$' '' x4ctl move 0 0 0 5 --freq 1000 --ramp 0 --wait

# ---- positioning: profile, zero, goto, halt, limits, status (ProStep4) ---------------------------
# No switch is wired on QEMU's port (the machine section at the end has them).
check profile-show 0 '^vm *1000 steps/s (maximum)$' '' x4ctl profile 1
check profile-set 0 '^vm *4000 steps/s (maximum)$' '' x4ctl profile 1 --vm 4000 --a0 40000 --ae 20000
has profile-set-a0 "$out" '^a0 *40000 steps/s^2 (ramp 0.100 s)$'
has profile-set-ae "$out" '^ae *20000 steps/s^2 (ramp 0.200 s)$'
check profile-kept 0 '^vm *4000 steps/s' '' x4ctl profile 1
check bad-profile-vm 2 '' '^x4ctl: profile: vm 100001 out of range: use 1 to 100000 steps/s$' x4ctl profile 1 --vm 100001
check bad-profile-fit 2 '' 'profile: v0 5000, ve 0, vm 4000, .* do not fit together' x4ctl profile 1 --v0 5000
check bad-profile-unchanged 0 '^v0 *0 steps/s' '' x4ctl profile 1
check zero 0 '^axis 1 at 0, synchronized$' '' x4ctl zero 1 2 3 4
has zero-4 "$out" '^axis 4 at 0, synchronized$'
ended=$(field moves_ended)
check goto 0 '^done: 1000 -200 0 0$' '' x4ctl goto 1=1000 2=-200
has goto-header "$out" '^goto: 1 to 1000, 2 to -200$'
check goto-relative 0 '^done: 900 -200 0 50$' '' x4ctl goto 1=-100 4=50 --relative
has goto-relative-header "$out" '^goto: 1 by -100 to 900, 4 by 50 to 50$'
check goto-there 0 '^done: 900 -200 0 50$' '' x4ctl goto 1=900
check status-coordinates 0 '^axis 1 *900, synchronized, idle$' '' x4ctl status
has status-coordinates-4 "$out" '^axis 4 *50, synchronized, idle$'
check status-json-axes 0 '"axes":\[{"axis":1,"position":900,"velocity":0,"running":false,"synced":true,' '' \
	x4ctl status --json
check goto-no-wait 0 'running in the background as PID' '' x4ctl goto 3=4000 --no-wait
has goto-no-wait-header "$out" '^goto: 3 to 4000$'
eventually active true
check halt 0 '^braked: 3=[0-9]*$' '' x4ctl halt 3
if settle 50; then pass halt-released; else fail halt-released "port still held"; fi
check halt-idle 1 '' '^x4ctl: halt: axis 3 is not moving$' x4ctl halt 3
check halt-idle-two 1 '' '^x4ctl: halt: axes 1, 3 are not moving$' x4ctl halt 1 3
check goto-brake-start 0 'running in the background' '' x4ctl goto 2=5000 --no-wait
eventually active true
check goto-brake 0 '^braked: ' '' x4ctl brake
if settle 50; then pass goto-brake-released; else fail goto-brake-released "port still held"; fi
check zero-at 0 '^axis 3 at -40, synchronized$' '' x4ctl zero 3 --at -40
check bad-goto-twice 2 '' "^x4ctl: goto: axis 3 given twice$" x4ctl goto 3=0 3=-40
check bad-goto-form 2 '' "^x4ctl: goto: '3': use AXIS=POSITION, e.g. 1=1000$" x4ctl goto 3
check bad-goto-range 2 '' 'goto: position 2147483648 out of range' x4ctl goto 1=2147483648
check bad-halt-axis 2 '' 'halt: axis 5 out of range: use 1 to 4' x4ctl halt 5
check limits-show 0 '^axis 1 *ref none, E+ none, E- none$' '' x4ctl limits
has limits-show-inputs "$out" '^input 5 *pin 11 [A-Z]*, free (X4GetIn only)$'
check home-no-ref 1 '' '^x4ctl: home: axis 1 has no reference switch' x4ctl home 1
check limits-set 0 '^axis 2 *ref input 5 (pin 11), E+ none, E- input 4 (pin 10)$' '' x4ctl limits 2 --ref 5 --minus 4
check limits-nc 0 '^input 4 *pin 10 [A-Z]*, normally closed, [a-z]*, E- 2$' '' x4ctl limits --nc 4
check limits-kept 0 '^axis 2 *ref input 5 (pin 11)' '' x4ctl limits
check limits-clear 0 '^axis 2 *ref none, E+ none, E- none$' '' x4ctl limits 2 --ref 0 --minus none --nc none
check bad-limits-input 2 '' 'limits: input 6 out of range: use 1 to 5' x4ctl limits 1 --plus 6
check bad-limits-noaxis 2 '' 'limits: --ref, --plus and --minus need an AXIS' x4ctl limits --ref 1
check bad-home-vref 2 '' 'home: vref1 0 out of range' x4ctl home 1 --vref1 0
# Back to the default profile and 0 for whatever runs next.
check profile-restore 0 '^vm *1000 steps/s (maximum)$' '' x4ctl profile 1 --vm 1000 --a0 1000 --ae 1000
check zero-restore 0 '^axis 4 at 0, synchronized$' '' x4ctl zero 1 2 3 4

# ---- the machine: home and limit switches on the test-only virtual port ---------------------------
# With x4vport.ko in $X4MOD (run-suite: --module @FIXTURES@/x4vport.ko) the
# virtual port is a machine whose switches drive the inputs; without it, skipped.
vmod=${X4MOD:-/lib/x4}/x4vport.ko
V=/sys/kernel/debug/x4vport
if [ -r "$vmod" ]; then
	mount -t debugfs none /sys/kernel/debug 2>/dev/null
	if insmod "$vmod" && [ -d "$V" ]; then pass machine-setup; else fail machine-setup "insmod $vmod"; fi
	vlpt=$(($(cat "$V/port") + 1))
	for _ in 1 2 3 4 5 6 7 8 9 10; do [ -c "/dev/x4step$((vlpt - 1))" ] && break; usleep 100000; done
	m() { x4ctl -p "$vlpt" "$@"; }
	at() { cut -d' ' -f"$1" "$V/positions"; } # the machine's position of axis $1, from the edges
	coordinate() { m status --json | sed -n "s/.*\"axis\":$1,\"position\":\([-0-9]*\).*/\1/p"; }
	same() {                                   # NAME GOT WANT
		if [ "$2" = "$3" ]; then pass "$1"; else fail "$1" "'$2', want '$3'"; fi
	}

	# Reference run: REF of axis 1 on input 1, a switch active at -500 and below (5 steps hysteresis).
	echo "add 1 0 below -500 5 no" >"$V/switches"
	check machine-ref 0 '^axis 1 *ref input 1 (pin 15), E+ none, E- none$' '' m limits 1 --ref 1
	check machine-home 0 '^done: axis 1 at 0, synchronized$' '' m home 1 --vref1 -2000 --vref2 200 --sref 10000
	home=$(at 1)
	case "$home" in -49[0-4]) pass machine-home-where ;; *) fail machine-home-where "machine at $home" ;; esac
	check machine-home-status 0 '^axis 1 *0, synchronized, idle$' '' m status
	check machine-home-goto 0 '^done: 100 ' '' m goto 1=100
	same machine-home-edges "$(at 1)" "$((home + 100))"

	# E+ of axis 2 on input 2 at 300: goto stops there, with the error; backing off works.
	echo "add 2 1 above 300 0 no" >"$V/switches"
	check machine-limit-set 0 '^axis 2 *ref none, E+ input 2 (pin 13), E- none$' '' m limits 2 --plus 2
	check machine-zero 0 '^axis 2 at 0, synchronized$' '' m zero 2
	check machine-limit 1 '' '^x4ctl: goto: axis 2: stopped at E+ at 30[0-9] (target 1000); coordinates 100 30[0-9] 0 0$' \
		m goto 2=1000
	# A limit hit costs the synchronization.
	check machine-limit-status 0 '^axis 2 *30[0-9], not synchronized, idle, error: stopped at E+$' '' m status
	hit=$(at 2)
	same machine-limit-edges "$hit" "$(coordinate 2)"
	check machine-limit-again 1 '' '^x4ctl: goto: ' m goto 2=400 # toward the active limit: not a step
	same machine-limit-again-edges "$(at 2)" "$hit"
	check machine-back-off 0 '^done: 100 0 0 0$' '' m goto 2=0
	same machine-back-off-edges "$(at 2)" 0

	# A normally closed switch: with the input taken as normally open it is "active" at once.
	echo "clear; add 2 1 above 300 0 nc" >"$V/switches"
	check machine-nc-wrong 1 '' '^x4ctl: goto: ' m goto 2=100
	same machine-nc-wrong-edges "$(at 2)" 0
	check machine-nc-set 0 '^input 2 *pin 13 HIGH, normally closed, idle, E+ 2$' '' m limits --nc 2
	check machine-nc-goto 0 '^done: 100 100 0 0$' '' m goto 2=100
	check machine-nc-limit 1 '' 'goto: axis 2: stopped at E+ at 30[0-9] (target 1000)' m goto 2=1000

	# sref: REF of axis 3 on input 3, its switch far beyond reach.
	echo "add 3 2 below -100000 0 no" >"$V/switches"
	m limits 3 --ref 3 >/dev/null
	check machine-sref 1 '' '^x4ctl: home: axis 3: reference travel exceeded at -10[0-9][0-9]: ' \
		m home 3 --vref1 -5000 --sref 1000
	same machine-sref-edges "$(at 3)" "$(coordinate 3)"
	check machine-sref-status 0 '^axis 3 *-10[0-9][0-9], not synchronized, idle, error: reference travel exceeded$' \
		'' m status

	echo clear >"$V/switches"
	m limits 1 --ref 0 >/dev/null
	m limits 2 --plus 0 --nc none >/dev/null
	m limits 3 --ref 0 >/dev/null

	# x4ctl path (issue 18): checked first, then streamed; the machine's
	# edges end where the lines add up, on every axis.
	p1=$(at 1) p2=$(at 2) p3=$(at 3)
	printf '# a square, then a helix-like piece\n1000 0\n0 1000 speed=3000\n-1000 0\n0 -1000\n300 -200 77 # diagonal\n' \
		>"$tmp/square.path"
	check path-check 0 'square.path: 5 segments, 4369 steps along the path: OK' '' m path --check "$tmp/square.path"
	same path-check-moves-nothing "$(at 1) $(at 2) $(at 3)" "$p1 $p2 $p3"
	check path-run 0 '^path: done, 5 of 5 segments, at ' '' m path -s 2000 -a 20000 "$tmp/square.path"
	same path-edges "$(at 1) $(at 2) $(at 3)" "$((p1 + 300)) $((p2 - 200)) $((p3 + 77))"
	echo 50 >"$tmp/one.path"
	check path-json 0 '^{"schema":1,"state":"idle","line":0,"done":1,"total":1,' '' m path --json "$tmp/one.path"
	same path-json-edges "$(at 1)" "$((p1 + 350))"
	printf '100 0\n0 1x\n' >"$tmp/bad.path"
	check path-bad-line 2 '' "bad.path:2:3: '1x' is no step count" m path "$tmp/bad.path"
	same path-bad-line-moves-nothing "$(at 1) $(at 2)" "$((p1 + 350)) $((p2 - 200))"
	printf '100 speed=45000 accel=1000000\n' >"$tmp/fast.path"
	check path-too-fast 1 '' "fast.path:1: its leader axis would step at 45000 steps/s; the port's step timing allows" \
		sh -c "x4ctl -p $vlpt timing --pulse 20000 --space 20000 >/dev/null && x4ctl -p $vlpt path $tmp/fast.path"
	m timing --pulse 0 --space 0 >/dev/null

	# x4ctl gcode (issue 20): a machine in mm (Y reversed) on this port; the
	# program is planned from where the motors stand, and they end at
	# round(programmed end x SCALE) exactly, after lines and arcs.
	cat >"$tmp/mill.ini" <<-EOF
		[X4STEP]
		PORT = LPT$vlpt
		ARC_TOLERANCE = 0.01
		JUNCTION_DEVIATION = 0.02
		[TRAJ]
		COORDINATES = XYZ
		LINEAR_UNITS = mm
		[AXIS_X]
		MIN_LIMIT = -1000
		MAX_LIMIT = 1000
		MAX_VELOCITY = 50
		MAX_ACCELERATION = 500
		[AXIS_Y]
		MIN_LIMIT = -1000
		MAX_LIMIT = 1000
		MAX_VELOCITY = 50
		MAX_ACCELERATION = 500
		[AXIS_Z]
		MIN_LIMIT = -1000
		MAX_LIMIT = 1000
		MAX_VELOCITY = 20
		MAX_ACCELERATION = 200
		[JOINT_0]
		MOTOR = 1
		SCALE = 100
		[JOINT_1]
		MOTOR = 2
		SCALE = -100
		[JOINT_2]
		MOTOR = 3
		SCALE = 100
	EOF
	# 200 moves of 0.3 steps in between: rounded move by move, none would step.
	{
		printf 'G21 G90\nG0 X10 Y5\nG1 X12.345 Y-3.21 Z1.5 F1200\nG2 X2.345 Y-3.21 I-5 J0\nG91 G1\n'
		i=0
		while [ "$i" -lt 200 ]; do
			echo 'X0.003 Y0.003'
			i=$((i + 1))
		done
		printf 'G90 G1 X3.333 Y-1.117 Z0.5\nM2\n'
	} >"$tmp/part.ngc"
	a1=$(at 1) a2=$(at 2) a3=$(at 3) c1=$(coordinate 1) c2=$(coordinate 2) c3=$(coordinate 3)
	check gcode-check 0 'part.ngc: OK: 207 lines, ' '' m gcode -m "$tmp/mill.ini" --check "$tmp/part.ngc"
	same gcode-check-moves-nothing "$(at 1) $(at 2) $(at 3)" "$a1 $a2 $a3"
	check gcode-run 0 '^gcode: done in [0-9:]*, estimated [0-9:]*, at X3.33 Y-1.12 Z0.5 (mm)$' '' \
		x4ctl gcode -m "$tmp/mill.ini" --svg "$tmp/part.svg" "$tmp/part.ngc"
	# The plot: the planned cuts and rapids, the positions the module
	# reported, the largest deviation (x4ctl.gcode_svg reads the rest).
	for c in cut rapid "done"; do
		has "gcode-svg-$c" "$tmp/part.svg" "class=\"$c\"[^>]* d=\"M-\{0,1\}[0-9]"
	done
	has gcode-svg-deviation "$tmp/part.svg" 'id="deviation" data-value="[0-9]'
	# X 3.333 * 100 = 333; Y -1.117 * -100 = 111.7 -> 112; Z 50.
	same gcode-edges "$(at 1) $(at 2) $(at 3)" "$((a1 + 333 - c1)) $((a2 + 112 - c2)) $((a3 + 50 - c3))"
	printf 'G91 G1 X0.5 F600\nM2\n' >"$tmp/nudge.ngc"
	x4ctl gcode --json -m "$tmp/mill.ini" "$tmp/nudge.ngc" >"$tmp/gcode.json"
	has gcode-json "$tmp/gcode.json" '^{"schema":1,"result":"done","position":{"X":3.83,'
	sed 's/^/X4JSON /' "$tmp/gcode.json"
	same gcode-json-edges "$(at 1)" "$((a1 + 383 - c1))"
	printf 'G0 X10\nG0 X2000\nM2\n' >"$tmp/far.ngc"
	check gcode-soft-limit 2 '' 'far.ngc:2:1: X 2000 is beyond the soft limit \[AXIS_X\] MAX_LIMIT 1000' \
		x4ctl gcode -m "$tmp/mill.ini" "$tmp/far.ngc"
	same gcode-soft-limit-moves-nothing "$(at 1)" "$((a1 + 383 - c1))"

	# Homed first and persistent offsets (issue 30): Z of this machine has a home switch.
	# The module keeps whether an axis is referenced between commands: an emergency
	# stop loses it, zero gives it back; touch-off's offset is read by the next gcode.
	cp "$tmp/mill.ini" "$tmp/hmill.ini"
	printf 'HOME_SEARCH_VEL = 1\nHOME_LATCH_VEL = -0.5\nHOME_INPUT = 3\n[RS274NGC]\nPARAMETER_FILE = hmill.var\n' \
		>>"$tmp/hmill.ini"
	printf 'G0 Z0\nM2\n' >"$tmp/z0.ngc"
	check homed-first-jog 0 'running in the background' '' m jog 3 + --freq 1000
	usleep 200000
	check homed-first-stop 0 '^stopped: ' '' m stop
	check homed-first-unsynced 0 '^axis 3 .*not synchronized' '' m status
	z=$(at 3)
	check homed-first-refused 1 '' 'z0.ngc: Z is not homed: home first: x4ctl home --machine .*hmill.ini (a machine without home switches' \
		x4ctl gcode -m "$tmp/hmill.ini" "$tmp/z0.ngc"
	same homed-first-moves-nothing "$(at 3)" "$z"
	check homed-first-zero 0 '^axis 3 at 0, synchronized$' '' m zero 3
	check touch-off 0 '^touch-off: G54 Z 0.5: Z stands at work -0.5, machine 0 (mm)$' '' \
		x4ctl touch-off -m "$tmp/hmill.ini" Z=-0.5
	has touch-off-var "$tmp/hmill.var" '^5223	0.500000$'
	check homed-first-runs 0 '^gcode: done in [0-9:]*, estimated [0-9:]*, at X[-0-9.]* Y[-0-9.]* Z0.5 (mm)$' '' \
		x4ctl gcode -m "$tmp/hmill.ini" "$tmp/z0.ngc"
	same touch-off-edges "$(at 3)" "$((z + 50))"
fi

settle 50
if [ "$failed" = 0 ]; then echo "x4ctl guest tests: all passed"; else echo "x4ctl guest tests: FAILED"; fi
exit "$failed"
