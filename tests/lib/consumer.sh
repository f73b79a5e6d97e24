#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# libx4step as a packager installs it and a user finds it: a staged
# install of BUILD, a C-only CMake project linking x4step::x4step and
# x4step::x4step_static, and pkg-config's flags for x4step (C) and
# x4stepcxx (C++). Usage: consumer.sh BUILD
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
printf '#include <x4step.hpp>\n#include <cstdio>\nstatic_assert((x4step::axis::x | x4step::axis::z).mask() == 5, "typed axes in C++17");\nint main() { std::printf("%%s\\n", x4step::make_error_code(x4step::errc::lpt_not_found).message().c_str()); try { x4step::controller c(4); } catch (const x4step::error &e) { return e.code() == x4step::errc::lpt_not_found ? 0 : 1; } return 1; }\n' >"$tmp/use.cpp"
# shellcheck disable=SC2046
g++ -std=c++17 -o "$tmp/pc_cxx" "$tmp/use.cpp" $(pkg-config --cflags --libs x4stepcxx)
LD_LIBRARY_PATH=$libdir "$tmp/pc_cxx"
echo "consumers: CMake (C, shared and static) and pkg-config (C, C++) built and ran"
