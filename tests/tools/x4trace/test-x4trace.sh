#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# Self-test of x4trace on a hand-made trace whose answers are known.
# Usage: tests/tools/x4trace/test-x4trace.sh [X4TRACE_BINARY]  (default: build to a temp dir)
set -euo pipefail

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bin=${1:-}
if [ -z "$bin" ]; then
	bin=$tmp/x4trace
	g++ -std=c++17 -O2 -Wall -Wextra -Werror -o "$bin" "$(dirname "$0")/x4trace.cpp"
fi

# Times in us after the first write; the comments give the expected meaning.
cat >"$tmp/t.log" <<'EOF'
1@100.000000:parallel_ioport_write write [SW] addr 0x02 val 0x0c
1@100.000010:parallel_ioport_write write [SW] addr 0x00 val 0x00
1@100.000011:parallel_ioport_read read [SW] addr 0x01 val 0xdf
1@100.000012:parallel_ioport_write write [SW] addr 0x01 val 0x58
1@100.000013:parallel_ioport_write write [HW] addr 0x00 val 0xff
some other line
1@100.000100:parallel_ioport_write write [SW] addr 0x00 val 0x01
1@100.000200:parallel_ioport_write write [SW] addr 0x00 val 0x03
1@100.000210:parallel_ioport_write write [SW] addr 0x00 val 0x01
1@100.000300:parallel_ioport_write write [SW] addr 0x00 val 0x03
1@100.000305:parallel_ioport_write write [SW] addr 0x00 val 0x01
1@100.000350:parallel_ioport_write write [SW] addr 0x00 val 0x00
1@100.000400:parallel_ioport_write write [SW] addr 0x00 val 0x02
1@100.000420:parallel_ioport_write write [SW] addr 0x00 val 0x00
1@100.000500:parallel_ioport_write write [SW] addr 0x02 val 0x05
EOF
# Control 0x0c: C0=0 C1=0 (inverted: pins 1, 14 high), C2=1 (pin 16 high),
# C3=1 (inverted: pin 17 low). 0x05: pin 1 low, 14 high, 16 high, 17 high.
cat >"$tmp/edges.want" <<'EOF'
100.000 2 1
200.000 3 1
210.000 3 0
300.000 3 1
305.000 3 0
350.000 2 0
400.000 3 1
420.000 3 0
500.000 1 0
500.000 17 1
EOF

fails=0
ok() { echo "ok   $1"; }
bad() { echo "FAIL $1"; fails=$((fails + 1)); }

"$bin" edges "$tmp/t.log" >"$tmp/edges.got"
if diff -u "$tmp/edges.want" "$tmp/edges.got"; then ok edges; else bad edges; fi

"$bin" summary "$tmp/t.log" --json >"$tmp/s.json"
if command -v python3 >/dev/null; then
	if python3 - "$tmp/s.json" <<'EOF'; then ok summary-json; else bad summary-json; fi
import json, sys
s = json.load(open(sys.argv[1]))
pins = {p["pin"]: p for p in s["pins"]}
ax = s["axes"][0]
want = {
    "steps": 3, "steps_dir_high": 2, "steps_dir_low": 1,
    "first_rise_us": 200.0, "last_rise_us": 400.0, "min_period_us": 100.0,
    "min_high_us": 5.0, "min_low_us": 90.0, "dir_at_first_step": 1,
    "dir_changes_during_move": 1, "min_dir_setup_us": 50.0,
    "clk_pin": 3, "dir_pin": 2, "axis": 1,
}
errs = [f"axis1 {k}: {ax[k]} != {v}" for k, v in want.items() if ax[k] != v]
checks = [
    (s["writes"], 11), (s["data_writes"], 9), (s["control_writes"], 2),
    (pins[3]["rising"], 3), (pins[3]["falling"], 3), (pins[3]["final"], 0),
    (pins[2]["rising"], 1), (pins[2]["falling"], 1),
    (pins[1]["falling"], 1), (pins[1]["final"], 0), (pins[14]["final"], 1),
    (pins[16]["final"], 1), (pins[17]["rising"], 1), (pins[17]["final"], 1),
    (s["axes"][1]["steps"], 0), (s["axes"][1]["first_rise_us"], None),
]
errs += [f"check {i}: {g} != {w}" for i, (g, w) in enumerate(checks) if g != w]
for e in errs:
    print(e)
sys.exit(1 if errs else 0)
EOF
else
	echo "skip summary-json (no python3)"
fi

expect() { # NAME COMMAND...
	local name=$1
	shift
	if "$@"; then ok "$name"; else bad "$name"; fi
}
# shellcheck disable=SC2317 # called through expect()
status_is() { # WANT COMMAND...
	local want=$1 rc=0
	shift
	"$@" >/dev/null 2>&1 || rc=$?
	[ "$rc" = "$want" ]
}

