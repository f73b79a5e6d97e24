#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins phase_test
#: check check-phase.sh
#: seconds 20
# Guest script: load x4step and run phase_test (tests/qemu/phase/phase_test.cpp).
insmod "$X4MOD/x4step.ko" || exit 1
exec /bin/phase_test
