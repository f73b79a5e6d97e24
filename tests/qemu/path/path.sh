#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins path_test
#: flags --icount --timeout 600 --module @FIXTURES@/x4vport.ko
#: check ../common/check-segments.sh
#: seconds 45
# Guest script: continuous paths (issue 18) on the virtual port, observed
# from its guest-time write trace, then a streamed path on QEMU's parport
# for tests/qemu/common/check-segments.sh. Run with --icount.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
# A debug kernel's timers are too late for the microsecond checks.
case $(uname -r) in
*-x4debug) exec /bin/path_test --no-timing ;;
*) exec /bin/path_test ;;
esac
