#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins brake_test
#: flags --icount --module @FIXTURES@/x4vport.ko
#: seconds 20
# Guest script: every brake source decelerates along its ramp, timed in
# guest time on the virtual port (tests/qemu/brake/brake_test.cpp). Run with
# --icount.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
# A debug kernel's timers are too late for the timing checks.
case $(uname -r) in
*-x4debug) exec /bin/brake_test --no-timing ;;
*) exec /bin/brake_test ;;
esac
