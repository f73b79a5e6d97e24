#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
#: bins ioctl_fuzz
#: check check-no-edges.sh
#: seconds 56
# Guest script: the ioctl fuzzer (tests/qemu/fuzz/ioctl_fuzz.cpp) with a fixed seed.
# First a run of invalid calls only, framed in QEMU's port trace by markers
# (0x58 0x49 ... 0x58 0x4a written to the status register, which changes no
# pin): tests/qemu/fuzz/check-no-edges.sh asserts no clock edge between them. Then
# the full run (threads, monitors, open/close races). About 45 s of fuzzing
# on the debug kernel, where KASAN, lockdep and UBSAN see what a call did;
# 28 s on Debian's kernels, which see the same calls but only crashes.
# X4FUZZ_SEED, X4FUZZ_SECONDS (the full run) and X4FUZZ_INVALID_SECONDS
# override the defaults, e.g. for a long run.
seed=${X4FUZZ_SEED:-20240601}
case "$(uname -r)" in
*-x4debug) secs=${X4FUZZ_SECONDS:-33} isecs=${X4FUZZ_INVALID_SECONDS:-12} ;;
*) secs=${X4FUZZ_SECONDS:-20} isecs=${X4FUZZ_INVALID_SECONDS:-8} ;;
esac
dev=/dev/x4step0
mark() { # two bytes to the status register (addr 1 = 0x379)
	# shellcheck disable=SC2059 # the octal escape is the point
	for v in "$@"; do printf "\\$v" | dd of=/dev/port bs=1 seek=889 2>/dev/null; done
}
rc=0
insmod "$X4MOD/x4step.ko" || { echo "FAIL fuzz-insmod"; exit 1; }
[ -c $dev ] || { echo "FAIL fuzz-device: no $dev"; exit 1; }

mark 130 111 # 0x58 0x49: invalid-only phase starts
ioctl_fuzz --invalid-only --seed "$seed" --seconds "$isecs" --device $dev
irc=$?
mark 130 112 # 0x58 0x4a: invalid-only phase ends
if [ $irc -eq 0 ]; then echo "PASS fuzz-invalid-only"; else echo "FAIL fuzz-invalid-only (status $irc)"; rc=1; fi

ioctl_fuzz --seed "$seed" --seconds "$secs" --device $dev
frc=$?
if [ $frc -eq 0 ]; then echo "PASS fuzz-full"; else echo "FAIL fuzz-full (status $frc)"; rc=1; fi

if rmmod x4step; then echo "PASS fuzz-rmmod"; else echo "FAIL fuzz-rmmod"; rc=1; fi
exit $rc
