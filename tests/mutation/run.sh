#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Mutation run of the engine core (issue 16): apply each one-line mutation
# of tests/mutation/mutations.txt, one at a time, to a copy of the engine's
# sources, build the engine's host tests (tests/engine: req_test,
# track_test, lateness_test, probe_test, path_test, positioning_test,
# engine_test)
# against it and run them. Every mutation must make at least
# one test fail (KILLED); one that all tests pass is SURVIVED, and one that
# cannot be applied (its text is not on exactly one line) or does not build
# is INVALID. Prints one line per mutation and a score line; exits non-zero
# if any mutation survived or was invalid. The mutations are tried side by
# side, one worker per CPU (X4_MUTATION_JOBS).
#
# The working tree is never touched: the engine's files are copied to
# $BUILD/mutation (default build/mutation), kept there between runs, and
# only the mutated file is compiled again (-O1) for each mutation. Tests
# that fail on the unmutated engine are reported and left out of the runs.
#
# mutations.txt: one mutation a line, "original<TAB>replacement<TAB>what",
# '#' lines and empty lines ignored. The original text is found among
# kmod/engine/*.c and *.h (kmod/x4_engine.c before the engine was split);
# it must be on exactly one line, once. A mutated header is seen by the
# engine only: the tests, the oracle, keep the original.
#
# Usage: tests/mutation/run.sh [mutations.txt]
# shellcheck disable=SC2086 # the lists ($files, $tests, $pids) and the compiler flags are words
set -u
top=$(cd "$(dirname "$0")/../.." && pwd)
list=${1:-$top/tests/mutation/mutations.txt}
build=${BUILD:-$top/build}
case $build in /*) ;; *) build=$top/$build ;; esac
work=$build/mutation
tests="req_access_test req_test track_test lateness_test probe_test path_test positioning_test engine_test" # fastest first
start=$(date +%s)

if [ -d "$top/kmod/engine" ]; then
	engdir=$top/kmod/engine
	files=$(cd "$engdir" && echo *.c *.h)
else # before the split
	engdir=$top/kmod
	files="x4_engine.c x4_engine.h"
fi
csrcs=$(printf '%s\n' $files | grep '\.c$')
search=$(printf "$engdir/%s\n" $files)
[ -d "$top/kmod/engine" ] || search=$engdir/x4_engine.c

CC=${CC:-gcc}
CXX=${CXX:-g++}
cflags="-std=c11 -O1 -Dnoinline=__attribute__((noinline)) -I$top/include/uapi"
cxxflags="-std=c++17 -O1 -I$top/include/uapi $(pkg-config --cflags gtest_main 2>/dev/null)"
ldlibs=$(pkg-config --libs gtest_main gtest 2>/dev/null || echo "-lgtest_main -lgtest -pthread")

# The baseline's directories; each mutation worker has its own $mut (the
# mutated sources), $omut (their objects), $bin (tests) and $wlog (logs).
mut=$work/mut omut=$work/obj/mut bin=$work/bin wlog=$work/log
mkdir -p "$work/src" "$work/obj/engine" "$work/obj/tests" "$bin" "$wlog"

# Copy a file only if its content changed, so that objects stay valid.
sync() { # SRC DST
	cmp -s "$1" "$2" || cp "$1" "$2"
}

# The pristine copy of the engine's files and of the tests; nothing else.
keep="$files $(for t in $tests; do printf "%s.cpp " "$t"; done)engine_ref.cpp engine_ref.h"
for f in "$work/src"/*; do
	case " $keep " in *" $(basename "$f") "*) ;; *) rm -f "$f" ;; esac
done
for f in $files; do sync "$engdir/$f" "$work/src/$f"; done
for f in $(for t in $tests; do printf "%s.cpp " "$t"; done) engine_ref.cpp engine_ref.h; do
	sync "$top/tests/engine/$f" "$work/src/$f"
done

# Compile SRC to OBJ if OBJ is missing or older than SRC or a header.
need() { # OBJ SRC
	[ -e "$1" ] || return 0
	[ "$2" -nt "$1" ] && return 0
	for h in "$work/src"/*.h; do [ "$h" -nt "$1" ] && return 0; done
	return 1
}

fail_build() {
	echo "mutation run: the unmutated engine or the tests do not build, see $1" >&2
	exit 2
}

# The tests' objects and the pristine engine objects, two at a time.
pids=""
for t in $tests engine_ref; do
	o=$work/obj/tests/$t.o
	if need "$o" "$work/src/$t.cpp"; then
		$CXX $cxxflags -I"$work/src" -c "$work/src/$t.cpp" -o "$o" >"$work/log/$t.build" 2>&1 &
		pids="$pids $!"
	fi
	if [ "$(echo $pids | wc -w)" -ge 2 ]; then
		for p in $pids; do wait "$p" || fail_build "$work/log/"; done
		pids=""
	fi
done
for c in $csrcs; do
	o=$work/obj/engine/${c%.c}.o
	if need "$o" "$work/src/$c"; then
		$CC $cflags -I"$work/src" -c "$work/src/$c" -o "$o" >"$work/log/${c%.c}.build" 2>&1 || fail_build "$work/log/${c%.c}.build"
	fi
done
for p in $pids; do wait "$p" || fail_build "$work/log/"; done

# Link the tests against the engine objects given.
link() { # ENGINE_OBJS...
	for t in $tests; do
		$CXX -o "$bin/$t" "$work/obj/tests/$t.o" "$work/obj/tests/engine_ref.o" "$@" $ldlibs || return 1
	done
}

# The names of failed tests in gtest's output (not its "N tests" lines).
failed_re='s/^\[  FAILED  \] \([A-Za-z0-9_/]*\.[A-Za-z0-9_./]*\) .*/\1/p'

