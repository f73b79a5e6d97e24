#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# The QEMU suite: for each Debian kernel (6.1, 6.12, 6.12-rt) build x4step.ko
# against its headers and run every guest test under tests/qemu/run-guest.sh.
#
# Usage: tests/qemu/run-suite.sh [-k KVER_SUBSTRING]... [-t TEST]... [-j JOBS] [-v]
#   -k/-t select kernels/tests (default: all); -j runs JOBS guests side by
#   side (default: X4_QEMU_JOBS or the number of CPUs), each test on each
#   kernel one guest, the longest tests first; -v streams the guest consoles
#   (to stderr, one guest at a time). X4_DEBUGKERNEL=1 adds the debug kernel
#   (tests/debugkernel) to the kernels.
# Output: one "PASS|FAIL|SKIP <test> <kver> [(<seconds> s)]" line per test and
# kernel, as the tests end (SKIP: the test does not apply to that kernel, with
# why; the time of a test that ran, to keep the suite's budget in sight), then
# "N passed, M failed".
# Logs: build/qemu/<kver>/<test>/ (console.log, dmesg.log, lpt.log,
# lpt-test.log, run.log, host-check.log), module build: build/qemu/<kver>/src.
set -euo pipefail
# wait -n -p (the job queue) needs bash 5.1.
if ((BASH_VERSINFO[0] * 100 + BASH_VERSINFO[1] < 501)); then
	echo "run-suite: bash 5.1 or newer is needed (this is $BASH_VERSION)" >&2
	echo "FAIL qemu suite: bash $BASH_VERSION is older than 5.1"
	exit 1
fi

top=$(cd "$(dirname "$0")/../.." && pwd)
qdir=$top/tests/qemu
bdir=${X4_QEMU_BUILD:-$top/build/qemu}

