#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# The QEMU suite: for each Debian kernel (6.1, 6.12, 6.12-rt) build x4step.ko
# against its headers and run every guest test under tests/qemu/run-guest.sh.
#
# Usage: tests/qemu/run-suite.sh [-k KVER_SUBSTRING]... [-t TEST]... [-j JOBS] [-v]
#   -k/-t select kernels/tests (default: all); -j runs JOBS kernels side by
#   side (default: X4_QEMU_JOBS or the number of CPUs); -v streams the guest
#   consoles (and runs one kernel at a time). X4_DEBUGKERNEL=1 adds the debug
#   kernel (tests/debugkernel) to the kernels.
# Output: one "PASS|FAIL|SKIP <test> <kver> [(<seconds> s)]" line per test and
# kernel (SKIP: the test does not apply to that kernel, with why; the time of a
# test that ran, to keep the suite's budget in sight), then "N passed, M failed".
# Logs: build/qemu/<kver>/<test>/ (console.log, dmesg.log, lpt.log,
# lpt-test.log, run.log, host-check.log), module build: build/qemu/<kver>/src.
set -euo pipefail

top=$(cd "$(dirname "$0")/../.." && pwd)
qdir=$top/tests/qemu
bdir=${X4_QEMU_BUILD:-$top/build/qemu}

# The tests: "name|guest script|extra static bins|run-guest flags|host check".
# Paths are relative to the repository. Bins are space-separated; the host
# check (optional) runs after a passing guest as `CHECK OUTDIR KVER` with
# X4TRACE set to a built tools/x4trace, e.g. to assert on edge counts in
# OUTDIR/lpt-test.log; its status decides the test.
# @KOUT@ in flags stands for the kernel's build directory (x4vport.ko).
g=build/guest
tests=(
	"smoke|tests/qemu/smoke.sh|||tests/qemu/check-no-steps.sh"
	"module|tests/guest/module.sh|$g/module_test||tests/qemu/check-segments.sh"
	"keys|tests/guest/keys.sh|$g/keys_test||tests/qemu/check-segments.sh"
	"cpp|tests/guest/cpp.sh|$g/cpp_test|--module @KOUT@/src/tests/kmod/x4vport.ko|tests/qemu/check-segments.sh"
	"manual|tests/guest/manual.sh|$(echo $g/man_{errors,load,start,brake,init,getsteps,lastbrakecode,timer,getin,setout})|--monitor @KOUT@/mon.sock|tests/qemu/check-segments.sh"
	"vport|tests/kmod/x4vport-guest.sh|$g/x4vctl|--module @KOUT@/src/tests/kmod/x4vport.ko|"
	"fuzz|tests/fuzz/fuzz.sh|$g/ioctl_fuzz||tests/fuzz/check-no-edges.sh"
	"reliability|tests/guest/reliability.sh|$g/reliability_test||tests/qemu/check-segments.sh"
	"phase|tests/guest/phase.sh|$g/phase_test||tests/qemu/check-phase.sh"
	"x4ctl|tests/x4ctl/guest-x4ctl.sh|$g/x4ctl|--module @KOUT@/src/tests/kmod/x4vport.ko|tests/x4ctl/check-json.sh"
	"x4ctl-keys|tests/x4ctl/guest-x4ctl-keys.sh|$g/x4ctl|--monitor @KOUT@/mon.sock|"
	"timing|tests/guest/timing.sh|$g/timing_bench|--icount --module @KOUT@/src/tests/kmod/x4vport.ko --module @KOUT@/src/tests/kmod/x4hrbench.ko|"
	"speed|tests/guest/speed.sh|$g/speed_bench|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko --module @KOUT@/src/tests/kmod/x4hrbench.ko|"
	"discipline|tests/guest/discipline.sh|$g/discipline_test|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko|"
	"positioning|tests/guest/positioning.sh|$g/positioning_test|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko|tests/qemu/check-positioning.sh"
	"events|tests/guest/events.sh|$g/events_test|--module @KOUT@/src/tests/kmod/x4vport.ko|"
	"config|tests/guest/config.sh|$g/config_test||tests/qemu/check-config.sh"
	"path|tests/guest/path.sh|$g/path_test|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko|tests/qemu/check-segments.sh"
	"faith|tests/faith/faith.sh|$g/faith_moves tests/faith/faith.machine|--icount --module @KOUT@/src/tests/kmod/x4vport.ko|tests/faith/check-faith.sh"
)

