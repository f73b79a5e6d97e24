#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# CNCjs 1.11.5, the G-code sender that tests the GRBL bridge
# (tests/grbl/cncjs/), installed from the npm registry into a cache with
# `npm ci` from the lockfile beside the harness (every package at the
# version and hash it names). Nothing is built: serialport's native binding
# ships prebuilt for linux-x64 and linux-arm64 (N-API, any Node.js >= 18),
# and no install script is run. The cache is reused while the lockfile is
# the one it was installed from. Needs node and npm (scripts/deps.sh test).
# Usage: scripts/get-cncjs.sh [CACHE]   (default /var/cache/x4step/cncjs)
# Prints nothing when the cache is complete.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)
cache=${1:-${X4_CNCJS_CACHE:-/var/cache/x4step/cncjs}}
lock=$top/tests/grbl/cncjs/package-lock.json
sum=$(sha256sum "$lock" "$top/tests/grbl/cncjs/package.json" | sha256sum | cut -d' ' -f1)
[ "$(cat "$cache/complete" 2>/dev/null)" = "$sum" ] && exit 0

for c in node npm; do
	command -v $c >/dev/null || {
		echo "x4step: $c is missing: run scripts/deps.sh test as root (Debian's nodejs and npm)" >&2
		exit 1
	}
done
if ! mkdir -p "$cache" 2>/dev/null || [ ! -w "$cache" ]; then
	echo "x4step: cannot write $cache: run scripts/deps.sh test as root, or set X4_CNCJS_CACHE" >&2
	exit 1
fi
rm -f "$cache/complete"
cp "$top/tests/grbl/cncjs/package.json" "$lock" "$cache/"
log=$cache/install.log
if ! (cd "$cache" && npm ci --ignore-scripts --no-audit --no-fund) >"$log" 2>&1; then
	cat "$log" >&2
	echo "x4step: npm ci of CNCjs failed in $cache (network? the npm registry?)" >&2
	exit 1
fi
# The native serial-port binding CNCjs opens the pty with, and the version.
bindings=$cache/node_modules/@serialport/bindings-cpp
if ! (cd "$cache" && node -e "require('node-gyp-build')('$bindings')") >>"$log" 2>&1; then
	cat "$log" >&2
	echo "x4step: serialport's binding has no prebuilt module for $(uname -m) here" >&2
	exit 1
fi
v=$(cd "$cache" && node -p "require('cncjs/package.json').version")
[ "$v" = 1.11.5 ] || {
	echo "x4step: $cache holds CNCjs $v, not 1.11.5" >&2
	exit 1
}
echo "$sum" >"$cache/complete"
echo "x4step: CNCjs $v in $cache"
