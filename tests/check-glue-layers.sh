#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# The kernel glue's files call downward only (docs/architecture.md): each
# object of kmod/x4step_*.c may use the x4step_ functions of the files
# listed after it here, never of its own level or above. Reads the objects
# of a module build: tests/check-glue-layers.sh KMOD_DIR (default kmod).
# Prints what breaks the order; exits non-zero if anything does.
set -u
dir=${1:-$(dirname "$0")/../kmod}
# Top to bottom; files on one line are one level and call none of each other.
levels="main
ioctl
move path keys
registry
motion
port
events"
fail=0
echo "$levels" | {
	while read -r level; do
		below=$(echo "$levels" | sed -n "/^$level\$/,\$p" | sed 1d | tr '\n' ' ')
		for f in $level; do
			o=$dir/x4step_$f.o
			if [ ! -f "$o" ]; then
				echo "check-glue-layers: $o missing: build the module first"
				fail=1
				continue
			fi
			for sym in $(nm -u "$o" | awk '$2 ~ /^x4step_/ { print $2 }'); do
				ok=0
				for g in $below; do
					nm --defined-only "$dir/x4step_$g.o" 2>/dev/null |
						awk '$2 ~ /^[TDBR]$/ { print $3 }' | grep -qx "$sym" && ok=1
				done
				if [ $ok -eq 0 ]; then
					echo "x4step_$f.c calls $sym, which is not below it ($below)"
					fail=1
				fi
			done
		done
	done
	# Every glue object is on a level.
	for o in "$dir"/x4step_*.o; do
		[ -e "$o" ] || continue
		case $o in *x4step.o | *x4step.mod.o) continue ;; esac
		f=$(basename "$o" .o)
		f=${f#x4step_}
		echo " $levels " | tr '\n' ' ' | grep -q " $f " || {
			echo "x4step_$f.o is on no level of $0"
			fail=1
		}
	done
	exit $fail
}
