#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Install the Debian packages that building, testing and the demo need.
# Usage: scripts/deps.sh [build|test|all]   (default: all)
# As root it runs apt-get for whatever is missing; otherwise it names the
# packages to install and fails, so nothing depends on what happens to be
# on the machine.
set -eu

build_pkgs="make gcc g++ cmake pkg-config kmod linux-headers-amd64"
test_pkgs="$build_pkgs libgtest-dev valgrind time qemu-system-x86 busybox-static cpio xz-utils zstd \
linux-image-amd64 linux-image-6.12-amd64 linux-headers-6.12-amd64 \
linux-image-6.12-rt-amd64 linux-headers-6.12-rt-amd64 sparse clang-format shellcheck python3 gcc-multilib groff-base strace \
linux-source-6.1 flex bison bc libelf-dev libssl-dev"

case "${1:-all}" in
build) want=$build_pkgs ;;
test | all) want=$test_pkgs ;;
*) echo "usage: $0 [build|test|all]" >&2; exit 2 ;;
esac

# The G-code tests' oracle, LinuxCNC's rs274: unpacked into a cache, not
# installed (scripts/get-rs274.sh).
if [ "${1:-all}" != build ] && [ "$(id -u)" -eq 0 ]; then
	"$(dirname "$0")/get-rs274.sh"
fi

missing=""
for p in $want; do
	dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed" || missing="$missing $p"
done
# Node.js and npm run CNCjs, the G-code sender that tests the GRBL bridge
# (tests/grbl/cncjs/): any Node.js >= 18 with its npm. A machine that has
# them from elsewhere keeps them (NodeSource's nodejs conflicts with
# Debian's npm); otherwise Debian's nodejs and npm.
if [ "${1:-all}" != build ] && ! { command -v node && command -v npm; } >/dev/null; then
	missing="$missing nodejs npm"
fi

if [ -n "$missing" ]; then
	if [ "$(id -u)" -ne 0 ]; then
		echo "x4step: missing Debian packages:$missing" >&2
		echo "x4step: install them with: sudo apt-get install$missing" >&2
		exit 1
	fi
	echo "x4step: installing$missing"
	export DEBIAN_FRONTEND=noninteractive
	apt-get update -q >/dev/null
	# shellcheck disable=SC2086
	apt-get install -y -q --no-install-recommends $missing >/dev/null
fi

# CNCjs itself: from the npm registry into a cache, not installed
# (scripts/get-cncjs.sh).
if [ "${1:-all}" != build ] && [ "$(id -u)" -eq 0 ]; then
	"$(dirname "$0")/get-cncjs.sh"
fi
