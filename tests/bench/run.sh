#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Engine benchmark: prints instructions per leader step (callgrind counts
# instructions, so the figure is reproducible), edge-time error and state
# size for a 4-axis 20 kHz move with 50 ms ramps, and the mutation score.
set -eu
build=${BUILD:-build}
bench=$build/tests/engine_bench
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failed=0

echo "== engine: 4 axes (20000/15000/-10000/5000 steps), 20 kHz, 50 ms ramps"
"$bench"

cg="valgrind --tool=callgrind --toggle-collect=x4_engine_load --toggle-collect=x4_engine_start --toggle-collect=x4_engine_fire"
$cg --callgrind-out-file="$tmp/all" "$bench" >/dev/null 2>&1
total=$(sed -n 's/^totals: *//p' "$tmp/all")
echo "instructions in the engine: $total total, $((total / 20000)) per leader step (goal <= 150)"

$cg --callgrind-out-file="$tmp/step" "$bench" --per-step >/dev/null 2>&1
# One dump per leader step (rise + fall); the biggest is the costliest step.
cat "$tmp"/step.* 2>/dev/null | sed -n 's/^totals: *//p' | sort -n |
	awk '{v[NR]=$1} END {printf "per leader step: median %d, p99 %d, max %d instructions (goal max <= 400)\n", v[int(NR/2)], v[int(NR*0.99)], v[NR]}'

$cg --callgrind-out-file="$tmp/hit" "$bench" --limit-hit >/dev/null 2>&1 || echo "(the limit-hit run failed)"
hit=$(cat "$tmp"/hit.* 2>/dev/null | sed -n 's/^totals: *//p' | sort -n | tail -n1)
echo "worst single event: a shared limit ending four axes' moves: $hit instructions"

echo
# Junction and ramp fidelity (issue 18): the edges of a multi-segment path
# against a double-precision reference of its plan; a bound exceeded makes
# this script exit non-zero at its end.
echo "== paths: junction and ramp fidelity against the plan in double (tests/bench/path_bench.cpp --junctions)"
"$build/tests/path_bench" --junctions || failed=1
echo

for chord in 4 20; do
	echo "== paths: a circle of 5000 chords of $chord steps, 10000 steps/s, 256-segment queue (tests/bench/path_bench.cpp)"
	"$build/tests/path_bench" --chord $chord
	"$build/tests/path_bench" --chord $chord --reference | grep -v '^path:'
	valgrind --tool=callgrind --toggle-collect=x4_engine_fire --callgrind-out-file="$tmp/path" \
		"$build/tests/path_bench" --chord $chord >"$tmp/path.out" 2>&1
	steps=$(sed -n 's/.*chords, \([0-9]*\) leader steps.*/\1/p' "$tmp/path.out")
	total=$(sed -n 's/^totals: *//p' "$tmp/path")
	echo "engine in path mode: $((total / steps)) instructions per leader step (goal <= 160)"
	rm -f "$tmp"/push.*
	valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$tmp/push" \
		"$build/tests/path_bench" --chord $chord --per-push >/dev/null 2>&1
	cat "$tmp"/push.* 2>/dev/null | sed -n 's/^totals: *//p' | sort -n |
		awk '{v[NR]=$1; s+=$1} END {printf "planner per appended segment: mean %d, max %d instructions (%d segments)\n", s/NR, v[NR], NR}'
	echo "the planner unbounded (every pass run through at each push, as before issue 28):"
	"$build/tests/path_bench" --chord $chord --unbounded | grep '^path:'
	echo
done

