#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins keys_test
#: check ../common/check-segments.sh
#: seconds 10
# Guest script: load x4step and run keys_test (see tests/qemu/keys/keys_test.cpp).
insmod "$X4MOD/x4step.ko" || exit 1
exec /bin/keys_test
