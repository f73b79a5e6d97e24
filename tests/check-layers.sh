#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Layers call only downward (docs/architecture.md): a file may call the
# functions of the levels below its own, never of its own level's other
# files or of a level above (nm -u of its object against what the other
# objects of the set define). Every file of the set must be on a level.
#
#   tests/check-layers.sh [engine [ENGINE_DIR]]   the engine (default):
#       kmod/engine/sources.mk lists its files by level (x4_level0 the
#       lowest); each file is compiled for the host (the engine is plain C)
#   tests/check-layers.sh glue KMOD_DIR   the kernel glue: the objects of
#       a module build (kmod/x4step_*.o), on the levels below
#
# Prints the offending calls; exits non-zero if there is one.
set -u
top=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/o"
st=0

# The glue's files, top to bottom; files on one line are one level.
glue_levels="x4step_main
x4step_ioctl
x4step_move x4step_path x4step_keys
x4step_registry
x4step_motion
x4step_port
x4step_events"

# $tmp/levels: "LEVEL FILE" lines (FILE without .c, the lowest level 0), and
# $tmp/o/FILE.o for each.
case ${1:-engine} in
engine)
	dir=${2:-$top/kmod/engine}
	where=kmod/engine
	awk '/^x4_level[0-9]+ *:=/ {
		lvl = $1; sub(/^x4_level/, "", lvl)
		for (i = 3; i <= NF; i++) { f = $i; sub(/\.c$/, "", f); print lvl, f }
	}' "$dir/sources.mk" >"$tmp/levels"
	order="kmod/engine/sources.mk"
	for f in "$dir"/*.c; do
		b=$(basename "$f" .c)
		grep -q " $b\$" "$tmp/levels" && continue
		echo "check-layers: $where/$b.c is in no level of $order"
		st=1
	done
	while read -r lvl f; do
		if ! ${CC:-gcc} -std=c11 -O2 '-Dnoinline=__attribute__((noinline))' \
			-I"$dir" -I"$top/include/uapi" -c "$dir/$f.c" -o "$tmp/o/$f.o" 2>"$tmp/cc.log"; then
			cat "$tmp/cc.log"
			echo "check-layers: $f.c does not compile"
			exit 1
		fi
	done <"$tmp/levels"
	;;
glue)
	dir=${2:?usage: $0 glue KMOD_DIR}
	where=kmod
	order="the glue's levels in tests/check-layers.sh"
	n=$(echo "$glue_levels" | wc -l)
	echo "$glue_levels" | awk -v n="$n" '{ for (i = 1; i <= NF; i++) print n - NR, $i }' >"$tmp/levels"
	for o in "$dir"/x4step_*.o; do
		[ -e "$o" ] || continue
		b=$(basename "$o" .o)
		grep -q " $b\$" "$tmp/levels" && continue
		echo "check-layers: $where/$b.c is in no level of $order"
		st=1
	done
	while read -r lvl f; do
		if [ ! -f "$dir/$f.o" ]; then
			echo "check-layers: $dir/$f.o is missing: build the module first"
			exit 1
		fi
		cp "$dir/$f.o" "$tmp/o/$f.o"
	done <"$tmp/levels"
	;;
*)
	echo "usage: $0 [engine [ENGINE_DIR] | glue KMOD_DIR]" >&2
	exit 2
	;;
esac
if [ ! -s "$tmp/levels" ]; then
	echo "check-layers: no levels for $where"
	exit 1
fi

# "FUNCTION LEVEL FILE" of every function the set defines.
while read -r lvl f; do
	nm --defined-only -g "$tmp/o/$f.o" | awk -v f="$f" -v lvl="$lvl" '$2 ~ /^[TDBR]$/ { print $3, lvl, f }'
done <"$tmp/levels" >"$tmp/syms"

# Each object's calls into the set (not libc's, not the kernel's, not a
# lower set's): to a lower level only.
while read -r lvl f; do
	nm -u "$tmp/o/$f.o" | awk -v lvl="$lvl" -v f="$f" -v where="$where" -v order="$order" '
		NR == FNR { L[$1] = $2; F[$1] = $3; next }
		($2 in L) && L[$2] + 0 >= lvl + 0 {
			printf "%s/%s.c (level %d) calls %s() of %s/%s.c (level %d): a file calls only the levels below its own (%s)\n", where, f, lvl, $2, where, F[$2], L[$2], order
			bad = 1
		}
		END { exit bad }' "$tmp/syms" - || st=1
done <"$tmp/levels"
exit $st
