#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# The QEMU suite: for each Debian kernel (6.1, 6.12, 6.12-rt) build x4step.ko
# against its headers and run every guest test under tests/qemu/run-guest.sh.
#
# Usage: tests/qemu/run-suite.sh [-k KVER_SUBSTRING]... [-t TEST]... [-j JOBS] [-v] [-l]
#   -k/-t select kernels/tests (default: all; a test is a folder of
#   tests/qemu, see below); -l lists the selected tests and exits; -j runs JOBS guests side by
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

# The tests: every folder tests/qemu/NAME/ with a guest script NAME.sh is
# one test, run in the guest by run-guest.sh. The script's "#: KEY VALUE"
# lines say how (tests/qemu/README.md):
#   #: bins WORD...   the static programs for the guest's /bin: a file of the
#                     test's folder (faith.machine) or a program tests/qemu/build.sh
#                     builds into build/guest
#   #: flags ...      run-guest.sh flags; @FIXTURES@ stands for the kernel's
#                     built tests/qemu/fixtures (x4vport.ko), @OUT@ for the
#                     test's OUTDIR (tests of a kernel run side by side)
#   #: check FILE     the host check, relative to the folder, run after a
#                     passing guest as `CHECK OUTDIR KVER` with X4TRACE set to a
#                     built tests/tools/x4trace; its status decides the test
#   #: seconds N      about how long the test takes on Debian's 6.12, for the
#                     longest to start first (none: 60)
# Entries are "name|guest script|bins|flags|check|seconds", paths relative to
# the repository.
meta() { # SCRIPT KEY: the value of its "#: KEY" line
	sed -n "s/^#: $2 //p" "$1" | head -n 1
}
tests=()
for script in "$qdir"/*/; do
	name=$(basename "$script")
	script=$qdir/$name/$name.sh
	[ -f "$script" ] || continue # common/, fixtures/: no test
	rel=tests/qemu/$name
	bins=""
	for b in $(meta "$script" bins); do
		if [ -e "$qdir/$name/$b" ]; then bins="$bins $rel/$b"; else bins="$bins build/guest/$b"; fi
	done
	check=$(meta "$script" check)
	tests+=("$name|$rel/$name.sh|${bins# }|$(meta "$script" flags)|${check:+$rel/$check}|$(meta "$script" seconds)")
done

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

want_k=() want_t=() verbose=0 list=0 jobs=${X4_QEMU_JOBS:-$(nproc)}
while [ $# -gt 0 ]; do
	case "$1" in
	-k) want_k+=("${2:?}"); shift 2 ;;
	-t) want_t+=("${2:?}"); shift 2 ;;
	-j) jobs=${2:?}; shift 2 ;;
	-v) verbose=1; shift ;;
	-l) list=1; shift ;;
	*) echo "usage: $0 [-k KVER_SUBSTRING]... [-t TEST]... [-j JOBS] [-v] [-l]" >&2; exit 2 ;;
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

if [ "$list" = 1 ]; then # one "name|guest script|bins|flags|check|seconds" line per test
	for t in "${tests[@]}"; do selected "${t%%|*}" "${want_t[@]}" && echo "$t"; done
	exit 0
fi

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
	mkdir -p "$kout/src"
	if [ ! -d "$kdir" ]; then
		why="no headers for $kver (linux-headers package)"
	else
		cp -a "$top/Kbuild" "$top/kmod" "$top/include" "$kout/src/"
		mkdir -p "$kout/src/tests/qemu"
		cp -a "$qdir/fixtures" "$kout/src/tests/qemu/"
		find "$kout/src" \( -name '*.o' -o -name '*.ko' -o -name '*.mod*' -o -name '.*.cmd' \
			-o -name modules.order -o -name Module.symvers \) -delete
		if ! make -C "$kdir" M="$kout/src" modules >"$kout/build.log" 2>&1; then
			why="module build failed, see $kout/build.log"
		elif ! make -C "$kdir" M="$kout/src/tests/qemu/fixtures" modules >>"$kout/build.log" 2>&1; then
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
	flags=${flags//@FIXTURES@/$kout/src/tests/qemu/fixtures}
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
if [ -f "$top/tests/tools/x4trace/x4trace.cpp" ]; then
	g++ -std=c++17 -O2 -Wall -Wextra -o "$bdir/x4trace" "$top/tests/tools/x4trace/x4trace.cpp" \
		>"$bdir/x4trace-build.log" 2>&1 &
fi
"$top/tests/qemu/build.sh" "$top/build/guest" >"$bdir/guest-build.log" 2>&1 &
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
elif [ -f "$top/tests/tools/x4trace/x4trace.cpp" ]; then
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
		why="no /boot/$glob: install the Debian kernel package (scripts/deps.sh test)"
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
