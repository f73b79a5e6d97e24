#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# Unpack a compressed kernel (bzImage) into the ELF kernel it carries, for
# QEMU to boot through the kernel's PVH entry: that skips the decompressor,
# which under TCG takes 3 s of every boot (7 s with --icount).
#
# Usage: tests/qemu/pvh-kernel.sh VMLINUZ OUT
# Writes OUT and exits 0 if VMLINUZ holds an xz, zstd or gzip compressed ELF
# kernel with a PVH entry (CONFIG_PVH: the Xen ELF note PHYS32_ENTRY, type
# 18); exits 1 without OUT otherwise (boot VMLINUZ itself then).
set -euo pipefail

[ $# -eq 2 ] || { echo "usage: $0 VMLINUZ OUT" >&2; exit 2; }
img=$1 out=$2
[ -r "$img" ] || { echo "pvh-kernel: cannot read $img" >&2; exit 2; }
tmp=$out.tmp.$$
trap 'rm -f "$tmp"' EXIT

# The byte offset of the first compressed stream of a kind, and its unpacker.
found() { # MAGIC (grep -P escapes)
	LC_ALL=C grep -obUaP -m1 "$1" "$img" | head -n1 | cut -d: -f1
}
for kind in 'xz -dc --single-stream|\xfd7zXZ\x00' 'zstd -qdc|\x28\xb5\x2f\xfd' 'gzip -dc|\x1f\x8b\x08'; do
	off=$(found "${kind#*|}" || true)
	[ -n "$off" ] || continue
	# Data after the stream is the decompressor's, not the kernel's: zstd and
	# gzip complain about it after writing the kernel out, hence no status.
	tail -c +$((off + 1)) "$img" | ${kind%%|*} >"$tmp" 2>/dev/null || true
	if [ "$(head -c 4 "$tmp" | od -An -tx1 | tr -d ' ')" = 7f454c46 ] &&
		readelf -n "$tmp" 2>/dev/null | grep -q 'Xen .*(0x00000012)'; then
		mv "$tmp" "$out"
		exit 0
	fi
done
exit 1
