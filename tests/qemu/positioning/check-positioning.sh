#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Host check of the positioning test (tests/qemu/positioning/positioning_test.cpp):
# its last part moves on QEMU's emulated parport and prints the change of
# the module's coordinates per move as `SEG` lines, and the coordinates
# before and after as `COORD0` and `COORD`. QEMU's own port trace must
# show exactly those moves (check-segments.sh: steps per axis from the
# clock edges, signed by the direction pin), and the coordinates must have
# changed by the sum of the steps QEMU saw.
# Usage: check-positioning.sh OUTDIR KVER
set -eu
out=${1:?}
here=$(dirname "$0")
"$here/../common/check-segments.sh" "$@"
c0=$(tr -d '\r' <"$out/console.log" | sed -n 's/^COORD0 //p')
c1=$(tr -d '\r' <"$out/console.log" | sed -n 's/^COORD //p')
if [ -z "$c0" ] || [ -z "$c1" ]; then
	echo "BAD: no COORD0/COORD lines"
	exit 1
fi
sums=$(awk '$1 == "MOVE" { for (a = 0; a < 4; a++) s[a] += $(4 + a) }
	END { printf "%d %d %d %d\n", s[0], s[1], s[2], s[3] }' "$out/segments.seen")
echo "module coordinates: before $c0, after $c1; steps QEMU saw, per axis: $sums"
echo "$c0 $c1 $sums" | awk '{
	bad = 0
	for (a = 1; a <= 4; a++) if ($(4 + a) - $a != $(8 + a)) bad = 1
	if (bad) { print "BAD: coordinates changed by other than the steps QEMU saw"; exit 1 }
	print "ok: coordinates changed by exactly the steps QEMU saw"
}'
