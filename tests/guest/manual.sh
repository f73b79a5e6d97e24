#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Guest script: the manual's example programs (tests/guest/manual/*.c),
# built against the installed x4step.h and static libx4step. Programs that
# wait for ESC get it typed on the emulated AT keyboard (QEMU's sendkey):
# the real atkbd -> input core -> x4step input handler path.
insmod "$X4MOD/x4step.ko" || exit 1
fail=0

check() { # NAME COMMAND...
	name=$1
	shift
	if "$@"; then echo "PASS manual $name"; else echo "FAIL manual $name"; fail=1; fi
}

# Run PROGRAM, type KEY after SECONDS; fail if it does not end by itself.
with_key() { # SECONDS KEY PROGRAM
	"$3" >/tmp/out 2>&1 &
	pid=$!
	sleep "$1"
	echo "X4MON sendkey $2"
	(sleep 10 && kill -9 $pid 2>/dev/null) &
	watchdog=$!
	wait $pid
	status=$?
	kill $watchdog 2>/dev/null
	cat /tmp/out
	return $status
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
