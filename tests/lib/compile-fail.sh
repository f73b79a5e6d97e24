#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Compile-fail checks of the C++ API: FILE must compile as C++17 against
# the headers in INCLUDE; then, for each line with a "// bad: CODE" mark,
# FILE with that line replaced by CODE must not, and for a type error, not
# for a typo in CODE. Usage: compile-fail.sh CXX INCLUDE FILE
set -u
cxx=${1:?usage: compile-fail.sh CXX INCLUDE FILE}
inc=${2:?usage: compile-fail.sh CXX INCLUDE FILE}
file=${3:?usage: compile-fail.sh CXX INCLUDE FILE}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
compile() { "$cxx" -std=c++17 -Wall -Wextra -Werror -fsyntax-only -I"$inc" -x c++ "$1" >"$tmp/log" 2>&1; }
compile "$file" || { echo "$file does not compile as it is:" && cat "$tmp/log" && exit 1; }
fail=0
n=0
# shellcheck disable=SC2013 # line numbers, one word each
for line in $(grep -n '// bad: ' "$file" | cut -d: -f1); do
	n=$((n + 1))
	bad=$(sed -n "${line}s|.*// bad: ||p" "$file")
	awk -v n="$line" -v code="$bad" 'NR == n { print code; next } { print }' "$file" >"$tmp/bad.cpp"
	if compile "$tmp/bad.cpp"; then
		echo "line $line compiles, but must not: $bad" && fail=1
	elif grep -Eq "was not declared|expected .* before|has no member named|does not name a type" "$tmp/log"; then
		echo "line $line fails for another reason than its types: $bad" && grep error "$tmp/log" | head -3 && fail=1
	fi
done
[ $fail = 0 ] && echo "$n wrong spellings refused, the right ones compile"
exit $fail
