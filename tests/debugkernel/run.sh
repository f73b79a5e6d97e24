#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# Run the QEMU suite on the debug kernel (lockdep, atomic-sleep, KASAN, UBSAN,
# debugobjects): build or reuse it with tests/debugkernel/build.sh (which
# installs /boot/vmlinuz-6.1.*-x4debug and /lib/modules/.../build), then run
# tests/qemu/run-suite.sh on that kernel only. run-guest.sh fails a test
# (status 126) on any lockdep, KASAN, UBSAN, "sleeping function called from
# invalid context", WARNING or BUG report in the guest's console or kernel log.
#
# Usage: tests/debugkernel/run.sh [-t TEST]... [-v]    (options go to run-suite.sh)
# Logs: build/qemu-debug/<release>/<test>/ (as run-suite.sh's), the kernel's
# build in ${X4_CACHE:-/var/cache/x4step}/debugkernel-KEY (see build.sh).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
suite=$top/tests/qemu/run-suite.sh

[ "$(id -u)" -eq 0 ] || {
	echo "debugkernel: run.sh installs the kernel under /boot and /lib/modules: run it as root" >&2
	exit 2
}
release=$("$here/build.sh" "$top/build/debugkernel" | tail -n1)
[ -r "/boot/vmlinuz-$release" ] || { echo "debugkernel: no /boot/vmlinuz-$release" >&2; exit 1; }

export X4_QEMU_BUILD=${X4_QEMU_BUILD:-$top/build/qemu-debug}
export X4_DEBUGKERNEL=1
guest=$top/tests/qemu/run-guest.sh
# run-guest.sh's bare "lockdep" pattern matches the debug kernel's boot banner
# "RCU lockdep checking is enabled." (every lockdep report has a "WARNING: "
# title and a "Call Trace:", which it catches anyway).
patch_guest=0
grep -q '|lockdep|' "$guest" && patch_guest=1
if [ "$patch_guest" = 0 ] && grep -q 'x4debug' "$suite"; then
	# run-suite.sh knows the debug kernel kind (enabled by X4_DEBUGKERNEL=1).
	exec "$suite" -k "$release" "$@"
fi

# Until then: temporary copies (here, so that their paths to the repository
# hold) with the debug kernel as the only kernel kind and the pattern fixed.
tmp_suite=$here/.run-suite-debug.$$.sh
tmp_guest=$here/.run-guest-debug.$$.sh
trap 'rm -f "$tmp_suite" "$tmp_guest"' EXIT
# shellcheck disable=SC2016 # the text run-suite.sh has, to be replaced
runner='"$qdir/run-guest.sh"'
if [ "$patch_guest" = 1 ]; then
	sed -e 's/|lockdep|/|WARNING: |turning off the locking correctness validator|DEBUG_LOCKS_WARN_ON|/' \
		-e "s|\"\$here/qemu-monitor.py\"|\"$top/tests/qemu/qemu-monitor.py\"|" "$guest" >"$tmp_guest"
	chmod +x "$tmp_guest"
	runner="\"$tmp_guest\""
fi
awk -v runner="$runner" '
/^kernel_kinds=\(/ { print; print "\t\"debug|vmlinuz-*-x4debug|\""; skip = 1; next }
skip && /^\)/ { skip = 0 }
skip { next }
{ gsub(/"\$qdir\/run-guest.sh"/, runner); print }
' "$suite" >"$tmp_suite"
grep -q '"debug|vmlinuz-\*-x4debug|"' "$tmp_suite" || { echo "debugkernel: cannot find kernel_kinds in $suite" >&2; exit 1; }
bash "$tmp_suite" -k "$release" "$@"