# The planner's worst case (issue 28 item 6): short segments through a
# queue shorter than their stop distance, where every push can raise every
# entry; a push plans a bounded part of the pass (goal <= 5000
# instructions per appended segment at any depth).
echo "== paths: the planner per appended segment, worst case (4-step segments, 200 000 steps to stop)"
worst=0
for depth in 256 4096; do
	rm -f "$tmp"/push.*
	valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$tmp/push" \
		"$build/tests/path_bench" --worst $depth --per-push >/dev/null 2>&1
	line=$(cat "$tmp"/push.* 2>/dev/null | sed -n 's/^totals: *//p' | sort -n |
		awk '{v[NR]=$1; s+=$1} END {printf "%d %d %d", s/NR, v[NR], NR}')
	# shellcheck disable=SC2086 # its three numbers as the arguments
	set -- $line
	echo "depth $depth: mean $1, max $2 instructions per appended segment ($3 segments)"
	[ "${2:-0}" -gt "$worst" ] && worst=$2
	"$build/tests/path_bench" --worst $depth
	rm -f "$tmp"/push.*
	valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file="$tmp/push" \
		"$build/tests/path_bench" --worst $depth --per-push --unbounded >/dev/null 2>&1
	cat "$tmp"/push.* 2>/dev/null | sed -n 's/^totals: *//p' | sort -n |
		awk '{v[NR]=$1; s+=$1} END {printf "unbounded (before issue 28): mean %d, max %d instructions per appended segment\n", s/NR, v[NR]}'
	"$build/tests/path_bench" --worst $depth --unbounded | sed 's/^/unbounded: /'
done
echo "worst case: $worst instructions per appended segment (goal <= 5000)"
[ "$worst" -gt 0 ] && [ "$worst" -le 5000 ] || failed=1
echo

# The G-code interpreter and planner (issue 20): lines per second from a
# 100 000-line file of a real CAM program (LinuxCNC's plasmatest.ngc)
# repeated, then `x4ctl gcode --check` of that file (goal: under a second)
# and its peak memory (the program is streamed, never held whole).
echo "== G-code interpreter and planner: 100 000 lines of CAM output (tests/bench/gcode_bench.cpp)"
if "$build/tests/gcode_bench" /var/cache/x4step/linuxcnc/root/usr/share/linuxcnc/ncfiles/plasmatest.ngc \
	100000 "$tmp/cam"; then
	/usr/bin/time -f '%e s %M' "$build/tools/x4ctl/x4ctl" gcode --machine "$tmp/cam.ini" --check "$tmp/cam.ngc" \
		>"$tmp/check.out" 2>"$tmp/check.time" || cat "$tmp/check.time"
	read -r secs _ kb <"$tmp/check.time" || true
	echo "x4ctl gcode --check: ${secs:-?} s (goal < 1 s), peak memory ${kb:-?} kB: $(head -n1 "$tmp/check.out")"
else
	echo "(the G-code bench failed: scripts/get-rs274.sh fetches its program)"
fi
echo

# The same for arc-heavy CAM output (issue 30): Fusion 360's LinuxCNC post's
# style, adaptive clearing (1220 arcs in 1352 lines, 16 chords an arc at
# 0.01 mm) and drilling cycles, tests/gcode/cam/fusion360-linuxcnc.ngc
# repeated to 100 000 lines; then callgrind's instructions per line of
# `x4ctl gcode --check` on 10 000 of them (a count, not a time: the same
# under load).
echo "== G-code interpreter and planner: 100 000 lines of arc-heavy CAM output (cam/fusion360-linuxcnc.ngc)"
if "$build/tests/gcode_bench" tests/gcode/cam/fusion360-linuxcnc.ngc 100000 "$tmp/arcs"; then
	/usr/bin/time -f '%e s %U %M' "$build/tools/x4ctl/x4ctl" gcode --machine "$tmp/arcs.ini" --check "$tmp/arcs.ngc" \
		>"$tmp/check.out" 2>"$tmp/check.time" || cat "$tmp/check.time"
	# The last line is /usr/bin/time's, after the program's warnings.
	tail -n 1 "$tmp/check.time" >"$tmp/check.last"
	read -r secs _ user kb <"$tmp/check.last" || true
	echo "x4ctl gcode --check: ${secs:-?} s, ${user:-?} s of CPU (goal < 1 s), peak memory ${kb:-?} kB: $(head -n1 "$tmp/check.out")"
	"$build/tests/gcode_bench" tests/gcode/cam/fusion360-linuxcnc.ngc 10000 "$tmp/arcs10k" >/dev/null
	valgrind --tool=callgrind --callgrind-out-file="$tmp/arcs.cg" "$build/tools/x4ctl/x4ctl" gcode \
		--machine "$tmp/arcs10k.ini" --check "$tmp/arcs10k.ngc" >/dev/null 2>&1
	total=$(sed -n 's/^totals: *//p' "$tmp/arcs.cg")
	echo "x4ctl gcode --check: $((total / 10000)) instructions per line, 10 000 lines (callgrind; 601 000 before the soft-limit fix)"
