#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# `make check`: host unit tests, static checks and the engine's mutation
# run, then the QEMU suite on the Debian kernels and the debug kernel. Ends
# with one line `N passed, M failed` counting every test case of all parts.
set -u
top=$(cd "$(dirname "$0")/.." && pwd)
cd "$top" || exit 2
build=${BUILD:-$top/build}
log=$build/check
mkdir -p "$log"
passed=0 failed=0
count() { # LOGFILE: add its PASS/FAIL lines
	p=$(grep -c '^PASS' "$1")
	f=$(grep -c '^FAIL' "$1")
	passed=$((passed + p))
	failed=$((failed + f))
}

echo "== host: build and unit tests"
if make -s userspace BUILD="$build" >"$log/build.log" 2>&1; then
	# --timeout: a test that hangs (a wait that never ends) fails in 5 min.
	(cd "$build" && ctest --output-on-failure --no-tests=error -j2 --timeout 300) >"$log/ctest.log" 2>&1
	tail -n 3 "$log/ctest.log"
	# One PASS/FAIL line per test case, from CTest's report: anything but
	# "Passed" (failed, not run, timeout) fails, and so does a count that
	# does not match CTest's total.
	awk '/^ *[0-9]+\/[0-9]+ +Test +#[0-9]+: / {
		print ($0 ~ / Passed +[0-9.]+ sec$/ ? "PASS" : "FAIL"), $4; n++
	}
	/tests passed, .* tests failed out of / { total = $NF }
	END { if (n != total) print "FAIL host: " n " results for " total " tests in ctest.log" }' \
		"$log/ctest.log" >"$log/host.results"
	count "$log/host.results"
	grep '^FAIL' "$log/host.results"
else
	cat "$log/build.log"
	echo "FAIL host build" | tee "$log/host.results"
	count "$log/host.results"
fi

# The static checks and the engine's mutation run side by side: each keeps
# about one CPU busy for a minute or two.
tests/check-style.sh >"$log/style.log" 2>&1 &
style=$!
BUILD="$build" tests/mutation/run.sh >"$log/mutation.log" 2>&1 &
mutation=$!

echo "== static checks"
wait $style
st=$?
# A check script that died without its FAIL line still fails.
[ $st -ne 0 ] && ! grep -q '^FAIL' "$log/style.log" &&
	echo "FAIL static checks: check-style.sh ended with status $st, see $log/style.log" >>"$log/style.log"
grep -E '^(PASS|FAIL)' "$log/style.log"
grep -q '^FAIL' "$log/style.log" && cat "$log/style.log"
count "$log/style.log"

# The mutation run: every one-line mutation of tests/mutation/mutations.txt
# must fail a host test. One PASS/FAIL line.
wait $mutation
st=$?
score=$(tail -n 1 "$log/mutation.log" | sed "s/^mutation score: //")
if [ $st -eq 0 ]; then
	echo "PASS mutation run: $score"
else
	echo "FAIL mutation run: $score (see $log/mutation.log)"
fi >"$log/mutation.results"
cat "$log/mutation.results"
grep -E '^(SURVIVED|INVALID)' "$log/mutation.log"
count "$log/mutation.results"

echo "== debug kernel: build or reuse (tests/debugkernel)"
# Lockdep, KASAN, UBSAN, atomic-sleep and debugobjects: the QEMU suite runs
# on it too. Built once per config and source version (about 7 min), cached.
release=$(tests/debugkernel/build.sh "$build/debugkernel" 2>"$log/debugkernel.log" | tail -n1)
if [ -n "$release" ] && [ -r "/boot/vmlinuz-$release" ]; then
	cat "$log/debugkernel.log"
	export X4_DEBUGKERNEL=1
else
	tail -n 5 "$log/debugkernel.log"
	echo "FAIL debug kernel: not built or not installed (run make check as root), see $log/debugkernel.log" |
		tee "$log/debugkernel.results"
	count "$log/debugkernel.results"
fi

echo "== QEMU: the module on Debian's kernels and the debug kernel"
tests/qemu/run-suite.sh | tee "$log/qemu.log"
grep -qE '^(PASS|FAIL)' "$log/qemu.log" || echo "FAIL qemu suite ran nothing" >>"$log/qemu.log"
count "$log/qemu.log"

echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
