#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins config_test
#: check check-config.sh
#: seconds 18
# Guest script: SET_CONFIG while idle makes no step edge for the new wiring,
# and is refused while a move runs (tests/qemu/config/config_test.cpp; the host
# checks QEMU's port trace with tests/qemu/config/check-config.sh).
insmod "$X4MOD/x4step.ko" || exit 1
exec /bin/config_test
