#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: check check-no-steps.sh
#: seconds 8
#
# Guest script (busybox sh): load x4step, check its device node, the parport
# claim/release protocol and the exclusive writer, unload, reload.
# Run by tests/qemu/run-guest.sh; expects $X4MOD/x4step.ko and parport0.
# shellcheck disable=SC2317 # helpers are called through check()

mod=${X4MOD:-/lib/x4}/x4step.ko
dev=/dev/x4step0
active=/proc/sys/dev/parport/parport0/devices/active
failed=0

pass() { echo "PASS $1"; }
fail() {
	echo "FAIL $1${2:+: $2}"
	failed=1
}
check() { # NAME DETAIL COMMAND...: PASS if the command succeeds
	name=$1 detail=$2
	shift 2
	if "$@"; then pass "$name"; else fail "$name" "$detail"; fi
}
claimed_by() { [ "$(cat "$active" 2>/dev/null)" = "$1" ]; }
major_of() { awk -v n="$1" '$2 == n { print $1 }' /proc/devices; }
not_loaded() { ! grep -q '^x4step ' /proc/modules; }
was_ebusy() { # uses $rc and $err of the last open attempt
	[ "$rc" -ne 0 ] && case "$err" in *"resource busy"*) true ;; *) false ;; esac
}

if ! insmod "$mod"; then
	fail insmod "insmod $mod"
	exit 1
fi
pass insmod

# Node: a char device, major from /proc/devices, minor 0 (parport0), mode 0660.
check devnode "$dev missing or not a char device" test -c "$dev"
maj=$(major_of x4step)
node=$(stat -c '%t %T' "$dev" 2>/dev/null)
node_dec=$(printf '%d %d' "0x${node% *}" "0x${node#* }" 2>/dev/null)
check devnode-major-minor "node $node_dec, /proc/devices says major '$maj'" \
	test -n "$maj" -a "$node_dec" = "$maj 0"
mode=$(stat -c '%A' "$dev" 2>/dev/null)
check devnode-mode-0660 "mode $mode" test "$mode" = crw-rw----

# The pardevice, registered with the device model, hangs below parport0.
pdev=""
for d in /sys/bus/parport/devices/x4step*; do
	[ -e "$d" ] && case "$(readlink -f "$d")" in */parport0/*) pdev=${d##*/} ;; esac
done
check parport-device "no x4step* below parport0 in /sys/bus/parport/devices: $(ls /sys/bus/parport/devices)" \
	test -n "$pdev"
[ -n "$pdev" ] && echo "     ($pdev -> $(readlink -f /sys/bus/parport/devices/"$pdev"))"

# The port is claimed only while a controller (read-write opener) holds it.
check unclaimed-when-closed "active: $(cat $active)" claimed_by none
if command exec 3<>"$dev"; then
	pass open-rdwr
	check claimed-while-open "active: $(cat $active)" claimed_by x4step
	err=$(sh -c "exec 4<>$dev" 2>&1)
	rc=$?
	check second-rdwr-ebusy "second O_RDWR open: status $rc, $err" was_ebusy
	check rdonly-open-while-claimed "read-only open failed" sh -c "exec 5<$dev"
	check still-claimed-after-rdonly "active: $(cat $active)" claimed_by x4step
	check rmmod-refused-while-open "rmmod succeeded with $dev open" \
		sh -c '! rmmod x4step 2>/dev/null'
	exec 3>&-
	check released-on-close "active: $(cat $active)" claimed_by none
else
	fail open-rdwr "cannot open $dev read-write"
fi
check reopen-after-close "O_RDWR open after close failed" sh -c "exec 4<>$dev"

# Unload: node, chrdev region and module all gone; then once more.
check rmmod "rmmod x4step failed" rmmod x4step
check devnode-removed "$dev still exists" test ! -e "$dev"
check chrdev-unregistered "x4step still in /proc/devices" test -z "$(major_of x4step)"
check module-unloaded "x4step still in /proc/modules" not_loaded
check reload "insmod/rmmod again failed" sh -c "insmod $mod && test -c $dev && rmmod x4step"
check reload-unloaded "x4step still loaded" not_loaded

bad=$(dmesg | grep -E 'WARNING|BUG|Oops|leak')
check dmesg-clean "$bad" test -z "$bad"

[ "$failed" = 0 ] && echo "smoke: all checks passed" || echo "smoke: some checks FAILED"
exit "$failed"
