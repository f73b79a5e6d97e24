#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Host check of the faithfulness test (README.md here): the moves that
# faith_moves made on the module in the guest (x4vport's trace, `XV` lines
# of console.log) are made again on the simulated port, virtual time, with
# the same machine; both must give the same edges (x4trace compare: counts,
# order per pin, times within 1 us, README.md) and the module
# must report the same coordinates, errors and steps (`FAITH` lines).
# Usage: check-faith.sh OUTDIR KVER   (X4TRACE: a built tests/tools/x4trace)
set -eu
out=${1:?usage: check-faith.sh OUTDIR KVER}
here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../../.." && pwd)
x4trace=${X4TRACE:?X4TRACE must name a built tests/tools/x4trace}
moves=${FAITH_MOVES:-$top/build/guest/faith_moves}
within=${FAITH_WITHIN_NS:-1000}

tr -d '\r' <"$out/console.log" >"$out/console.txt"
sed -n 's/^XV //p' "$out/console.txt" >"$out/guest.trace"
want=$(sed -n 's/^XV-BEGIN //p' "$out/console.txt")
got=$(wc -l <"$out/guest.trace")
if [ -z "$want" ] || [ "$want" != "$got" ]; then
	echo "BAD: guest trace has $got of ${want:-?} lines"
	exit 1
fi
grep '^FAITH ' "$out/console.txt" >"$out/guest.faith" || true

X4STEP_SIM=1 X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD="$out/sim.vcd" \
	X4STEP_SIM_MACHINE="$here/faith.machine" "$moves" 2 >"$out/sim.faith"
if ! diff -u "$out/guest.faith" "$out/sim.faith"; then
	echo "BAD: the module and the simulator report different coordinates, errors or steps"
	exit 1
fi
echo "ok: $(wc -l <"$out/sim.faith") stages report the same coordinates, errors and steps"
"$x4trace" compare "$out/guest.trace" "$out/sim.vcd" --within-ns "$within" --max-ns 3000 --late-ns 1500 \
	--permille 3
