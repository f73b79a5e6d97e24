#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins x4vctl
#: flags --module @FIXTURES@/x4vport.ko
#: seconds 30
#
# Guest test of the virtual port (tests/qemu/run-suite.sh -t vport; runs under tests/qemu/run-guest.sh,
# which has loaded parport and parport_pc, so the virtual port is parport1):
# x4vport's debugfs files, x4step on the virtual port (open, a move through
# the hard-irq timer, inputs), the machine (positions counted from the
# clock edges, switches on the inputs), removal of the port while x4step
# is attached, open, and moving, and the port alone as parport0. Prints
# PASS/FAIL lines; exits with the number of failures.

fails=0
check() { # DESCRIPTION COMMAND...
	d=$1
	shift
	if "$@"; then
		echo "PASS $d"
	else
		echo "FAIL $d"
		fails=$((fails + 1))
	fi
}
# Clock rising edges of axis 1 (data bit 1) in a trace on stdin:
# "EDGES MEAN_NS MIN_NS MAX_NS" of the periods between them.
edges() {
	awk '$2 == "d" {
		h = substr($3, 3)
		v = (index("0123456789abcdef", substr(h, 1, 1)) - 1) * 16 +
		    index("0123456789abcdef", substr(h, 2, 1)) - 1
		c = int(v / 2) % 2
		if (c && !p) {
			e++
			if (last) { d = $1 - last; s += d; n++
				if (!mn || d < mn) mn = d
				if (d > mx) mx = d }
			last = $1
		}
		p = c
	}
	END { printf "%d %.0f %d %d\n", e, n ? s / n : 0, mn, mx }'
}
D=/sys/kernel/debug/x4vport
mount -t debugfs none /sys/kernel/debug
echo "kernel $(uname -r)"

check "insmod x4vport" insmod "$X4MOD/x4vport.ko"
check "debugfs dir" [ -d "$D" ]
N=$(cat "$D/port")
check "port is parport1 (parport_pc has 0)" [ "$N" = 1 ]
echo "after announce: data=$(cat "$D/data") control=$(cat "$D/control")" \
	"status=$(cat "$D/status") pins=$(cat "$D/pins")" \
	"count=$(cat "$D/count") overruns=$(cat "$D/overruns")"
check "initial status 0x78" [ "$(cat "$D/status")" = 0x78 ]
check "initial pins 0x1f" [ "$(cat "$D/pins")" = 0x1f ]
check "initial positions 0 0 0 0" [ "$(cat "$D/positions")" = "0 0 0 0" ]
check "initial switches none" [ -z "$(cat "$D/switches")" ]

check "insmod x4step" insmod "$X4MOD/x4step.ko"
sleep 1
check "/dev/x4step$N exists" [ -c "/dev/x4step$N" ]
check "/dev/x4step0 (parport_pc) exists" [ -c /dev/x4step0 ]
check "x4step$N sits under the virtual port's device in sysfs" \
	[ "$(readlink -f "/sys/class/x4step/x4step$N/device")" = "$(readlink -f /sys/bus/platform/devices/x4vport)" ]

# Inputs: pins -> status register -> X4GetIn through x4step.
for p in 0x1f 0x00 0x10 0x0f 0x01 0x02 0x04 0x08 0x15; do
	echo "$p" >"$D/pins"
	got=$(x4vctl "/dev/x4step$N" inputs | sed -n 's/inputs=\(0x..\).*/\1/p')
	check "pins $p -> status $(cat "$D/status") -> X4GetIn $got" [ "$got" = "$p" ]
done
# A read-only status read leaves a port that x4step has not claimed alone
# (lp or ppdev may own it): no register read; the levels last read by a
# controller come back, marked stale.
echo 0x15 >"$D/pins"
echo >"$D/clear"
got=$(x4vctl "/dev/x4step$N" inputs-ro)
check "read-only, no controller: $got, no register read (reads $(cat "$D/reads"))" \
	[ "$got $(cat "$D/reads")" = "inputs=0x15 err=0 stale=1 0" ]
echo 0x0a >"$D/pins"
got=$(x4vctl "/dev/x4step$N" inputs-ro)
check "read-only, no controller, pins changed: still the last read, stale ($got)" \
	[ "$got $(cat "$D/reads")" = "inputs=0x15 err=0 stale=1 0" ]
