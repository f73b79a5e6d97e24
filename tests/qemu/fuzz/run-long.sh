#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# A long ioctl fuzz run in one QEMU guest (make check runs tests/qemu/fuzz/fuzz.sh
# for about 45 s with a fixed seed; this is the documented longer run).
#
# Usage: tests/qemu/fuzz/run-long.sh [--kver KVER] [--seconds S] [--seed N] [--out DIR]
#   --kver     kernel release under /boot (default: the newest 6.1 Debian kernel;
#              e.g. 6.1.192-x4debug for the debug kernel, tests/debugkernel)
#   --seconds  length of the full fuzz run (default 600; the invalid-only run
#              before it takes a fifth of that, at most 120 s)
#   --seed     default: the current time (printed, to repeat a failure)
#   --out      default: build/fuzz/<kver>
# Passes if the guest's fuzzer found nothing, the kernel reported nothing
# (run-guest.sh) and the invalid-only run left no clock edge in the port trace.
set -euo pipefail

top=$(cd "$(dirname "$0")/../../.." && pwd)
kver="" secs=600 seed=$(date +%s) out=""
while [ $# -gt 0 ]; do
	case "$1" in
	--kver) kver=${2:?}; shift 2 ;;
	--seconds) secs=${2:?}; shift 2 ;;
	--seed) seed=${2:?}; shift 2 ;;
	--out) out=${2:?}; shift 2 ;;
	*) echo "usage: $0 [--kver KVER] [--seconds S] [--seed N] [--out DIR]" >&2; exit 2 ;;
	esac
done
[[ "$secs" =~ ^[0-9]+$ && "$seed" =~ ^[0-9]+$ ]] || { echo "run-long: --seconds and --seed are numbers" >&2; exit 2; }
if [ -z "$kver" ]; then
	kver=$(cd /boot && for f in vmlinuz-6.1.*-amd64; do [ -e "$f" ] && echo "${f#vmlinuz-}"; done | sort -V | tail -n1)
	[ -n "$kver" ] || { echo "run-long: no Debian 6.1 kernel under /boot" >&2; exit 2; }
fi
out=${out:-$top/build/fuzz/$kver}
kdir=/lib/modules/$kver/build
[ -d "$kdir" ] || kdir=/usr/src/linux-headers-$kver
isecs=$((secs / 5 > 120 ? 120 : (secs / 5 < 10 ? 10 : secs / 5)))

rm -rf "$out"
mkdir -p "$out/src"
cp -a "$top/Kbuild" "$top/kmod" "$top/include" "$out/src/"
find "$out/src" \( -name '*.o' -o -name '*.ko' -o -name '*.mod*' -o -name '.*.cmd' \
	-o -name modules.order -o -name Module.symvers \) -delete
make -C "$kdir" M="$out/src" modules >"$out/build.log" 2>&1 || { echo "run-long: module build failed, see $out/build.log" >&2; exit 1; }
g++ -std=c++17 -O2 -Wall -Wextra -Werror -static -I"$top/include/uapi" -pthread \
	-o "$out/ioctl_fuzz" "$top/tests/qemu/fuzz/ioctl_fuzz.cpp"
g++ -std=c++17 -O2 -o "$out/x4trace" "$top/tests/tools/x4trace/x4trace.cpp"

{
	echo "#!/bin/sh"
	echo "export X4FUZZ_SEED=$seed X4FUZZ_SECONDS=$secs X4FUZZ_INVALID_SECONDS=$isecs"
	sed 1d "$top/tests/qemu/fuzz/fuzz.sh"
} >"$out/fuzz-long.sh"

echo "run-long: $kver, seed $seed, invalid-only ${isecs}s + full ${secs}s; logs in $out"
rc=0
"$top/tests/qemu/run-guest.sh" --kver "$kver" --out "$out/guest" --module "$out/src/kmod/x4step.ko" \
	--bin "$out/ioctl_fuzz" --timeout $((secs + isecs + 300)) "$out/fuzz-long.sh" >"$out/run.log" 2>&1 || rc=$?
grep -a -E '^(PASS|FAIL) |VIOLATION|calls/iterations|^run-guest:' "$out/run.log" | tr -d '\r' || true
if [ "$rc" -eq 0 ]; then
	X4TRACE=$out/x4trace "$top/tests/qemu/fuzz/check-no-edges.sh" "$out/guest" "$kver" >"$out/host-check.log" 2>&1 || rc=1
	tail -n1 "$out/host-check.log"
fi
echo "run-long: $([ "$rc" -eq 0 ] && echo PASS || echo "FAIL (status $rc)") seed $seed"
exit "$rc"
