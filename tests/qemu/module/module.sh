#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins module_test
#: check ../common/check-segments.sh
#: seconds 10
# Guest script: load x4step and run module_test (see tests/qemu/module/module_test.cpp).
insmod "$X4MOD/x4step.ko" || exit 1
exec /bin/module_test
