#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins x4grbl grbl_stream grbl-mill.ini grbl-part.nc
#: check check-grbl.sh
#: seconds 15
#
# Guest script (busybox sh): the GRBL bridge (issue 31) on the module, on
# QEMU's parallel port. x4grbl runs grbl-mill.ini (four axes, no home
# switches: no homing lock) on a pseudo-terminal; grbl_stream, a minimal
# sender, streams grbl-part.nc over it with GRBL's character counting
# (lines, two arcs, rounding-sized moves), holds the motion (`!`) mid-path
# and resumes it (`~`), waits for Idle and prints the final MPos. On the
# host, check-grbl.sh counts each motor's steps in QEMU's port trace and
# wants round(programmed end x SCALE) on every axis.
dev=/dev/x4step0
link=/tmp/ttyGRBL0
failed=0
pass() { echo "PASS $1"; }
fail() {
	echo "FAIL $1${2:+: $2}"
	failed=1
}

if ! insmod "$X4MOD/x4step.ko"; then
	fail setup "insmod $X4MOD/x4step.ko"
	exit 1
fi
for _ in 1 2 3 4 5 6 7 8 9 10; do [ -c "$dev" ] && break; usleep 100000; done
[ -c "$dev" ] || { fail setup "no $dev"; exit 1; }
# Pseudo-terminals: /init mounts no devpts.
mkdir -p /dev/pts
mount -t devpts -o ptmxmode=0666 devpts /dev/pts 2>/dev/null
[ -c /dev/ptmx ] || ln -s pts/ptmx /dev/ptmx
# The machine file where x4grbl may keep its settings beside it.
cp /bin/grbl-mill.ini /tmp/mill.ini
pass setup

x4grbl --machine /tmp/mill.ini --link "$link" 2>/tmp/x4grbl.log &
bridge=$!
start=$(cut -d' ' -f1 /proc/uptime)
# Lines 1..5 (through the first arc) go out, then the hold, then the rest.
grbl_stream "$link" /bin/grbl-part.nc --hold-after 5 || fail stream "grbl_stream failed"
end=$(cut -d' ' -f1 /proc/uptime)
echo "X4GRBL guest-seconds $start $end"

# SIGTERM: x4grbl ends cleanly (status 0), the port released.
kill -TERM "$bridge"
wait "$bridge"
rc=$?
if [ "$rc" = 0 ]; then pass sigterm; else fail sigterm "x4grbl exit $rc"; fi
cat /tmp/x4grbl.log # its lines start with "x4grbl: "
exit "$failed"