# The tests: "name|guest script|extra static bins|run-guest flags|host
# check|seconds". Paths are relative to the repository. Bins are
# space-separated; the host check (optional) runs after a passing guest as
# `CHECK OUTDIR KVER` with X4TRACE set to a built tools/x4trace, e.g. to
# assert on edge counts in OUTDIR/lpt-test.log; its status decides the test.
# In flags @KOUT@ stands for the kernel's build directory (x4vport.ko), @OUT@
# for the test's OUTDIR (tests of a kernel run side by side). Seconds: about
# how long the test takes on Debian's 6.12, for the longest to start first
# (empty: 60).
g=build/guest
tests=(
	"smoke|tests/qemu/smoke.sh|||tests/qemu/check-no-steps.sh|8"
	"module|tests/guest/module.sh|$g/module_test||tests/qemu/check-segments.sh|10"
	"keys|tests/guest/keys.sh|$g/keys_test||tests/qemu/check-segments.sh|10"
	"cpp|tests/guest/cpp.sh|$g/cpp_test|--module @KOUT@/src/tests/kmod/x4vport.ko|tests/qemu/check-segments.sh|13"
	"manual|tests/guest/manual.sh|$(echo $g/man_{errors,load,start,brake,init,getsteps,lastbrakecode,timer,getin,setout})|--monitor @OUT@/mon.sock|tests/qemu/check-segments.sh|15"
	"vport|tests/kmod/x4vport-guest.sh|$g/x4vctl|--module @KOUT@/src/tests/kmod/x4vport.ko||30"
	"fuzz|tests/fuzz/fuzz.sh|$g/ioctl_fuzz||tests/fuzz/check-no-edges.sh|56"
	"reliability|tests/guest/reliability.sh|$g/reliability_test||tests/qemu/check-segments.sh|50"
	"phase|tests/guest/phase.sh|$g/phase_test||tests/qemu/check-phase.sh|20"
	"x4ctl|tests/x4ctl/guest-x4ctl.sh|$g/x4ctl|--module @KOUT@/src/tests/kmod/x4vport.ko|tests/x4ctl/check-json.sh|65"
	"x4ctl-keys|tests/x4ctl/guest-x4ctl-keys.sh|$g/x4ctl|--monitor @OUT@/mon.sock||46"
	"timing|tests/guest/timing.sh|$g/timing_bench|--icount --module @KOUT@/src/tests/kmod/x4vport.ko --module @KOUT@/src/tests/kmod/x4hrbench.ko||30"
	"speed|tests/guest/speed.sh|$g/speed_bench|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko --module @KOUT@/src/tests/kmod/x4hrbench.ko||48"
	"discipline|tests/guest/discipline.sh|$g/discipline_test|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko||35"
	"ontime|tests/guest/ontime.sh|$g/ontime_test|--icount --module @KOUT@/src/tests/kmod/x4vport.ko||20"
	"positioning|tests/guest/positioning.sh|$g/positioning_test|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko|tests/qemu/check-positioning.sh|45"
	"brake|tests/guest/brake.sh|$g/brake_test|--icount --module @KOUT@/src/tests/kmod/x4vport.ko||20"
	"events|tests/guest/events.sh|$g/events_test|--module @KOUT@/src/tests/kmod/x4vport.ko||20"
	"config|tests/guest/config.sh|$g/config_test||tests/qemu/check-config.sh|18"
	"path|tests/guest/path.sh|$g/path_test|--icount --timeout 600 --module @KOUT@/src/tests/kmod/x4vport.ko|tests/qemu/check-segments.sh|45"
	"faith|tests/faith/faith.sh|$g/faith_moves tests/faith/faith.machine|--icount --module @KOUT@/src/tests/kmod/x4vport.ko|tests/faith/check-faith.sh|22"
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

mkdir -p "$bdir"

# The newest /boot/vmlinuz-* release matching GLOB, without EXCLUDE.
kernel_release() { # GLOB EXCLUDE
	local f
	cd /boot && for f in $1; do
		[ -e "$f" ] || continue
		[ -n "$2" ] && [[ "$f" == *"$2"* ]] && continue
		echo "${f#vmlinuz-}"
	done | sort -V | tail -n1
}

# Build x4step.ko and the test modules for one kernel in its own copy of the
# sources (one tree cannot hold several builds), and unpack the kernel for a
# faster boot (pvh-kernel.sh). Writes why it cannot run tests to $kout/why
# (empty: it can).
prepare_kernel() { # KVER
	local kver=$1 kdir kout why=""
	kdir=/lib/modules/$kver/build
	[ -d "$kdir" ] || kdir=/usr/src/linux-headers-$kver
	kout=$bdir/$kver
	rm -rf "$kout/src" "$kout/vmlinux-pvh" "$kout/why" # no stale "can run"
	mkdir -p "$kout/src/tests"
	if [ ! -d "$kdir" ]; then
		why="no headers for $kver (linux-headers package)"
	else
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
	# Without a PVH entry (the debug kernel) the guests boot /boot's image.
	"$qdir/pvh-kernel.sh" "/boot/vmlinuz-$kver" "$kout/vmlinux-pvh" || true
	echo "$why" >"$kout/why"
}

# Run one test on one kernel and print its result line(s).
run_test() { # KVER TEST
	local kver=$1 kout name script bins flags check out args rc why2 b started took=""
	IFS='|' read -r name script bins flags check _ <<<"$2"
	kout=$bdir/$kver
	out=$kout/$name
	rm -rf "$out"
	mkdir -p "$out"
	args=(--kver "$kver" --out "$out" --module "$kout/src/kmod/x4step.ko")
	[ -f "$kout/vmlinux-pvh" ] && args+=(--kernel "$kout/vmlinux-pvh")
	for b in $bins; do args+=(--bin "$top/$b"); done
	flags=${flags//@KOUT@/$kout}
	# shellcheck disable=SC2206 # flags are words by design
	args+=(${flags//@OUT@/$out})
	set +e
	started=$SECONDS
	if [ "$verbose" = 1 ]; then
		# The consoles to stderr: only result lines are counted.
		"$qdir/run-guest.sh" "${args[@]}" "$top/$script" 2>&1 | tee "$out/run.log" >&2
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
		return
	fi
	if [ -n "$check" ] && ! "$top/$check" "$out" "$kver" >"$out/host-check.log" 2>&1; then
		result FAIL "$name" "$kver" "host check $check failed, see $out/host-check.log"
		sed 's/^/    /' "$out/host-check.log" | tail -n 20
		return
	fi
	result PASS "$name" "$kver"
}

# The kernels to run, resolved to the newest release matching each kind.
kinds=()
for kind in "${kernel_kinds[@]}"; do
	IFS='|' read -r label glob exclude _ <<<"$kind"
	kver=$(kernel_release "$glob" "$exclude")
	selected "${kver:-$label}" "${want_k[@]}" || continue
	kinds+=("$kind|$kver")
done

# Built side by side: x4trace (host checks use it), the guest programs (the
# same for every kernel) and each kernel's modules.
rm -f "$bdir/x4trace"
if [ -f "$top/tools/x4trace/x4trace.cpp" ]; then
	g++ -std=c++17 -O2 -Wall -Wextra -o "$bdir/x4trace" "$top/tools/x4trace/x4trace.cpp" \
		>"$bdir/x4trace-build.log" 2>&1 &
fi
"$top/tests/guest/build.sh" "$top/build/guest" >"$bdir/guest-build.log" 2>&1 &
guest_build=$!
for kind in "${kinds[@]}"; do
	kver=${kind##*|}
	[ -z "$kver" ] || prepare_kernel "$kver" &
done
if ! wait "$guest_build"; then
	wait
	cat "$bdir/guest-build.log" >&2
	echo "FAIL building the guest programs, see $bdir/guest-build.log"
	echo "0 passed, 1 failed"
	exit 1
fi
wait
if [ -x "$bdir/x4trace" ]; then
	export X4TRACE=$bdir/x4trace
elif [ -f "$top/tools/x4trace/x4trace.cpp" ]; then
	echo "run-suite: building x4trace failed, see $bdir/x4trace-build.log" >&2
fi

# Every result goes to the terminal and to $all, which is counted at the end.
all=$bdir/suite.out
: >"$all"
report() { # FILE
	cat "$1"
	cat "$1" >>"$all"
}

# One job per kernel and test that has to boot; what needs no guest (SKIP,
# or FAIL for a kernel without headers or module) is reported at once.
joblist=()
for kind in "${kinds[@]}"; do
	IFS='|' read -r label glob _ skip kver <<<"$kind"
	why=""
	if [ -z "$kver" ]; then
		why="no /boot/$glob: install the Debian kernel package (tools/deps.sh test)"
	else
		why=$(cat "$bdir/$kver/why" 2>/dev/null || echo "preparing $kver failed, see $bdir/$kver")
		label=$kver
	fi
	for ti in "${!tests[@]}"; do
		IFS='|' read -r name _ _ _ _ secs <<<"${tests[ti]}"
		selected "$name" "${want_t[@]}" || continue
		if [ -n "$why" ]; then
			result FAIL "$name" "$label" "$why"
		elif [[ " ${skip%%:*} " == *" $name "* ]]; then
			result SKIP "$name" "$kver" "${skip#*:}"
		else
			joblist+=("${secs:-60} $ti $kver")
			continue
		fi >"$bdir/direct.out"
		report "$bdir/direct.out"
	done
done

# The jobs, JOBS guests side by side (each is one TCG thread). One at a time
# they run in order; side by side the longest start first, so that the CPUs
# finish together. Each result is printed when its test is done.
# (No process substitution here: wait -n would see it end.)
[ "$jobs" = 1 ] || [ ${#joblist[@]} = 0 ] ||
	mapfile -t joblist <<<"$(printf '%s\n' "${joblist[@]}" | sort -s -k1,1nr)"
declare -A job_out
running=0
reap() { # wait for a job to end and print its result
	local pid="" st=0 f
	wait -n -p pid || st=$?
	if [ -n "$pid" ] && [ -n "${job_out[$pid]:-}" ]; then
		f=${job_out[$pid]}
		# A job that died before its result line still counts, as a FAIL.
		grep -qE '^(PASS|FAIL|SKIP) ' "$f" ||
			echo "FAIL $(basename "$f" .out) (the job ended with status $st and no result, see $f)" >>"$f"
		report "$f"
		running=$((running - 1))
	elif [ "$st" = 127 ]; then
		running=0 # no job left to wait for
	fi
}
mkdir -p "$bdir/jobs"
for job in "${joblist[@]}"; do
	read -r _ ti kver <<<"$job"
	f=$bdir/jobs/$kver-${tests[ti]%%|*}.out
	if [ "$jobs" = 1 ]; then
		run_test "$kver" "${tests[ti]}" | tee -a "$all"
		continue
	fi
	while [ "$running" -ge "$jobs" ]; do reap; done
	run_test "$kver" "${tests[ti]}" >"$f" 2>&1 &
	job_out[$!]=$f
	running=$((running + 1))
done
while [ "$running" -gt 0 ]; do reap; done

passed=$(grep -c '^PASS' "$all" || true)
failed=$(grep -c '^FAIL' "$all" || true)
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