# Run the tests, fastest first, until one fails: returns 0 if one did and
# sets $failed to the first failed test. Each test program gets 120 s and
# 4 GB: a hang or a runaway is a failure, as it would be under ctest. (The
# subshell's stderr: the shell's report of a test killed by a signal.)
run_tests() { # FILTER
	local t rc
	for t in $tests; do
		(ulimit -v 4000000; timeout 120 "$bin/$t" --gtest_brief=1 ${1:+"--gtest_filter=$1"} \
			>"$wlog/$t.out" 2>&1) 2>/dev/null
		rc=$?
		if [ $rc -ne 0 ]; then
			failed=$(sed -n "$failed_re" "$wlog/$t.out" | head -n 1)
			case $rc in
			124) failed="$t: timeout" ;;
			0 | 1) failed="$t: ${failed:-exit $rc}" ;;
			*) failed="$t: ${failed:-exit $rc (crash)}" ;;
			esac
			return 0
		fi
	done
	failed=""
	return 1
}

# Baseline: what fails without a mutation is left out of the runs.
engine_objs=""
for c in $csrcs; do engine_objs="$engine_objs $work/obj/engine/${c%.c}.o"; done
# shellcheck disable=SC2086
link $engine_objs >"$work/log/link.build" 2>&1 || fail_build "$work/log/link.build"
exclude=""
for t in $tests; do
	(ulimit -v 4000000; timeout 300 "$bin/$t" --gtest_brief=1 >"$work/log/$t.baseline" 2>&1) 2>/dev/null
	rc=$?
	names=$(sed -n "$failed_re" "$work/log/$t.baseline" | sort -u)
	if [ $rc -gt 1 ] || { [ $rc -eq 1 ] && [ -z "$names" ]; }; then
		echo "mutation run: $t ends with status $rc on the unmutated engine, see $work/log/$t.baseline" >&2
		exit 2
	fi
	for name in $names; do exclude="$exclude${exclude:+:}$name"; done
done
filter=${exclude:+-$exclude}
[ -n "$exclude" ] && echo "baseline: left out, failing without a mutation: $(echo "$exclude" | tr ':' ' ')"

# The unique line of the engine that holds TEXT, as FILE:LINE.
locate() { # TEXT
	local hits n
	# shellcheck disable=SC2086
	hits=$(grep -n -H -F -- "$1" $search)
	[ -n "$hits" ] || { echo "not found"; return 1; }
	n=$(printf '%s\n' "$hits" | wc -l)
	[ "$n" -eq 1 ] || { echo "on $n lines"; return 1; }
	printf '%s\n' "$hits" | cut -d: -f1,2
}

