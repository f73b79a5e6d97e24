#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins man_errors man_load man_start man_brake man_init man_getsteps man_lastbrakecode man_timer man_getin man_setout
#: flags --monitor @OUT@/mon.sock
#: check ../common/check-segments.sh
#: seconds 15
# Guest script: the manual's example programs (examples/manual/*.c),
# built against the installed x4step.h and static libx4step. Programs that
# wait for ESC get it typed on the emulated AT keyboard (QEMU's sendkey):
# the real atkbd -> input core -> x4step input handler path.
# shellcheck disable=SC2317 # helpers are called indirectly
insmod "$X4MOD/x4step.ko" || exit 1
fail=0

check() { # NAME COMMAND...
	name=$1
	shift
	if "$@"; then echo "PASS manual $name"; else echo "FAIL manual $name"; fail=1; fi
}

# A move has started on /dev/x4step0: in the module's event stream, read
# by a monitor (dd, one 64-byte struct x4step_event per read) into
# /tmp/events, an event of type 1 (X4STEP_EV_MOVE_STARTED; the type is the
# u32 at byte 16, the first number of each event's second od line).
move_started() {
	od -An -tu4 -v /tmp/events 2>/dev/null | awk 'NR % 4 == 2 && $1 == 1 { f = 1 } END { exit !f }'
}

has_dev() { # PID: the process has /dev/x4step0 open
	for f in "/proc/$1/fd"/*; do
		[ "$(readlink "$f" 2>/dev/null)" = /dev/x4step0 ] && return 0
	done
	return 1
}

# Run PROGRAM, type KEY SECONDS after its move started; fail if it does not
# end by itself. The start is waited for (up to 10 s), not assumed after a
# fixed time: without -icount a loaded host lets the guest do less in its
# time, and a key typed before the move would brake nothing.
with_key() { # SECONDS KEY PROGRAM
	: >/tmp/events
	dd if=/dev/x4step0 of=/tmp/events bs=64 2>/dev/null &
	mon=$!
	n=0 # the monitor sees the events from its open on
	while [ "$n" -lt 100 ] && ! has_dev "$mon"; do
		usleep 10000
		n=$((n + 1))
	done
	"$3" >/tmp/out 2>&1 &
	pid=$!
	n=0
	while [ "$n" -lt 100 ] && ! move_started; do
		usleep 100000
		n=$((n + 1))
	done
	move_started && echo "manual: $3: its move started" || echo "manual: $3: no move start seen in 10 s"
	kill "$mon"
	sleep "$1"
	echo "X4MON sendkey $2"
	(sleep 10 && kill -9 "$pid" 2>/dev/null) &
	watchdog=$!
	wait "$pid"
	status=$?
	kill "$watchdog" 2>/dev/null
	cat /tmp/out
	return "$status"
}

check errors /bin/man_errors
check load /bin/man_load
echo "SEG 1000 0 0 0"
echo "SEG -1000 0 0 0"
check start /bin/man_start
echo "SEG 1000 0 0 0"
check brake /bin/man_brake
check init with_key 1 esc /bin/man_init
echo "SEG ? 0 0 0 braked"
check getsteps with_key 1 esc /bin/man_getsteps
check lastbrakecode with_key 1 ret /bin/man_lastbrakecode
grep -q "ENTER hat abgebrochen" /tmp/out
check "lastbrakecode says ENTER" [ $? -eq 0 ]
echo "SEG ? 0 0 0 braked"
check timer /bin/man_timer
check getin /bin/man_getin
echo "SEG ? 0 0 0"
check setout with_key 1 esc /bin/man_setout
echo "SEG ? 0 0 0 braked signal1"
exit $fail
