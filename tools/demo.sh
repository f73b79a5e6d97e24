#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# make demo: the X4Step manual's first example on an emulated parallel
# port. Boots Debian's kernel in QEMU with x4step loaded, runs
#   x4ctl move 1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400
# (load, start, preload the way back, start it when the first move ends)
# and shows what the pins did, from QEMU's own trace of the port writes:
# edge counts and timing per axis, a VCD file and an SVG plot of each
# axis's step frequency over time.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/build/demo
mkdir -p "$out"
cd "$top"

echo "== building (module, library, x4ctl, x4trace)"
make -s userspace >"$out/build.log" 2>&1 || { cat "$out/build.log"; exit 1; }
kver=$(cd /boot && ls vmlinuz-*-amd64 | grep -v -- -rt- | sed 's/^vmlinuz-//' | sort -V | head -n 1)
src=$out/src
rm -rf "$src"
mkdir -p "$src"
cp -r Kbuild kmod include "$src/"
make -s -C "/usr/src/linux-headers-$kver" M="$src" modules >>"$out/build.log" 2>&1 ||
	{ cat "$out/build.log"; exit 1; }
tests/guest/build.sh "$top/build/guest" >>"$out/build.log" 2>&1 || { cat "$out/build.log"; exit 1; }

cat >"$out/guest.sh" <<'GUEST'
insmod "$X4MOD/x4step.ko" || exit 1
set -x
echo
x4ctl move 1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400 --wait | cat
x4ctl status
GUEST

echo "== booting Linux $kver in QEMU with an emulated parallel port"
tests/qemu/run-guest.sh --kver "$kver" --out "$out/qemu" --module "$src/kmod/x4step.ko" \
	--bin "$top/build/guest/x4ctl" "$out/guest.sh" >"$out/qemu.log" 2>&1 ||
	{ tail -n 30 "$out/qemu.log"; exit 1; }
tr -d '\r' <"$out/qemu/console.log" | sed -n '/^+ x4ctl/,/X4GUEST-EXIT/p' | grep -v X4GUEST-EXIT

trace=$out/qemu/lpt-test.log
x4trace=$top/build/tools/x4trace
echo
echo "== what the pins did (QEMU's trace of the port writes; host time, so timing under TCG is approximate)"
"$x4trace" moves "$trace"
"$x4trace" summary "$trace" | sed -n '/^axis/,$p'
"$x4trace" vcd "$trace" "$out/demo.vcd"
"$x4trace" svg "$trace" "$out/demo.svg"
echo
echo "VCD (GTKWave, PulseView): $out/demo.vcd"
echo "step frequency per axis over time (SVG): $out/demo.svg"

# The same example on libx4step's simulated port: no QEMU, module or root.
sim="X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD=$out/sim.vcd build/tools/x4ctl/x4ctl --sim move 1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400 --wait"
echo
echo "== the same example simulated (libx4step's simulated port: no QEMU, no module, no root), in one line:"
echo "   $sim"
env X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD="$out/sim.vcd" "$top/build/tools/x4ctl/x4ctl" --sim \
	move 1000 800 600 400 --freq 1000 --ramp 50 --then -1000 -800 -600 -400 --wait
echo "its VCD: $out/sim.vcd"
