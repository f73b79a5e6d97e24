#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# libx4step as a packager installs it and a user finds it: a staged
# install of BUILD, a C-only CMake project linking x4step::x4step and
# x4step::x4step_static, pkg-config's flags for x4step (C) and x4stepcxx
# (C++), and the manual's first example built as its README says.
# Usage: consumer.sh BUILD
set -eu
build=${1:?usage: consumer.sh BUILD}
here=$(cd "$(dirname "$0")" && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# As a package is staged: DESTDIR under the configured prefix.
DESTDIR=$tmp/root cmake --install "$build" >/dev/null
libdir=$(dirname "$(find "$tmp/root" -name libx4step.so)")
prefix=${libdir%/lib*}
[ -z "$(find "$tmp/root" -path '*/include/linux*')" ] ||
	{ echo "installs into include/linux, the kernel headers' place"; exit 1; }
cmake -S "$here/consumer" -B "$tmp/c" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$tmp/c" >"$tmp/c.log" 2>&1 || { cat "$tmp/c.log"; exit 1; }
LD_LIBRARY_PATH=$libdir "$tmp/c/use_shared"
"$tmp/c/use_static"
export PKG_CONFIG_PATH="$libdir/pkgconfig" PKG_CONFIG_SYSROOT_DIR="$tmp/root"
grep -q "^libdir=/" "$libdir/pkgconfig/x4step.pc" || { echo "x4step.pc: libdir not absolute"; exit 1; }
# shellcheck disable=SC2046
gcc -o "$tmp/pc_c" "$here/consumer/use.c" $(pkg-config --cflags --libs x4step)
LD_LIBRARY_PATH=$libdir "$tmp/pc_c"
# The manual's first example (examples/first.c) with the build lines its
# README gives: shared, and static (pkg-config --static: Libs.private brings
# -lstdc++ -lm); both run the example on the simulated port.
ex=$here/../../examples/first.c
# shellcheck disable=SC2046
cc -Wall -Wextra -Werror -o "$tmp/first" "$ex" $(pkg-config --cflags --libs x4step)
# shellcheck disable=SC2046
cc -Wall -Wextra -Werror -static -o "$tmp/first_static" "$ex" $(pkg-config --static --cflags --libs x4step)
for first in "$tmp/first" "$tmp/first_static"; do
	got=$(LD_LIBRARY_PATH=$libdir X4STEP_SIM=1 X4STEP_SIM_TIME=virtual "$first")
	[ "$got" = "done: -1000 -800 -600 -400" ] || { echo "$(basename "$first"): '$got'"; exit 1; }
done
# Without a port it says why (and fails).
if LD_LIBRARY_PATH=$libdir X4STEP_SIM='' "$tmp/first" 2>"$tmp/first.err" >/dev/null; then
	echo "first: ran without /dev/x4step0 and without the simulator"
	exit 1
fi
grep -q 'X4STEP_SIM=1' "$tmp/first.err" || { cat "$tmp/first.err"; exit 1; }
printf '#include <x4step.hpp>\n#include <cstdio>\nstatic_assert((x4step::axis::x | x4step::axis::z).mask() == 5, "typed axes in C++17");\nint main() { std::printf("%%s\\n", x4step::make_error_code(x4step::errc::lpt_not_found).message().c_str()); try { x4step::controller c(4); } catch (const x4step::error &e) { return e.code() == x4step::errc::lpt_not_found ? 0 : 1; } return 1; }\n' >"$tmp/use.cpp"
# shellcheck disable=SC2046
g++ -std=c++17 -o "$tmp/pc_cxx" "$tmp/use.cpp" $(pkg-config --cflags --libs x4stepcxx)
LD_LIBRARY_PATH=$libdir "$tmp/pc_cxx"
echo "consumers: CMake (C, shared and static), pkg-config (C, C++) and examples/first.c (shared, static) built and ran"