# Try one mutation; print its one result line.
mutate() { # ENTRY
	local entry=$1 orig repl what where file line name objs built c f
	orig=$(printf '%s' "$entry" | cut -f1)
	repl=$(printf '%s' "$entry" | cut -f2)
	what=$(printf '%s' "$entry" | cut -f3)
	if [ "$(printf '%s' "$entry" | awk -F'\t' '{print NF}')" -ne 3 ]; then
		echo "INVALID  $entry: not original<TAB>replacement<TAB>description"
		return
	fi
	if ! where=$(locate "$orig"); then
		echo "INVALID  $what: \"$orig\" $where"
		return
	fi
	file=${where%:*}
	line=${where##*:}
	name=$(basename "$file")
	# Apply it to a copy: the line must hold the text once.
	if ! ORIG=$orig REPL=$repl awk -v ln="$line" '
		NR == ln {
			o = ENVIRON["ORIG"]; i = index($0, o)
			if (index(substr($0, i + length(o)), o)) bad = 1
			$0 = substr($0, 1, i - 1) ENVIRON["REPL"] substr($0, i + length(o))
		}
		{ print }
		END { exit bad }' "$work/src/$name" >"$mut/$name"; then
		echo "INVALID  $what: \"$orig\" is on $name:$line more than once"
		return
	fi
	objs=""
	built=true
	: >"$wlog/mutant.build"
	case $name in
	*.c)
		for c in $csrcs; do
			if [ "$c" = "$name" ]; then
				cp "$work/src"/*.h "$mut/" 2>/dev/null
				$CC $cflags -I"$mut" -c "$mut/$c" -o "$omut/${c%.c}.o" \
					>>"$wlog/mutant.build" 2>&1 || built=false
				objs="$objs $omut/${c%.c}.o"
			else
				objs="$objs $work/obj/engine/${c%.c}.o"
			fi
		done
		;;
	*.h) # every engine file sees the mutated header
		for f in "$work/src"/*; do [ -e "$mut/$(basename "$f")" ] || cp "$f" "$mut/"; done
		for c in $csrcs; do
			$CC $cflags -I"$mut" -c "$mut/$c" -o "$omut/${c%.c}.o" \
				>>"$wlog/mutant.build" 2>&1 || built=false
			objs="$objs $omut/${c%.c}.o"
		done
		;;
	esac
	# shellcheck disable=SC2086
	$built && link $objs >>"$wlog/mutant.build" 2>&1 || built=false
	rm -f "$mut"/*
	if ! $built; then
		echo "INVALID  $what ($name:$line): does not build: $(grep -m 1 'error' "$wlog/mutant.build")"
		return
	fi
	if run_tests "$filter"; then
		echo "KILLED   $what ($name:$line) by $failed"
	else
		echo "SURVIVED $what ($name:$line)"
	fi
}

# The mutations, one worker per CPU (X4_MUTATION_JOBS), each with its own
# directories; the results in the order of the list.
entries=()
while IFS= read -r entry || [ -n "$entry" ]; do
	case $entry in '' | '#'*) continue ;; esac
	entries+=("$entry")
done <"$list"
workers=${X4_MUTATION_JOBS:-$(nproc)}
case $workers in '' | 0* | *[!0-9]*)
	echo "mutation run: X4_MUTATION_JOBS wants a positive number, not '$workers'" >&2
	exit 2 ;;
esac
rm -rf "$work/res"
mkdir -p "$work/res"
for w in $(seq "$workers"); do
	(
		mut=$work/mut$w omut=$work/obj/mut$w bin=$work/bin$w wlog=$work/log/w$w
		mkdir -p "$mut" "$omut" "$bin" "$wlog"
		rm -f "$mut"/*
		for i in "${!entries[@]}"; do
			[ $((i % workers + 1)) = "$w" ] && mutate "${entries[i]}" >"$work/res/$i"
		done
	) &
done
wait
total=${#entries[@]} killed=0 survived=0 invalid=0
for i in "${!entries[@]}"; do
	cat "$work/res/$i"
	case $(cat "$work/res/$i") in
	KILLED*) killed=$((killed + 1)) ;;
	SURVIVED*) survived=$((survived + 1)) ;;
	*) invalid=$((invalid + 1)) ;;
	esac
done

echo "mutation score: $killed of $total killed, $survived survived, $invalid invalid ($(($(date +%s) - start)) s)"
[ "$total" -gt 0 ] && [ "$survived" -eq 0 ] && [ "$invalid" -eq 0 ]
