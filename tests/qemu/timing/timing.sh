#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins timing_bench
#: flags --icount --module @FIXTURES@/x4vport.ko --module @FIXTURES@/x4hrbench.ko
#: seconds 30
# Guest script of the timing benchmark (run with --icount).
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
insmod "$X4MOD/x4hrbench.ko" || exit 1
exec /bin/timing_bench