# The kernels the module must pass on: label, glob under /boot, exclusion,
# and "TEST...:WHY" for tests that do not apply to that kernel.
kernel_kinds=(
	"6.1|vmlinuz-6.1.*-amd64|-rt-|"
	"6.12|vmlinuz-6.12.*-amd64|-rt-|"
	"6.12-rt|vmlinuz-6.12.*-rt-amd64||"
)
# The debug kernel (tests/debugkernel) only when asked, as it is built
# locally; first, as it is the slowest.
[ -n "${X4_DEBUGKERNEL:-}" ] && kernel_kinds=(
	"debug|vmlinuz-*-x4debug||timing speed faith:its timer is ~16 us late (Debian's ~0.6 us), too late for the microsecond checks (timing, faith) and the speed ceiling (measured on Debian's kernels; paths at 100 kHz run here in the path test)"
	"${kernel_kinds[@]}")

want_k=() want_t=() verbose=0 jobs=${X4_QEMU_JOBS:-$(nproc)}
while [ $# -gt 0 ]; do
	case "$1" in
	-k) want_k+=("${2:?}"); shift 2 ;;
	-t) want_t+=("${2:?}"); shift 2 ;;
	-j) jobs=${2:?}; shift 2 ;;
	-v) verbose=1; shift ;;
	*) echo "usage: $0 [-k KVER_SUBSTRING]... [-t TEST]... [-j JOBS] [-v]" >&2; exit 2 ;;
	esac
