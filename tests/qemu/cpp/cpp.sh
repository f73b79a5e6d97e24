#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins cpp_test
#: flags --module @FIXTURES@/x4vport.ko
#: check ../common/check-segments.sh
#: seconds 13
# Guest script: load x4step, ppdev (another parport client) and the virtual
# port (parport1, which cpp_test removes), and run cpp_test (see
# tests/qemu/cpp/cpp_test.cpp).
insmod "$X4MOD/x4step.ko" || exit 1
if [ -e /lib/kmod/ppdev.ko ]; then insmod /lib/kmod/ppdev.ko || exit 1; fi
if [ -e "$X4MOD/x4vport.ko" ]; then insmod "$X4MOD/x4vport.ko" || exit 1; fi
exec /bin/cpp_test
