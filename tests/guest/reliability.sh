#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Guest script: load x4step and run reliability_test, then check that
# rmmod is refused while a controller holds the device (module in use).
insmod "$X4MOD/x4step.ko" || exit 1
/bin/reliability_test || exit 1
exec 3<>/dev/x4step0
if rmmod x4step 2>/dev/null; then echo "FAIL rmmod refused while the device is open"; exit 1; fi
echo "PASS rmmod refused while the device is open"
exec 3>&-
rmmod x4step && echo "PASS rmmod after close" || { echo "FAIL rmmod after close"; exit 1; }
