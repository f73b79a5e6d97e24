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
exec "$suite" -k "$release" "$@"
