#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Guest script: load x4step and run phase_test (tests/guest/phase_test.cpp).
insmod "$X4MOD/x4step.ko" || exit 1
exec /bin/phase_test
