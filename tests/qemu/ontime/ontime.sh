#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins ontime_test
#: flags --icount --module @FIXTURES@/x4vport.ko
#: seconds 20
# Guest script: the X4Step API's top rate on time (issue 28, item 10) on
# the virtual port. Run with --icount.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
# A debug kernel's timer is ~16 us late: more than the spin may make up.
case $(uname -r) in
*-x4debug) exec /bin/ontime_test --no-timing ;;
*) exec /bin/ontime_test ;;
esac
