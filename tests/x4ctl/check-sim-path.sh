#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# x4ctl --sim path: a path file streams to its end on the simulated port,
# in virtual time (fast) and in real time (its own time), with progress;
# a line the port cannot step fails before anything moves.
#   check-sim-path.sh X4CTL
set -u
x4ctl=$1
# shellcheck source=tests/x4ctl/check-lib.sh
. "$(dirname "$0")/check-lib.sh"

# 600 lines (more than the queue's 256): a 24-gon, 25 times round, 100 steps a side.
awk 'BEGIN { for (i = 0; i < 600; i++) { a = i * 3.14159265 / 12;
	printf "%d %d\n", 100 * cos(a), 100 * sin(a) } }' >"$dir/circle.txt"
start=$(date +%s%N)
X4STEP_SIM_TIME=virtual timeout 30 "$x4ctl" --sim path --json -s 4000 "$dir/circle.txt" >"$dir/virtual.out" 2>&1
st=$?
took=$((($(date +%s%N) - start) / 1000000))
tail -n 1 "$dir/virtual.out"
check "virtual time: exit 0" $st
tail -1 "$dir/virtual.out" | grep -q "\"state\":\"idle\".*\"done\":600,\"total\":600"
check "virtual time: the last progress record says 600 of 600 done" $?
grep '"state":"running"' "$dir/virtual.out" | head -1 | grep -qE '"speed":[0-9.]+[,}]'
check "virtual time: a running record's speed is a number (steps/s)" $?
# Host time, so the bound is the one a loaded host cannot break: the motion
# is 15 s (60000 steps at 4000 steps/s at most), which a run in real time
# cannot beat; in virtual time it takes some 30 ms of CPU.
[ "$took" -lt 15000 ]
check "virtual time: 15 s of motion in ${took} ms (less than the motion's own time)" $?

# Real time: 8 sides of 1000 steps at 8000 steps/s take more than 1 s.
printf '1000 0\n0 1000\n-1000 0\n0 -1000\n1000 0\n0 1000\n-1000 0\n0 -1000\n' >"$dir/square.txt"
start=$(date +%s%N)
X4STEP_SIM_TIME=real timeout 60 "$x4ctl" --sim path -s 8000 "$dir/square.txt" >"$dir/real.out" 2>&1
st=$?
took=$((($(date +%s%N) - start) / 1000000))
cat "$dir/real.out"
check "real time: exit 0" $st
grep -q '^path: done, 8 of 8 segments, at 0 0 0 0$' "$dir/real.out"
check "real time: done, back at 0" $?
# Only the lower bound, which no load can break (a late timer only stretches
# the motion): the time a loaded host adds is unbounded (the timeout above
# catches a run that never ends).
[ "$took" -ge 1000 ]
check "real time: took ${took} ms (at least the motion's 1 s)" $?

# A line faster than the port steps: refused, naming it, nothing runs.
printf '100 0\n100 0 speed=150000\n' >"$dir/fast.txt"
X4STEP_SIM_TIME=virtual "$x4ctl" --sim path "$dir/fast.txt" >"$dir/fast.out" 2>&1
st=$?
cat "$dir/fast.out"
[ $st -ne 0 ] && grep -q 'fast.txt:2' "$dir/fast.out" && ! grep -q '^path: done' "$dir/fast.out"
check "a bad line fails, naming file and line, before anything moves" $?
exit $failed