exec 3<>"/dev/x4step$N"
echo >"$D/clear"
got=$(x4vctl "/dev/x4step$N" inputs-ro)
r=$(cat "$D/reads")
check "read-only beside a controller: live ($got)" [ "$got" = "inputs=0x0a err=0 stale=0" ]
check "... read from the port (reads $r)" [ "$r" -gt 0 ]
exec 3>&-
echo 0x07 >"$D/status"
echo 0x1f >"$D/pins"
check "pins write keeps status bits 0..2" [ "$(cat "$D/status")" = 0x7f ]
echo 0x78 >"$D/status"
check "pins 0x20 rejected" sh -c "! echo 0x20 2>/dev/null >$D/pins"
check "status 0x100 rejected" sh -c "! echo 0x100 2>/dev/null >$D/status"

# Opening read-write claims the port and writes the registers.
echo >"$D/clear"
check "clear: count 0" [ "$(cat "$D/count")" = 0 ]
exec 3<>"/dev/x4step$N"
echo "trace after open:"
cat "$D/trace"
check "open wrote control" grep -q ' c ' "$D/trace"
check "control after open 0x0b (pins 1, 14, 16, 17 low)" [ "$(cat "$D/control")" = 0x0b ]
exec 3>&-
echo "trace after close:"
cat "$D/trace"

# A move through the hard-irq hrtimer.
echo >"$D/clear"
check "move 200 steps" x4vctl "/dev/x4step$N" move 200 5000 0
cat "$D/trace" >/tmp/t
n=$(wc -l </tmp/t)
echo "move trace: $n entries, $(grep -c ' d ' /tmp/t) data," \
	"$(grep -c ' c ' /tmp/t) control, overruns $(cat "$D/overruns")"
# shellcheck disable=SC2046 # split into the four numbers
set -- $(edges </tmp/t)
check "200 clock rising edges on axis 1 (got $1)" [ "$1" = 200 ]
echo "info: clock period mean $2 ns, min $3, max $4 (200000 nominal; exact only under --icount)"
# shellcheck disable=SC2016 # awk's own variables
check "timestamps non-decreasing" awk 'NR > 1 && $1 < prev { exit 1 } { prev = $1 }' /tmp/t
check "trace_pipe gives the same lines" [ "$(wc -l <"$D/trace_pipe")" = "$n" ]
check "trace_pipe consumed all" [ "$(cat "$D/count")" = 0 ]
check "trace_pipe empty: end of file" [ "$(wc -l <"$D/trace_pipe")" = 0 ]

# Readers while the timer writes.
x4vctl "/dev/x4step$N" move 2000 20000 100 &
mp=$!
for _ in 1 2 3 4 5 6 7 8; do
	cat "$D/trace" >/dev/null
	cat "$D/trace_pipe" >/dev/null
done
check "move with concurrent readers" wait $mp
check "overruns 0" [ "$(cat "$D/overruns")" = 0 ]

# The machine: positions from the clock edges, switches on the inputs.
P=$D/positions
S=$D/switches
wr() { echo "$2" 2>/dev/null >"$1"; } # FILE TEXT: succeeds if the write does
inp() { x4vctl "/dev/x4step$N" inputs | sed -n 's/inputs=\(0x..\).*/\1/p'; }
bit() { echo $(((${1:-} >> $2) & 1)); } # INPUTS BIT
go() { x4vctl "/dev/x4step$N" move "$1" 5000 0 >/dev/null; }
# Axis 1 rising edges before the first status entry of a trace on stdin,
# that entry's value and the number of status entries: "EDGES VAL COUNT".
first_status() {
	awk '$2 == "s" { if (!n++) { v = $3; at = e } }
	$2 == "d" {
		h = substr($3, 3)
		x = (index("0123456789abcdef", substr(h, 1, 1)) - 1) * 16 +
		    index("0123456789abcdef", substr(h, 2, 1)) - 1
		c = int(x / 2) % 2
		if (c && !p) e++
		p = c
	}
	END { printf "%d %s %d\n", at, v, n }'
}
echo 0x1f >"$D/pins"
check "the moves so far: 2200 0 0 0 (got $(cat "$P"))" [ "$(cat "$P")" = "2200 0 0 0" ]
check "place the machine at 0" wr "$P" "0 0 0 0"
check "machine at 0 0 0 0" [ "$(cat "$P")" = "0 0 0 0" ]
check "machine: move +300" go 300
check "positions 300 0 0 0 (got $(cat "$P"))" [ "$(cat "$P")" = "300 0 0 0" ]
check "machine: move -100" go -100
check "positions 200 0 0 0 (got $(cat "$P"))" [ "$(cat "$P")" = "200 0 0 0" ]

