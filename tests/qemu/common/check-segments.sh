#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Host check: every move the guest announced with a line
#   SEG s1 s2 s3 s4 [braked] [signal1]       (s = signed steps, ? = any)
# appears, in order, as an AKTIV-framed move in QEMU's port trace, with
# those step counts (rising clock edges, signed by the direction pin), no
# direction change while stepping, and pin 1 high if signal1. A braked move
# must end on a ramp: its leader's last steps (at least 2) made with BOOST
# (pin 16) high, where a move cut in its cruise has none. Counts, order and
# levels only: the trace's timestamps are host time, which a loaded host
# stretches and squeezes under plain TCG. How a brake decelerates in time
# is measured in guest time (tests/qemu/brake/brake_test.cpp, under -icount).
# Usage: check-segments.sh OUTDIR KVER
set -eu
out=${1:?}
tr -d '\r' <"$out/console.log" | grep '^SEG ' >"$out/segments.expected" || true
"${X4TRACE:?}" moves "$out/lpt-test.log" >"$out/segments.seen"
want=$(wc -l <"$out/segments.expected")
got=$(wc -l <"$out/segments.seen")
echo "moves announced by the guest: $want, moves in the port trace: $got"
[ "$want" -gt 0 ] || { echo "no SEG lines: nothing checked"; exit 1; }
[ "$want" -eq "$got" ] || { paste -d'|' "$out/segments.expected" "$out/segments.seen"; exit 1; }
paste -d' ' "$out/segments.expected" "$out/segments.seen" | awk '
{
	# $1 SEG, $2..$5 expected, then flags, then MOVE i steps a b c d dirchanges n rampend r signal1 l
	for (m = 2; $m != "MOVE"; m++) ;
	ok = 1
	for (a = 0; a < 4; a++)
		if ($(2 + a) != "?" && $(2 + a) != $(m + 3 + a)) ok = 0
	if ($(m + 8) != 0) ok = 0
	for (f = 6; f < m; f++) {
		if ($f == "braked" && $(m + 10) < 2) ok = 0
		if ($f == "signal1" && $(m + 12) != 1) ok = 0
	}
	print (ok ? "ok  " : "BAD ") $0
	if (!ok) bad++
}
END { exit bad > 0 }'
