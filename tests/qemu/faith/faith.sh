#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins faith_moves faith.machine
#: flags --icount --module @FIXTURES@/x4vport.ko
#: check check-faith.sh
#: seconds 22
# Guest script of the faithfulness test (tests/qemu/faith/README.md), run with
# --icount: the machine of faith.machine on the virtual port x4vport, the
# moves of faith_moves on the module, then x4vport's trace of every port
# write (guest time, ns) on the console as `XV` lines for check-faith.sh.
mount -t debugfs none /sys/kernel/debug 2>/dev/null
insmod "$X4MOD/x4step.ko" || exit 1
insmod "$X4MOD/x4vport.ko" || exit 1
v=/sys/kernel/debug/x4vport
# faith.machine as x4vport's switches and positions (README, the sim
# table, and x4vport.c: "add AXIS BIT below|above AT HYST no|nc").
sw=$(awk '
	function bit(p) { sub(/^pin/, "", p); return p == 15 ? 0 : p == 13 ? 1 : p == 12 ? 2 : p == 10 ? 3 : 4 }
	{ sub(/#.*/, "") }
	$1 == "ref" { printf "add %s %d %s %s %d %s;", $2, bit($5), $3, $4, $8 + 0, $6 }
	$1 == "e+" || $1 == "e-" {
		printf "add %s %d %s %s %d %s;", $2, bit($4), $1 == "e+" ? "above" : "below", $3, $7 + 0, $5
	}' /bin/faith.machine)
pos=$(awk '{ sub(/#.*/, "") } $1 == "position" { p[$2] = $3 }
	END { printf "%d %d %d %d", p[1], p[2], p[3], p[4] }' /bin/faith.machine)
echo "machine: switches '$sw' positions '$pos'"
printf 'clear;%s\n' "$sw" >$v/switches || exit 1
echo "$pos" >$v/positions || exit 1
echo 0 >$v/pins || exit 1 # the simulator's unswitched inputs read LOW
echo 1 >$v/clear
/bin/faith_moves $(($(cat $v/port) + 1)) || exit 1
[ "$(cat $v/overruns)" = 0 ] || { echo "FAIL x4vport trace overruns"; exit 1; }
echo "XV-BEGIN $(cat $v/count)"
sed 's/^/XV /' $v/trace
echo "XV-END"