# An NO switch above 250 with 5 steps of hysteresis on input 0 (pin 15).
check "add 1 0 above 250 5 no" wr "$S" "add 1 0 above 250 5 no"
check "listed, idle (got '$(cat "$S")')" [ "$(cat "$S")" = "1 0 above 250 5 no idle" ]
i=$(inp)
check "NO switch idle: input 0 low, the others as pins (got $i)" [ "$i" = 0x1e ]
echo >"$D/clear"
check "move +100 onto the switch" go 100
i=$(inp)
check "position 300: input 0 high (got $i)" [ "$(bit "$i" 0)" = 1 ]
check "listed active" [ "$(cat "$S")" = "1 0 above 250 5 no active" ]
# shellcheck disable=SC2046 # split into the three fields
set -- $(first_status <"$D/trace")
check "status changed once (got $3), to 0x78 (got $2), at the 50th step (got $1)" \
	[ "$1 $2 $3" = "50 0x78 1" ]
go -52
check "248: still active (hysteresis)" [ "$(bit "$(inp)" 0)" = 1 ]
go -3
check "245: still active" [ "$(bit "$(inp)" 0)" = 1 ]
go -1
check "244: released" [ "$(bit "$(inp)" 0)" = 0 ]
go 5
check "249: still released" [ "$(bit "$(inp)" 0)" = 0 ]
go 1
check "250: active again" [ "$(bit "$(inp)" 0)" = 1 ]
check "positions 250 0 0 0 (got $(cat "$P"))" [ "$(cat "$P")" = "250 0 0 0" ]

# Placing the machine; one switch per axis.
check "write positions" wr "$P" "10 -20 30 -40"
check "positions read back" [ "$(cat "$P")" = "10 -20 30 -40" ]
check "placing released input 0" [ "$(bit "$(inp)" 0)" = 0 ]
check "switches per axis" wr "$S" "clear; add 2 1 below -10 0 no
add 3 2 above 30 0 no
add 4 3 below -41 0 no"
i=$(inp)
check "axes 2, 3 active, 4 idle, inputs 0, 4 as pins (got $i)" [ "$i" = 0x17 ]
wr "$P" "10 -9 29 -41"
i=$(inp)
check "axes 2, 3 idle, 4 active (got $i)" [ "$i" = 0x19 ]
check "switches listed" [ "$(tr '\n' , <"$S")" = \
	"2 1 below -10 0 no idle,3 2 above 30 0 no idle,4 3 below -41 0 no active," ]
check "positions: 3 numbers rejected" sh -c "! echo 1 2 3 2>/dev/null >$P"
check "positions: 5 numbers rejected" sh -c "! echo 1 2 3 4 5 2>/dev/null >$P"
check "positions: junk rejected" sh -c "! echo 1 2 3 x 2>/dev/null >$P"
check "positions: beyond 2^62 rejected" sh -c "! echo 1 2 3 9223372036854775807 2>/dev/null >$P"
check "positions unchanged" [ "$(cat "$P")" = "10 -9 29 -41" ]

# An NC switch: low while active, high while idle, over any pins level.
check "clear" wr "$S" clear
check "cleared: inputs back to pins" [ "$(inp)" = 0x1f ]
wr "$P" "250 0 0 0"
check "add 1 1 below 0 0 nc" wr "$S" "add 1 1 below 0 0 nc"
check "NC idle: input 1 high" [ "$(inp)" = 0x1f ]
wr "$P" "-5 0 0 0"
check "NC active: input 1 low" [ "$(inp)" = 0x1d ]
wr "$P" "5 0 0 0"
check "NC idle again" [ "$(inp)" = 0x1f ]
go -5
check "NC active after a move to 0" [ "$(inp)" = 0x1d ]
echo 0x00 >"$D/pins"
go 1
check "pins 0x00 under an idle NC switch: 0x02" [ "$(inp)" = 0x02 ]
check "status register 0x90 (got $(cat "$D/status"))" [ "$(cat "$D/status")" = 0x90 ]
check "pins file reads the switched level" [ "$(cat "$D/pins")" = 0x02 ]
wr "$S" clear
check "cleared: the pins level again" [ "$(inp)" = 0x00 ]
echo 0x1f >"$D/pins"

