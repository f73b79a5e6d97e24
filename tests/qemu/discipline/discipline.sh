#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins discipline_test
#: flags --icount --timeout 600 --module @FIXTURES@/x4vport.ko
#: seconds 35
# Guest script: the step timer's discipline (issue 15) on the virtual port.
# Run with --icount.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
# A debug kernel's timers are too late for the millisecond checks.
case $(uname -r) in
*-x4debug) exec /bin/discipline_test --no-timing ;;
*) exec /bin/discipline_test ;;
esac
