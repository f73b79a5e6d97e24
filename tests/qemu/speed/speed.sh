#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins speed_bench
#: flags --icount --timeout 600 --module @FIXTURES@/x4vport.ko --module @FIXTURES@/x4hrbench.ko
#: seconds 48
# Guest script of the speed ceiling benchmark (run with --icount): the
# module with its defaults (write budget included), rates up to
# X4STEP_VEL_MAX and one above it, which must be refused.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
insmod "$X4MOD/x4hrbench.ko" || exit 1
exec /bin/speed_bench 45000 60000 80000 100000 120000