done
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || { echo "run-suite: -j wants a positive number, not '$jobs'" >&2; exit 2; }
[ "$verbose" = 1 ] && jobs=1 # one console stream at a time
selected() { # VALUE PATTERNS... : no patterns selects everything
	local v=$1 p
	shift
	[ $# -eq 0 ] && return 0
	for p in "$@"; do [[ "$v" == *"$p"* ]] && return 0; done
	return 1
}

result() { # PASS|FAIL|SKIP TEST KVER [WHY]: with the test's time once it ran
	echo "$1 $2 $3${took:+ ($took s)}"
	[ -z "${4:-}" ] || echo "    $4"
}

# Host checks use x4trace; build it once if its source is there.
mkdir -p "$bdir"
if [ -f "$top/tools/x4trace/x4trace.cpp" ]; then
	if g++ -std=c++17 -O2 -Wall -Wextra -o "$bdir/x4trace" "$top/tools/x4trace/x4trace.cpp" \
		2>"$bdir/x4trace-build.log"; then
		export X4TRACE=$bdir/x4trace
	else
		echo "run-suite: building x4trace failed, see $bdir/x4trace-build.log" >&2
	fi
fi

# The guest programs are the same for every kernel.
if ! "$top/tests/guest/build.sh" "$top/build/guest" >"$bdir/guest-build.log" 2>&1; then
	cat "$bdir/guest-build.log" >&2
	echo "FAIL building the guest programs, see $bdir/guest-build.log"
	echo "0 passed, 1 failed"
	exit 1
fi

# Run the selected tests on one kernel, printing result lines.
kernel_release() { # GLOB EXCLUDE: the newest /boot/vmlinuz-* release matching
	local f
	cd /boot && for f in $1; do
		[ -e "$f" ] || continue
		[ -n "$2" ] && [[ "$f" == *"$2"* ]] && continue
		echo "${f#vmlinuz-}"
	done | sort -V | tail -n1
}

# Run the selected tests on one kernel, printing result lines.
run_kernel() { # KIND|RELEASE (empty: not installed)
	local label glob exclude skip kver kdir kout why t name script bins flags check out args rc why2 b started took=""
	IFS='|' read -r label glob exclude skip kver <<<"$1"
	if [ -z "$kver" ]; then
		for t in "${tests[@]}"; do
			name=${t%%|*}
			selected "$name" "${want_t[@]}" || continue
			result FAIL "$name" "$label" "no /boot/$glob: install the Debian kernel package (tools/deps.sh test)"
		done
		return
	fi
	kdir=/lib/modules/$kver/build
	[ -d "$kdir" ] || kdir=/usr/src/linux-headers-$kver
	kout=$bdir/$kver

	# Each kernel builds in its own copy: one tree cannot hold three builds.
	why=""
	if [ ! -d "$kdir" ]; then
		why="no headers for $kver (linux-headers package)"
	else
		rm -rf "$kout/src"
		mkdir -p "$kout/src"
		mkdir -p "$kout/src/tests"
		cp -a "$top/Kbuild" "$top/kmod" "$top/include" "$kout/src/"
		cp -a "$top/tests/kmod" "$kout/src/tests/"
		find "$kout/src" \( -name '*.o' -o -name '*.ko' -o -name '*.mod*' -o -name '.*.cmd' \
			-o -name modules.order -o -name Module.symvers \) -delete
		if ! make -C "$kdir" M="$kout/src" modules >"$kout/build.log" 2>&1; then
			why="module build failed, see $kout/build.log"
		elif ! make -C "$kdir" M="$kout/src/tests/kmod" modules >>"$kout/build.log" 2>&1; then
			why="x4vport build failed, see $kout/build.log"
		elif [ ! -f "$kout/src/kmod/x4step.ko" ]; then
			why="no kmod/x4step.ko after the build, see $kout/build.log"
		fi
	fi

	for t in "${tests[@]}"; do
		IFS='|' read -r name script bins flags check <<<"$t"
		took=""
		selected "$name" "${want_t[@]}" || continue
		if [[ " ${skip%%:*} " == *" $name "* ]]; then
			result SKIP "$name" "$kver" "${skip#*:}"
			continue
		fi
		if [ -n "$why" ]; then
			result FAIL "$name" "$kver" "$why"
			continue
		fi
		out=$kout/$name
		rm -rf "$out"
		mkdir -p "$out"
		args=(--kver "$kver" --out "$out" --module "$kout/src/kmod/x4step.ko")
		for b in $bins; do args+=(--bin "$top/$b"); done
		# shellcheck disable=SC2206 # flags are words by design
		args+=(${flags//@KOUT@/$kout})
		set +e
		started=$SECONDS
		if [ "$verbose" = 1 ]; then
			"$qdir/run-guest.sh" "${args[@]}" "$top/$script" 2>&1 | tee "$out/run.log"
			rc=${PIPESTATUS[0]}
		else
			"$qdir/run-guest.sh" "${args[@]}" "$top/$script" >"$out/run.log" 2>&1
			rc=$?
		fi
		set -e
		took=$((SECONDS - started))
		if [ "$rc" -ne 0 ]; then
			case "$rc" in
			124) why2="timeout" ;;
			125) why2="guest crashed" ;;
			126) why2="kernel reported problems" ;;
			*) why2="guest status $rc" ;;
			esac
			result FAIL "$name" "$kver" "$why2, see $out/run.log"
			# Show what failed without making the developer open the log.
			tr -d '\r' <"$out/run.log" | grep -a -E '^FAIL |^run-guest:' | sed 's/^/    /' | head -n 20 || true
			continue
		fi
		if [ -n "$check" ] && ! "$top/$check" "$out" "$kver" >"$out/host-check.log" 2>&1; then
			result FAIL "$name" "$kver" "host check $check failed, see $out/host-check.log"
			sed 's/^/    /' "$out/host-check.log" | tail -n 20
			continue
		fi
		result PASS "$name" "$kver"
	done
}

# The kernels to run, resolved to the newest release matching each kind.
kinds=()
for kind in "${kernel_kinds[@]}"; do
	IFS='|' read -r label glob exclude _ <<<"$kind"
	kver=$(kernel_release "$glob" "$exclude")
	selected "${kver:-$label}" "${want_k[@]}" || continue
	kinds+=("$kind|$kver")
done

# Kernels run side by side, JOBS at a time (each guest is one TCG thread);
# each prints its block when it is done, in order.
outs=() pids=()
for i in "${!kinds[@]}"; do
	outs[i]=$bdir/suite-$i.out
	if [ "$jobs" = 1 ]; then
		run_kernel "${kinds[i]}" | tee "${outs[i]}"
		continue
	fi
	while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
	run_kernel "${kinds[i]}" >"${outs[i]}" 2>&1 &
	pids[i]=$!
done
if [ "$jobs" != 1 ]; then
	for i in "${!kinds[@]}"; do
		wait "${pids[i]}" || true
		cat "${outs[i]}"
	done
fi

passed=$(cat "${outs[@]}" /dev/null | grep -c '^PASS' || true)
failed=$(cat "${outs[@]}" /dev/null | grep -c '^FAIL' || true)
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