else
	echo "(the arc-heavy G-code bench failed)"
fi
echo

# The simulated port (issue 19): virtual-time speed and the VCD's cost.
echo "== simulated port: a 4-axis 20 kHz move of 10 s in virtual time, without and with a VCD (tests/bench/sim_bench.cpp)"
"$build/tests/sim_bench" || failed=1
echo

# The host tests against one-line mutations of the engine: every one must
# fail a test (tests/mutation/run.sh, about a minute on 2 cores).
echo
echo "== engine: mutation run (tests/mutation/mutations.txt against the host tests)"
BUILD=$build tests/mutation/run.sh >"$tmp/mutation.log" 2>&1 || true
grep -E '^(baseline|SURVIVED|INVALID)' "$tmp/mutation.log" || true
tail -n 1 "$tmp/mutation.log"

# The module's timer in QEMU under -icount (reproducible guest time), next
# to a bare hrtimer in the same boot: tests/qemu/timing/timing_bench.cpp.
echo
echo "== module: step timer lateness vs a bare hrtimer, 20 kHz 4-axis move (QEMU -icount, Debian 6.1)"
qout=${X4_QEMU_BUILD:-$(cd "$build" && pwd)/qemu-bench}
X4_QEMU_BUILD=$qout tests/qemu/run-suite.sh -k 6.1.0 -t timing >/dev/null 2>&1 || echo "(the timing run failed: see $qout)"
cat "$qout"/6.1.*/timing/console.log | tr -d '\r' | grep -E 'timer:|hrtimer:|ratio|kHz|example:|step timing|event cost|budget'

# The speed ceiling (issue 18): one axis' goto and a one-segment path with
# 10^6 steps/s^2 ramps at each rate up to X4STEP_VEL_MAX, in QEMU -icount:
# edges, lateness against a bare hrtimer at the same rate, the timer's CPU.
echo
echo "== module: speed ceiling, one axis, goto and path (QEMU -icount, Debian 6.1; tests/qemu/speed/speed_bench.cpp)"
X4_QEMU_BUILD=$qout tests/qemu/run-suite.sh -k 6.1.0 -t speed >/dev/null 2>&1 || echo "(the speed run failed: see $qout)"
cat "$qout"/6.1.*/speed/console.log | tr -d '\r' | grep -E '^ceiling' |
	sed -E 's/^ceiling //; s/ \(planned ([0-9]+), minimum ([0-9]+)\)/ (min \2)/; s/, [0-9]+ capped, [0-9]+ shifts//'

# The X4Step API's top rate on time (issue 28, item 10): the cruise period
# of 20 kHz with 25 us pulse and space, and the bounded waits that place its
# edges (X4STEP_GET_TIMING spins, spin_ns) with their CPU cost; 19 to 5 kHz
# beside it (tests/qemu/ontime/ontime_test.cpp).
echo
echo "== module: 20 kHz on time, cruise period and the spin's CPU cost (QEMU -icount, Debian 6.1)"
X4_QEMU_BUILD=$qout tests/qemu/run-suite.sh -k 6.1.0 -t ontime >/dev/null 2>&1 || echo "(the ontime run failed: see $qout)"
cat "$qout"/6.1.*/ontime/console.log | tr -d '\r' | grep -E '^ontime [0-9]'

# Paths in the module (issue 18): the rate at which 20-step segments are
# taken from a streaming writer, 5000/s asked for (tests/qemu/path/path_test.cpp).
echo
echo "== module: sustained segment rate of a streamed path (QEMU -icount, Debian 6.1)"
X4_QEMU_BUILD=$qout tests/qemu/run-suite.sh -k 6.1.0 -t path >/dev/null 2>&1 || echo "(the path run failed: see $qout)"
cat "$qout"/6.1.*/path/console.log | tr -d '\r' | grep -E '^sustained:'

# The GRBL bridge (issue 31): a real CAM program streamed with character
# counting on the simulated port: lines/s taken (check mode), '?' round
# trip and CPU while it runs at its feeds, starved refills.
echo
echo "== x4grbl: cam/fusion360-linuxcnc.ngc streamed as a sender does (tests/bench/grbl_bench.py)"
python3 tests/bench/grbl_bench.py "$build/tools/x4grbl/x4grbl" tests/gcode/cam/fusion360-linuxcnc.ngc 30 || failed=1
exit $failed
