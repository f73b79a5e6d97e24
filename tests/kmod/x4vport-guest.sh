#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#
# Guest half of run-x4vport-tests.sh (runs under tests/qemu/run-guest.sh,
# which has loaded parport and parport_pc, so the virtual port is parport1):
# x4vport's debugfs files, x4step on the virtual port (open, a move through
# the hard-irq timer, inputs), removal of the port while x4step is attached,
# open, and moving, and the port alone as parport0. Prints PASS/FAIL lines;
# exits with the number of failures.

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

check "insmod x4step" insmod "$X4MOD/x4step.ko"
sleep 1
check "/dev/x4step$N exists" [ -c "/dev/x4step$N" ]
check "/dev/x4step0 (parport_pc) exists" [ -c /dev/x4step0 ]

# Inputs: pins -> status register -> X4GetIn through x4step.
for p in 0x1f 0x00 0x10 0x0f 0x01 0x02 0x04 0x08 0x15; do
	echo "$p" >"$D/pins"
	got=$(x4vctl "/dev/x4step$N" inputs | sed -n 's/inputs=\(0x..\).*/\1/p')
	check "pins $p -> status $(cat "$D/status") -> X4GetIn $got" [ "$got" = "$p" ]
done
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

# Unload order: client first.
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