"$bin" summary "$tmp/t.log" >"$tmp/s.txt"
expect summary-text grep -q '^axis 1 (clk pin 3, dir pin 2): 3 steps' "$tmp/s.txt"

"$bin" vcd "$tmp/t.log" "$tmp/t.vcd"
expect vcd-var grep -q '^.var wire 1 # pin03_clk1 .end$' "$tmp/t.vcd"
expect vcd-time grep -q '^#200000$' "$tmp/t.vcd"
expect vcd-rises test "$(grep -c '^1#$' "$tmp/t.vcd")" = 3

"$bin" svg "$tmp/t.log" "$tmp/t.svg"
"$bin" svg "$tmp/t.log" "$tmp/t0.svg" --bin-ms 0
expect svg-binned grep -q '<polyline' "$tmp/t.svg"
expect svg-per-step grep -q '<polyline' "$tmp/t0.svg"

# The same writes as x4vport's trace (ns), and back from our VCD.
awk -F'[@: ]' '/\[SW\] addr 0x0[02]/ {
	split($2, t, "."); printf "%d%06d000 %s %s\n", t[1], t[2], $7 == "0x00" ? "d" : "c", $9 }' \
	"$tmp/t.log" >"$tmp/v.trace"
echo "100000000011 s 0x78" >>"$tmp/v.trace" # status: not a pin we drive
"$bin" edges "$tmp/v.trace" >"$tmp/v.edges"
expect x4vport-edges diff -u "$tmp/edges.want" "$tmp/v.edges"
"$bin" edges "$tmp/t.vcd" >"$tmp/vcd.edges"
expect vcd-edges diff -u "$tmp/edges.want" "$tmp/vcd.edges"

# compare: the same edges, times within 1 us of the move's start (AKTIV).
cat >"$tmp/m.trace" <<'EOF2'
1000 c 0x0c
1000 d 0x00
5000 c 0x04
105000 d 0x01
205000 d 0x03
230000 d 0x01
305000 d 0x03
330000 d 0x01
400000 c 0x0c
EOF2
sed 's/^5000 c/90000 c/; s/^105000/190000/; s/^205000/290000/; s/^230000/315000/;
	s/^305000/390000/; s/^330000/415500/; s/^400000/485000/' "$tmp/m.trace" >"$tmp/m-late.trace"
expect compare-same status_is 0 "$bin" compare "$tmp/m.trace" "$tmp/m-late.trace"
expect compare-2us status_is 1 "$bin" compare "$tmp/m.trace" "$tmp/m-late.trace" --within-ns 400
sed '/^305000/d; /^330000/d' "$tmp/m.trace" >"$tmp/m-drop.trace"
expect compare-dropped status_is 1 "$bin" compare "$tmp/m.trace" "$tmp/m-drop.trace"
sed 's/^305000 d 0x03/305000 d 0x02/' "$tmp/m.trace" >"$tmp/m-dir.trace"
expect compare-order status_is 1 "$bin" compare "$tmp/m.trace" "$tmp/m-dir.trace"

# moves: steps per AKTIV-framed move and the leader's steps at its end with
# BOOST (pin 16) high: 2 after a brake along the ramp, 0 for a cut cruise.
cat >"$tmp/b.trace" <<'EOF2'
1000 c 0x08
1000 d 0x00
2000 c 0x04
3000 d 0x03
3500 d 0x01
4000 c 0x00
5000 d 0x03
5500 d 0x01
6000 c 0x04
7000 d 0x03
7500 d 0x01
8000 d 0x03
8500 d 0x01
9000 c 0x08
10000 c 0x00
11000 d 0x03
11500 d 0x01
12000 c 0x08
EOF2
printf '%s\n' "MOVE 1 steps 4 0 0 0 dirchanges 0 rampend 2 signal1 1" \
	"MOVE 2 steps 1 0 0 0 dirchanges 0 rampend 0 signal1 1" >"$tmp/b.want"
"$bin" moves "$tmp/b.trace" >"$tmp/b.got"
expect moves-rampend diff -u "$tmp/b.want" "$tmp/b.got"

# Errors: bad usage is status 2, unreadable input status 1.
expect usage status_is 2 "$bin"
expect unreadable status_is 1 "$bin" summary "$tmp/missing.log"
expect bad-bin status_is 2 "$bin" svg "$tmp/t.log" "$tmp/x.svg" --bin-ms -3

[ "$fails" = 0 ] && echo "x4trace: all tests passed"
exit "$fails"
