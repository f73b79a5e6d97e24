#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# The engine's levels call only downward: kmod/engine/sources.mk lists its
# files by level (x4_level0 the lowest); a file may call functions of the
# levels below its own, never of its own level's other files or of a level
# above. Each engine file is compiled for the host (the engine is plain C)
# and the functions it calls (nm -u) are looked up among those the engine's
# objects define. Every .c file of kmod/engine must be on the list.
# Prints the offending calls; exits non-zero if there is one.
#
# Usage: tests/check-layers.sh [ENGINE_DIR]   (default kmod/engine)
set -u
top=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-$top/kmod/engine}
CC=${CC:-gcc}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
st=0

# "LEVEL FILE" lines from the x4_levelN := a.c b.c lines.
awk '/^x4_level[0-9]+ *:=/ {
	lvl = $1; sub(/^x4_level/, "", lvl)
	for (i = 3; i <= NF; i++) print lvl, $i
}' "$dir/sources.mk" >"$tmp/levels"
if [ ! -s "$tmp/levels" ]; then
	echo "check-layers: no x4_levelN lines in $dir/sources.mk"
	exit 1
fi
for f in "$dir"/*.c; do
	b=$(basename "$f")
	grep -q " $b\$" "$tmp/levels" && continue
	echo "check-layers: kmod/engine/$b is in no level of kmod/engine/sources.mk"
	st=1
done

# Compile each file; "FUNCTION FILE" for every function the engine defines.
: >"$tmp/defs"
while read -r lvl f; do
	o=$tmp/${f%.c}.o
	if ! $CC -std=c11 -O2 '-Dnoinline=__attribute__((noinline))' \
		-I"$dir" -I"$top/include/uapi" -c "$dir/$f" -o "$o" 2>"$tmp/cc.log"; then
		cat "$tmp/cc.log"
		echo "check-layers: $f does not compile"
		exit 1
	fi
	nm --defined-only -g "$o" | awk -v f="$f" '{ print $3, f }' >>"$tmp/defs"
done <"$tmp/levels"

# "FUNCTION LEVEL FILE" of every function the engine defines.
awk 'NR == FNR { lvl[$2] = $1; next } { print $1, lvl[$2], $2 }' "$tmp/levels" "$tmp/defs" >"$tmp/syms"

# Each object's calls into the engine (not libc's, not the kernel's): to a
# lower level only.
while read -r lvl f; do
	nm -u "$tmp/${f%.c}.o" | awk -v lvl="$lvl" -v f="$f" '
		NR == FNR { L[$1] = $2; F[$1] = $3; next }
		($2 in L) && L[$2] + 0 >= lvl + 0 {
			printf "kmod/engine/%s (level %d) calls %s() of kmod/engine/%s (level %d): a file calls only the levels below its own (kmod/engine/sources.mk)\n", f, lvl, $2, F[$2], L[$2]
			bad = 1
		}
		END { exit bad }' "$tmp/syms" - || st=1
done <"$tmp/levels"
exit $st
