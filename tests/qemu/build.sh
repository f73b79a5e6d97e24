#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Build the statically linked guest programs of the QEMU tests into OUTDIR,
# against the *installed* headers and static library (staged install): each
# test folder's programs, x4ctl, the fixtures' x4vctl and the manual's
# examples (examples/manual, as man_NAME); x4grbl too.
# The compilers run side by side, one per CPU. With PROGRAM names after
# OUTDIR only those are built (make demo: x4ctl).
#   build.sh OUTDIR [PROGRAM...]
set -eu
top=$(cd "$(dirname "$0")/../.." && pwd)
out=${1:?usage: build.sh OUTDIR [PROGRAM...]}
shift
only=" $* " # the programs to build; "  ": all
build=${BUILD:-$top/build}
mkdir -p "$out"
stage=$out/stage
rm -rf "$stage"
cmake --install "$build" --prefix "$stage" >/dev/null
lib=$(find "$stage" -name libx4step.a) # lib/ or lib/<multiarch>/
cxx="g++ -std=c++17 -O2 -Wall -Wextra -Werror -static"

failed=0
job() { # COMMAND...: in the background, at most one per CPU; skipped if its -o is not asked for
	if [ "$only" != "  " ]; then
		local a prev="" name=""
		for a in "$@"; do
			[ "$prev" = -o ] && name=$(basename "$a")
			prev=$a
		done
		case $only in *" $name "*) ;; *) return 0 ;; esac
	fi
	while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n || failed=1; done
	"$@" &
}
finish() { # wait for every job; fail if one did
	local p
	for p in $(jobs -p); do wait "$p" || failed=1; done
	[ "$failed" = 0 ] || { echo "build.sh: building the guest programs failed" >&2; exit 1; }
}

# Every C++ file of a test's folder (tests/qemu/NAME/*.cpp) is one program,
# named after the file: built against the UAPI header, the shared guest
# headers (tests/qemu/common) and the installed library headers, linked with
# the static library (a program that calls none of it takes nothing from it).
# timing_bench also takes the engine's objects, below.
for f in "$top"/tests/qemu/*/*.cpp; do
	p=$(basename "$f" .cpp)
	[ "$p" = timing_bench ] && continue
	# shellcheck disable=SC2086 # $cxx: the compiler and its options
	job $cxx -pthread -I"$stage/include" -I"$top/include/uapi" -I"$top/tests/qemu/common" \
		-o "$out/$p" "$f" "$lib"
done
engine_objs=
for f in "$top"/kmod/engine/*.c; do
	o=$out/$(basename "$f" .c).o
	job gcc -O2 -Wall -Wextra -Werror '-Dnoinline=__attribute__((noinline))' -I"$top/include/uapi" -c -o "$o" "$f"
	engine_objs="$engine_objs $o"
done
finish # the engine's objects, for timing_bench
# shellcheck disable=SC2086
job $cxx -I"$top/include/uapi" -I"$top/tests/qemu/common" -I"$top/tests/engine" -I"$top/kmod/engine" \
	-o "$out/timing_bench" "$top/tests/qemu/timing/timing_bench.cpp" "$top/tests/engine/engine_ref.cpp" $engine_objs
# x4ctl: the interpreter and the planner are in the tree, not installed; the
# library only through its installed headers, as any program.
# shellcheck disable=SC2086 # $cxx: the compiler and its options
job $cxx -I"$stage/include" -I"$top/lib/gcode" -I"$top/lib/machine" -I"$top/tools/x4ctl" \
	-o "$out/x4ctl" "$top"/tools/x4ctl/*.cpp "$top"/tools/x4ctl/commands/*.cpp \
	"$top"/lib/gcode/*.cpp "$top"/lib/machine/*.cpp "$lib"
# x4grbl (the GRBL bridge): its files on x4ctl's, without x4ctl's main().
x4ctl_lib=$(find "$top/tools/x4ctl" "$top/tools/x4ctl/commands" -maxdepth 1 -name '*.cpp' ! -path '*/x4ctl/main.cpp')
version=$(sed -n 's/^project(x4step VERSION \([0-9.]*\).*/\1/p' "$top/CMakeLists.txt")
# shellcheck disable=SC2086 # $cxx, $x4ctl_lib: words
job $cxx -DX4GRBL_VERSION="\"$version\"" -I"$stage/include" -I"$top/lib/gcode" -I"$top/lib/machine" \
	-I"$top/tools/x4ctl" -I"$top/tools/x4grbl" -o "$out/x4grbl" "$top"/tools/x4grbl/*.cpp $x4ctl_lib \
	"$top"/lib/gcode/*.cpp "$top"/lib/machine/*.cpp "$lib"
job gcc -static -O2 -Wall -Wextra -I"$top/include/uapi" -o "$out/x4vctl" "$top/tests/qemu/fixtures/x4vctl.c"
for f in "$top"/examples/manual/*.c; do
	job gcc -std=c99 -static -O2 -Wall -Wextra -Werror -I"$stage/include" \
		-o "$out/man_$(basename "$f" .c)" "$f" "$lib" -lstdc++ -lm
done
finish
