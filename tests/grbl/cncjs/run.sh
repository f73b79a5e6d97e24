#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# A real G-code sender, CNCjs 1.11.5 (scripts/get-cncjs.sh), runs PROGRAM
# on a GRBL bridge's pty, headless: this script starts the bridge command
# given after --, writes a .cncrc whose "ports" list holds the pty, starts
# CNCjs on a free loopback port and client.js, which opens the pty as a Grbl
# controller through CNCjs's socket.io API, loads and starts PROGRAM, and
# follows CNCjs's own state until the run has ended. Passes when CNCjs saw
# every line acknowledged, its workflow ended, its last state was Idle and
# its machine position is EXPECTED. Every process it started is ended.
#
# Usage: tests/grbl/cncjs/run.sh [-t TIMEOUT_S] [-e TOLERANCE] PROGRAM X,Y,Z[,A] -- BRIDGE [ARGS...]
#   @PTY@ in BRIDGE's arguments is replaced by the pty path CNCjs opens
#   (in this script's temporary folder), e.g.
#   run.sh prog.ngc 10,0,0 -- build/x4grbl --sim --link @PTY@ machines/sim.ini
# TIMEOUT_S (default 300) bounds the whole run; TOLERANCE (default 0.001 mm)
# each axis. X4_CNCJS_CACHE: where CNCjs is installed; X4_CNCJS_KEEP=1
# keeps the temporary folder (logs: bridge.log, cncjs.log, client.log).
set -u
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../../.." && pwd)
timeout=300
tolerance=0.001
while getopts t:e: o; do
	case $o in
	t) timeout=$OPTARG ;;
	e) tolerance=$OPTARG ;;
	*) exit 2 ;;
	esac
done
shift $((OPTIND - 1))
if [ $# -lt 4 ] || [ "$3" != -- ]; then
	sed -n 's/^# Usage: //p' "$0" >&2
	exit 2
fi
program=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
expected=$2
shift 3

cache=${X4_CNCJS_CACHE:-/var/cache/x4step/cncjs}
"$top/scripts/get-cncjs.sh" "$cache" || exit 1

tmp=$(mktemp -d "${TMPDIR:-/tmp}/x4-cncjs.XXXXXX")
pty=$tmp/ttyGRBL0
bridge_pid=
cncjs_pid=
client_pid=
# shellcheck disable=SC2317 # called by cleanup, from the trap
stop() { # PID: TERM, then KILL after 5 s
	[ -n "$1" ] && kill -0 "$1" 2>/dev/null || return 0
	kill -TERM "$1" 2>/dev/null
	for _ in $(seq 50); do
		kill -0 "$1" 2>/dev/null || break
		sleep 0.1
	done
	kill -KILL "$1" 2>/dev/null
	wait "$1" 2>/dev/null
}
# shellcheck disable=SC2317 # called by trap
cleanup() {
	stop "$client_pid"
	stop "$cncjs_pid"
	stop "$bridge_pid"
	if [ "${X4_CNCJS_KEEP:-0}" = 1 ]; then
		echo "cncjs: logs kept in $tmp"
	else
		rm -rf "$tmp"
	fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM
fail() {
	echo "cncjs: $*"
	for f in bridge.log cncjs.log; do
		[ -s "$tmp/$f" ] && { echo "--- last lines of $f"; tail -n 30 "$tmp/$f"; }
	done
	echo "FAIL"
	exit 1
}

# The bridge, on a pty at $pty.
args=()
for a in "$@"; do args+=("${a//@PTY@/$pty}"); done
echo "cncjs: bridge: ${args[*]}"
"${args[@]}" >"$tmp/bridge.log" 2>&1 &
bridge_pid=$!
for _ in $(seq 300); do
	[ -e "$pty" ] && break
	kill -0 "$bridge_pid" 2>/dev/null || fail "the bridge ended before its pty appeared"
	sleep 0.1
done
[ -e "$pty" ] || fail "no pty at $pty after 30 s"

# CNCjs's config: the pty as a configured port, a secret to sign the
# client's token with. HOME is the temporary folder (sessions go there).
secret=$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')
PTY=$pty SECRET=$secret node -e '
	require("fs").writeFileSync(process.argv[1], JSON.stringify({
		secret: process.env.SECRET,
		ports: [{ path: process.env.PTY, manufacturer: "x4step GRBL bridge" }],
	}, null, 2));' "$tmp/.cncrc"
HOME=$tmp FORCE_COLOR=0 node "$cache/node_modules/cncjs/bin/cncjs" -H 127.0.0.1 -p 0 -c "$tmp/.cncrc" \
	--controller Grbl -vvv >"$tmp/cncjs.log" 2>&1 &
cncjs_pid=$!
url=
for _ in $(seq 600); do
	url=$(sed -n 's/.*Starting the server at \(http:\/\/127\.0\.0\.1:[0-9]*\).*/\1/p' "$tmp/cncjs.log")
	[ -n "$url" ] && break
	kill -0 "$cncjs_pid" 2>/dev/null || fail "CNCjs ended before it listened"
	sleep 0.1
done
[ -n "$url" ] || fail "CNCjs did not listen within 60 s"
echo "cncjs: CNCjs $(node -p "require('$cache/node_modules/cncjs/package.json').version") on Node.js $(node --version) at $url, port $pty"

NODE_PATH=$cache/node_modules node "$here/client.js" "$url" "$secret" "$pty" "$program" \
	"$expected" "$timeout" "$tolerance" >"$tmp/client.log" 2>&1 &
client_pid=$!
wait "$client_pid"
st=$?
client_pid=
cat "$tmp/client.log"
[ $st -eq 0 ] || fail "CNCjs did not end the program Idle at $expected"
exit 0
