#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins reliability_test
#: check ../common/check-segments.sh
#: seconds 50
# Guest script: load x4step, then lp and ppdev (the port is shared, not
# exclusive), and run reliability_test; then check that rmmod is refused
# while a controller holds the device (module in use), that x4step serves
# a port lp has already, the `ports` parameter, and the device's place in
# sysfs (under the port's device, as ppdev's and lp's).
fail=0
check() { # DESCRIPTION COMMAND...
	d=$1
	shift
	if "$@"; then echo "PASS $d"; else echo "FAIL $d"; fail=1; fi
}
parent() { [ -e "$1/device" ] && readlink -f "$1/device"; } # /sys/class/X/Y -> its parent device
insmod "$X4MOD/x4step.ko" || exit 1
for m in lp ppdev; do
	if [ -e /lib/kmod/$m.ko ]; then
		insmod /lib/kmod/$m.ko || { echo "FAIL insmod $m"; fail=1; }
	else
		echo "SKIP $m: no $m.ko in this kernel"
	fi
done
if [ -e /lib/kmod/lp.ko ]; then
	check "lp registers on parport0 next to x4step (/dev/lp0)" [ -c /dev/lp0 ]
fi
x4parent=$(parent /sys/class/x4step/x4step0)
echo "x4step0 in sysfs: $(readlink -f /sys/class/x4step/x4step0), parent $x4parent"
check "x4step0 has a parent device in sysfs" [ -n "$x4parent" ]
# ppdev's and lp's parent is the port's device (port->dev).
for d in /sys/class/ppdev/parport0 /sys/class/printer/lp0; do
	if [ -e $d ]; then
		check "x4step0's parent is $d's: the port's device" [ "$x4parent" = "$(parent $d)" ]
	fi
done
/bin/reliability_test || fail=1
exec 3<>/dev/x4step0
if rmmod x4step 2>/dev/null; then echo "FAIL rmmod refused while the device is open"; exit 1; fi
echo "PASS rmmod refused while the device is open"
exec 3>&-
if rmmod x4step; then
	echo "PASS rmmod after close"
else
	echo "FAIL rmmod after close"
	exit 1
fi

# lp (and ppdev) have registered on parport0 first: x4step still serves it.
check "insmod x4step after lp" insmod "$X4MOD/x4step.ko"
check "/dev/x4step0 on the port lp has" [ -c /dev/x4step0 ]
check "a controller opens it" sh -c 'exec 3<>/dev/x4step0'
check "rmmod x4step" rmmod x4step
# The ports parameter: parport numbers to serve.
check "insmod x4step ports=1" insmod "$X4MOD/x4step.ko" ports=1
check "ports=1: no /dev/x4step0" [ ! -e /dev/x4step0 ]
check "ports=1: the kernel log says parport0 is not served" sh -c "dmesg | grep -q 'parport0: not served (not in the ports parameter)'"
check "rmmod x4step (ports=1)" rmmod x4step
check "insmod x4step ports=3,0" insmod "$X4MOD/x4step.ko" ports=3,0
check "ports=3,0: /dev/x4step0" [ -c /dev/x4step0 ]
check "rmmod x4step (ports=3,0)" rmmod x4step
check "insmod x4step ports=16 refused" sh -c "! insmod $X4MOD/x4step.ko ports=16 2>/dev/null"
check "insmod x4step ports=-1 refused" sh -c "! insmod $X4MOD/x4step.ko ports=-1 2>/dev/null"
dmesg | grep -E 'x4step|parport0|lp0|ppdev' | tail -n 12
exit $fail
