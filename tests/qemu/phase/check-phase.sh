#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Host check of the phase drive: the data register bytes QEMU saw, from
# the switch to phase mode on, are exactly those of the guest's PHASE
# line. Usage: check-phase.sh OUTDIR KVER
set -eu
out=${1:?}
want=$(tr -d '\r' <"$out/console.log" | sed -n 's/^PHASE //p')
# Data writes as two-digit hex, in order.
seen=$(sed -n 's/.*addr 0x00 val 0x\([0-9a-f]*\).*/\1/p' "$out/lpt-test.log" |
	while read -r v; do printf '%02x ' "0x$v"; done)
echo "expected: $want"
echo "seen:     $seen"
case " $seen" in
*" $want "*) echo "ok: the exact byte sequence" ;;
*) echo "BAD: sequence not found"; exit 1 ;;
esac