# SMC1500 wiring: both limit switches in parallel on input 4 (pin 11).
wr "$P" "0 0 0 0"
check "E+ and E- NC on input 4" wr "$S" "add 1 4 above 400 0 nc; add 1 4 below -400 0 nc"
check "both idle: input 4 high, status 0x78" [ "$(inp) $(cat "$D/status")" = "0x1f 0x78" ]
go 400
check "at +400: input 4 low, status 0xf8" [ "$(inp) $(cat "$D/status")" = "0x0f 0xf8" ]
go -400
check "at 0: input 4 high" [ "$(inp)" = 0x1f ]
go -400
check "at -400: input 4 low" [ "$(inp)" = 0x0f ]
check "positions -400 0 0 0" [ "$(cat "$P")" = "-400 0 0 0" ]
check "mixed polarity on input 4 refused" sh -c "! echo 'add 1 4 above 500 0 no' 2>/dev/null >$S"
check "NO on another input accepted" wr "$S" "add 2 3 above 500 0 no"
check "three switches" [ "$(wc -l <"$S")" = 3 ]
wr "$S" "clear; add 1 4 above 400 0 no; add 1 4 below -400 0 no"
wr "$P" "0 0 0 0"
check "NO pair idle: input 4 low" [ "$(inp)" = 0x0f ]
wr "$P" "400 0 0 0"
check "NO pair, E+ hit: input 4 high" [ "$(inp)" = 0x1f ]
wr "$P" "-400 0 0 0"
check "NO pair, E- hit: input 4 high" [ "$(inp)" = 0x1f ]

# Bad commands change nothing.
for c in "add 0 0 above 1 0 no" "add 5 0 above 1 0 no" "add 1 5 above 1 0 no" \
	"add 1 0 beside 1 0 no" "add 1 0 above 1 -1 no" "add 1 0 above 1 0 nx" \
	"add 1 0 above 1 0" "add 1 0 above 1 0 no x" "remove 1" "clear x" \
	"clear; add 1 0 above 1 0 no; add 1 9 above 1 0 no"; do
	check "refused: $c" sh -c "! echo '$c' 2>/dev/null >$S"
done
check "still the NO pair" [ "$(wc -l <"$S")" = 2 ]
check "eight switches" wr "$S" "clear; add 1 0 above 1 0 no; add 1 0 above 2 0 no
add 1 0 above 3 0 no; add 1 0 above 4 0 no; add 1 0 above 5 0 no
add 1 0 above 6 0 no; add 1 0 above 7 0 no; add 1 0 above 8 0 no"
check "a ninth refused" sh -c "! echo 'add 1 0 above 9 0 no' 2>/dev/null >$S"
check "eight listed" [ "$(wc -l <"$S")" = 8 ]
wr "$S" clear
wr "$P" "0 0 0 0"
check "machine reset: inputs 0x1f, status 0x78" [ "$(inp) $(cat "$D/status")" = "0x1f 0x78" ]

# Port removal while x4step is attached, device closed.
check "rmmod x4vport (closed)" rmmod x4vport
check "/dev/x4step$N gone" [ ! -e "/dev/x4step$N" ]
check "/dev/x4step0 still there" [ -c /dev/x4step0 ]
check "debugfs gone" [ ! -d "$D" ]

# ... device open, idle.
check "insmod x4vport again" insmod "$X4MOD/x4vport.ko"
sleep 1
check "/dev/x4step$(cat "$D/port") back" [ -c "/dev/x4step$(cat "$D/port")" ]
exec 3<>"/dev/x4step$N"
check "rmmod x4vport (open, idle)" rmmod x4vport
check "/dev/x4step$N gone while open" [ ! -e "/dev/x4step$N" ]
exec 3>&-

# ... device open, a move running (timer armed).
check "insmod x4vport again" insmod "$X4MOD/x4vport.ko"
sleep 1
x4vctl "/dev/x4step$N" hold-endless 2000 3 &
hp=$!
sleep 1
echo "entries while running: $(cat "$D/count")"
check "rmmod x4vport (open, moving)" rmmod x4vport
check "client survived" wait $hp
check "x4step still loaded" grep -q '^x4step ' /proc/modules

