#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins positioning_test
#: flags --icount --timeout 600 --module @FIXTURES@/x4vport.ko
#: check check-positioning.sh
#: seconds 45
# Guest script: positioning (issue 8) on the virtual port, a machine with
# positions and switches (tests/qemu/fixtures/x4vport.c), then a few moves on QEMU's
# parport for tests/qemu/positioning/check-positioning.sh. Run with --icount.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
# A debug kernel's timers are too late for the microsecond checks.
case $(uname -r) in
*-x4debug) exec /bin/positioning_test --no-timing ;;
*) exec /bin/positioning_test ;;
esac
