#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins events_test
#: flags --module @FIXTURES@/x4vport.ko
#: seconds 20
# Guest script: the event stream and status reads that leave an unclaimed
# port alone (issue 15), on the virtual port, with ppdev as the other
# parport client (tests/qemu/events/events_test.cpp).
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
# The debug kernel has no ppdev (tests/debugkernel/README.md): that part SKIPs.
if [ -e /lib/kmod/ppdev.ko ]; then insmod /lib/kmod/ppdev.ko || exit 1; fi
insmod "$X4MOD/x4vport.ko" || exit 1
exec /bin/events_test
