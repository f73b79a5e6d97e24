#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins probe_test
#: flags --icount --module @FIXTURES@/x4vport.ko
#: seconds 30
# Guest script: probing (issue 31) on the virtual port, a machine with a
# probe switch at a position (tests/qemu/fixtures/x4vport.c): the latch of
# a probing segment is the step at which the switch changed, as the port's
# write trace shows it. Run with --icount.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
exec /bin/probe_test
