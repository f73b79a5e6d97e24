#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# Build x4vport (the virtual parallel port) and x4step for each kernel in a
# temporary directory, and run x4vport-guest.sh in QEMU on each.
#
# Usage: tests/kmod/run-x4vport-tests.sh [--icount] [--out DIR] [KVER...]
# Default kernels: every /usr/src/linux-headers-*-amd64 with a /boot kernel.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
out=/tmp/x4vport-tests
extra=()
kvers=()
while [ $# -gt 0 ]; do
	case "$1" in
	--icount) extra+=(--icount); shift ;;
	--out) out=${2:?}; shift 2 ;;
	-*) echo "usage: $0 [--icount] [--out DIR] [KVER...]" >&2; exit 2 ;;
	*) kvers+=("$1"); shift ;;
	esac
done
if [ ${#kvers[@]} = 0 ]; then
	for h in /usr/src/linux-headers-*-amd64; do
		k=${h#/usr/src/linux-headers-}
		[ -r "/boot/vmlinuz-$k" ] && kvers+=("$k")
	done
fi

mkdir -p "$out"
gcc -static -O2 -Wall -Wextra -I"$top/include/uapi" -o "$out/x4vctl" "$here/x4vctl.c"

fails=0
for k in "${kvers[@]}"; do
	b=$out/build-$k
	rm -rf "$b"
	mkdir -p "$b/vport" "$b/x4step"
	cp "$here/x4vport.c" "$here/Kbuild" "$b/vport/"
	cp -r "$top/kmod" "$top/include" "$top/Kbuild" "$b/x4step/"
	rm -f "$b"/x4step/kmod/{*.o,*.ko,*.mod,*.mod.c,modules.order,.*.cmd}
	for d in vport x4step; do
		make -s -C "/usr/src/linux-headers-$k" M="$b/$d" W=1 modules 2>&1 |
			grep -v '^Skipping BTF generation' || true
	done
	if "$top/tests/qemu/run-guest.sh" "${extra[@]}" --kver "$k" --out "$out/$k" \
		--module "$b/vport/x4vport.ko" --module "$b/x4step/kmod/x4step.ko" \
		--bin "$out/x4vctl" "$here/x4vport-guest.sh" >"$out/$k.log" 2>&1; then
		echo "PASS $k"
	else
		echo "FAIL $k (exit $?): $out/$k.log"
		grep -a FAIL "$out/$k.log" || true
		fails=$((fails + 1))
	fi
done
exit $fails