# ... a controller closed during a 5 s brake (the module keeps the port
# until the motor stands): the removal stops it at once, waiting for nothing.
uptime_ms() { awk '{ printf "%d\n", $1 * 1000 }' /proc/uptime; }
check "insmod x4vport again" insmod "$X4MOD/x4vport.ko"
sleep 1
N=$(cat "$D/port")
out=$(x4vctl "/dev/x4step$N" close-braking 5000 1000)
rc=$?
check "close during a 5 s brake ($out)" [ "$rc" = 0 ]
closed=$(echo "$out" | sed -n 's/.*closed_ms=\([0-9]*\).*/\1/p')
check "a controller's open during the brake: refused" sh -c "! sh -c 'exec 3<>/dev/x4step$N' 2>/dev/null"
t0=$(uptime_ms)
check "rmmod x4vport (a closed controller's brake running)" rmmod x4vport
t1=$(uptime_ms)
# "At once" as "before the brake could have ended": it lasts 5 s of guest
# time from the close (5000 steps/s at 1000 steps/s^2; late timers only
# stretch it), so a removal that waited for it ends 5 s or more after the
# close. Not a tighter bound: without -icount the guest's time follows a
# loaded host's clock. (/proc/uptime and closed_ms: both CLOCK_BOOTTIME.)
check "... at once (rmmod took $((t1 - t0)) ms, done $((t1 - ${closed:-0})) ms after the close: less than the brake's 5000)" \
	sh -c "[ -n '$closed' ] && [ $((t1 - ${closed:-0})) -lt 5000 ]"
check "the kernel log says the brake was stopped" \
	sh -c "dmesg | grep -q 'x4step$N: port removed while braking: stopped'"
check "x4step still loaded" grep -q '^x4step ' /proc/modules

# Overrun counting with a small buffer.
check "insmod x4vport ring_order=10" insmod "$X4MOD/x4vport.ko" ring_order=10
sleep 1
echo >"$D/clear"
x4vctl "/dev/x4step$N" move 1000 20000 0
echo "small ring: count $(cat "$D/count") overruns $(cat "$D/overruns")"
check "small ring full at 1024" [ "$(cat "$D/count")" = 1024 ]
check "overruns counted" [ "$(cat "$D/overruns")" -gt 0 ]
echo >"$D/clear"
check "clear zeroes overruns" [ "$(cat "$D/overruns")" = 0 ]

# A port whose operations may sleep (a USB adapter's) is not served: x4step
# writes the registers from a hard-irq timer.
check "rmmod x4vport (small ring)" rmmod x4vport
check "insmod x4vport may_sleep=1" insmod "$X4MOD/x4vport.ko" may_sleep=1
sleep 1
N=$(cat "$D/port")
check "may_sleep: no /dev/x4step$N" [ ! -e "/dev/x4step$N" ]
check "may_sleep: the kernel log says why" \
	sh -c "dmesg | grep -q 'parport$N: not served: its operations may sleep'"
check "rmmod x4vport (may_sleep)" rmmod x4vport
check "insmod x4vport again" insmod "$X4MOD/x4vport.ko"
sleep 1
N=$(cat "$D/port")
check "/dev/x4step$N back" [ -c "/dev/x4step$N" ]

# Unload order: client first; here while a closed controller's brake runs
# on the virtual port (its deferred release is cancelled, the motor stopped).
check "close during a 5 s brake (then rmmod x4step)" x4vctl "/dev/x4step$N" close-braking 5000 1000
check "rmmod x4step" rmmod x4step
check "no /dev/x4step*" [ ! -e /dev/x4step0 ]
check "rmmod x4vport after x4step" rmmod x4vport

# Without parport_pc the virtual port is parport0.
check "rmmod parport_pc" rmmod parport_pc
check "insmod x4step first" insmod "$X4MOD/x4step.ko"
check "insmod x4vport" insmod "$X4MOD/x4vport.ko"
sleep 1
check "alone: port 0" [ "$(cat "$D/port")" = 0 ]
check "alone: /dev/x4step0" [ -c /dev/x4step0 ]
echo >"$D/clear"
check "alone: move 50 steps" x4vctl /dev/x4step0 move 50 2000 0
# shellcheck disable=SC2046 # split into the four numbers
set -- $(edges <"$D/trace")
check "alone: 50 edges traced (got $1)" [ "$1" = 50 ]
check "alone: rmmod x4vport" rmmod x4vport
check "alone: rmmod x4step" rmmod x4step

dmesg | grep -E 'x4|parport' | tail -n 20
echo "FAILURES $fails"
exit "$fails"
