#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# LinuxCNC's standalone G-code interpreter, rs274, the oracle of the G-code
# tests (tests/gcode/oracle.py): Debian's linuxcnc-uspace package and the
# libraries rs274 needs that a test machine lacks, downloaded with
# apt-get download and unpacked with dpkg -x into a cache; nothing is
# installed into the system. rs274 prints coordinates with 4 decimals
# (printf "%.4f"); rs274-9 is a copy whose format strings say "%.9f"
# (same length, nothing else changed), so that 1e-6 can be checked.
# Usage: scripts/get-rs274.sh [CACHE]   (default /var/cache/x4step/linuxcnc)
set -eu
cache=${1:-${X4_LINUXCNC_CACHE:-/var/cache/x4step/linuxcnc}}
pkgs="linuxcnc-uspace libboost-python1.74.0 libpython3.11"
[ -f "$cache/complete" ] && exit 0

if ! mkdir -p "$cache" 2>/dev/null || [ ! -w "$cache" ]; then
	echo "x4step: cannot write $cache: run scripts/deps.sh test as root to fetch LinuxCNC's rs274" >&2
	exit 1
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# shellcheck disable=SC2086 # the package names are words
(cd "$tmp" && apt-get download $pkgs) >"$tmp/log" 2>&1 || {
	cat "$tmp/log" >&2
	echo "x4step: apt-get download $pkgs failed (network? apt-get update?)" >&2
	exit 1
}
rm -rf "$cache/root"
for deb in "$tmp"/*.deb; do dpkg -x "$deb" "$cache/root"; done
libs=$cache/root/usr/lib:$cache/root/usr/lib/x86_64-linux-gnu
missing=$(LD_LIBRARY_PATH=$libs ldd "$cache/root/usr/bin/rs274" | sed -n 's/^\s*\(\S*\) => not found/\1/p' | sort -u)
if [ -n "$missing" ]; then
	echo "x4step: rs274 still lacks: $missing" >&2
	exit 1
fi
perl -0777 -pe 's/%\.4f/%.9f/g' "$cache/root/usr/bin/rs274" >"$cache/rs274-9"
chmod +x "$cache/rs274-9"
# A tool table (rs274 reads its values as inches) and an empty .var file.
printf 'T%d P%d Z0.%d D0.125 ;\n' 1 1 1 2 2 2 3 3 3 4 4 4 5 5 5 6 6 6 7 7 7 8 8 8 9 9 9 >"$cache/tool.tbl"
: >"$cache/empty.var"
printf 'G21\nG1 X1 F10\nG2 X2 I0.5\nM2\n' >"$tmp/t.ngc"
if ! LD_LIBRARY_PATH=$libs "$cache/rs274-9" -t "$cache/tool.tbl" -v "$cache/empty.var" -g "$tmp/t.ngc" </dev/null |
	grep -q 'ARC_FEED(2.000000000, 0.000000000, 1.500000000'; then
	echo "x4step: the patched rs274 does not run or print 9 decimals" >&2
	exit 1
fi
touch "$cache/complete"
echo "x4step: LinuxCNC's rs274 in $cache"
