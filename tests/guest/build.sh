#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Build the statically linked guest programs into OUTDIR: the module and
# key tests (UAPI only), and the library tests and the manual's examples
# against the *installed* headers and static library (staged install).
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

job $cxx -I"$top/include/uapi" -o "$out/module_test" "$top/tests/guest/module_test.cpp"
job $cxx -I"$top/include/uapi" -o "$out/keys_test" "$top/tests/guest/keys_test.cpp"
job $cxx -I"$top/include/uapi" -o "$out/discipline_test" "$top/tests/guest/discipline_test.cpp"
job $cxx -I"$top/include/uapi" -o "$out/ontime_test" "$top/tests/guest/ontime_test.cpp"
job $cxx -pthread -I"$top/include/uapi" -o "$out/reliability_test" "$top/tests/guest/reliability_test.cpp"
job $cxx -pthread -I"$top/include/uapi" -o "$out/events_test" "$top/tests/guest/events_test.cpp"
job $cxx -I"$top/include/uapi" -o "$out/config_test" "$top/tests/guest/config_test.cpp"
job $cxx -I"$top/include/uapi" -o "$out/path_test" "$top/tests/guest/path_test.cpp"
job $cxx -pthread -I"$top/include/uapi" -o "$out/ioctl_fuzz" "$top/tests/fuzz/ioctl_fuzz.cpp"
engine_objs=
for f in "$top"/kmod/engine/*.c; do
	o=$out/$(basename "$f" .c).o
	job gcc -O2 -Wall -Wextra -Werror '-Dnoinline=__attribute__((noinline))' -I"$top/include/uapi" -c -o "$o" "$f"
	engine_objs="$engine_objs $o"
done
finish # the engine's objects, for timing_bench
# shellcheck disable=SC2086
job $cxx -I"$top/include/uapi" -I"$top/tests/host" -I"$top/kmod/engine" -o "$out/timing_bench" \
	"$top/tests/guest/timing_bench.cpp" "$top/tests/host/engine_ref.cpp" $engine_objs
job $cxx -I"$top/include/uapi" -o "$out/speed_bench" "$top/tests/guest/speed_bench.cpp"
job $cxx -I"$stage/include" -I"$top/include/uapi" -o "$out/cpp_test" "$top/tests/guest/cpp_test.cpp" "$lib"
# x4ctl: the interpreter and the planner are in the tree, not installed; the
# library only through its installed headers, as any program.
job $cxx -I"$stage/include" -I"$top/lib/gcode" -I"$top/lib/machine" -I"$top/tools/x4ctl" \
	-o "$out/x4ctl" "$top"/tools/x4ctl/*.cpp "$top"/tools/x4ctl/commands/*.cpp \
	"$top"/lib/gcode/*.cpp "$top"/lib/machine/*.cpp "$lib"
job $cxx -I"$stage/include" -o "$out/phase_test" "$top/tests/guest/phase_test.cpp" "$lib"
job $cxx -I"$stage/include" -o "$out/positioning_test" "$top/tests/guest/positioning_test.cpp" "$lib"
job $cxx -I"$stage/include" -I"$top/include/uapi" -o "$out/brake_test" "$top/tests/guest/brake_test.cpp" "$lib"
job $cxx -I"$stage/include" -o "$out/faith_moves" "$top/tests/faith/faith_moves.cpp" "$lib"
job gcc -static -O2 -Wall -Wextra -I"$top/include/uapi" -o "$out/x4vctl" "$top/tests/kmod/x4vctl.c"
for f in "$top"/tests/guest/manual/*.c; do
	job gcc -std=c99 -static -O2 -Wall -Wextra -Werror -I"$stage/include" \
		-o "$out/man_$(basename "$f" .c)" "$f" "$lib" -lstdc++ -lm
done
finish
