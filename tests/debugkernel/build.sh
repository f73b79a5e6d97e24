#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# Build (or reuse) the x4step debug kernel: Debian's linux-source-6.1,
# `make tinyconfig` + tests/debugkernel/x4step-debug.config (lockdep,
# atomic-sleep, KASAN, UBSAN, debugobjects for timers, and what the QEMU
# bench needs), bzImage + modules.
#
# Usage: tests/debugkernel/build.sh [OUTDIR]     (default build/debugkernel)
#
# The kernel tree is built in a cache directory that survives fresh clones:
#   ${X4_CACHE:-/var/cache/x4step}/debugkernel-KEY/
# KEY = sha256 of the config fragment, the linux-source package version and the
# compiler version. A finished build there (bzImage, modules, release file) is
# reused. If the cache root cannot be created, KEY's directory goes under OUTDIR.
#
# As root the result is installed where tests/qemu/run-guest.sh looks:
#   /boot/vmlinuz-RELEASE, /lib/modules/RELEASE/ (RELEASE e.g. 6.1.192-x4debug),
#   with /lib/modules/RELEASE/build -> the built tree, so that
#   make -C /lib/modules/RELEASE/build M=DIR modules  builds out-of-tree modules.
# OUTDIR gets: release (the kernel release string), bzImage, kdir -> the tree,
# modroot/lib/modules/RELEASE, build.log, build-time.
# X4_JOBS sets make's -j (default: number of CPUs).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
top=$(cd "$here/../.." && pwd)
frag=$here/x4step-debug.config
out=${1:-$top/build/debugkernel}
jobs=${X4_JOBS:-$(nproc)}
srcpkg=linux-source-6.1
tarball=/usr/src/linux-source-6.1.tar.xz

say() { echo "debugkernel: $*" >&2; }
die() {
	say "ERROR: $*"
	exit 1
}

if [ ! -r "$tarball" ]; then
	if [ "$(id -u)" -eq 0 ]; then
		say "installing $srcpkg"
		DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "$srcpkg" >/dev/null ||
			die "apt-get install $srcpkg failed"
	fi
	[ -r "$tarball" ] || die "no $tarball: install $srcpkg (scripts/deps.sh test)"
fi
for t in make gcc flex bison bc; do
	command -v "$t" >/dev/null || die "$t not installed (scripts/deps.sh)"
done
[ -e /usr/include/libelf.h ] || die "libelf-dev not installed (objtool needs it)"
[ -e /usr/include/openssl/ssl.h ] || die "libssl-dev not installed"

srcver=$(dpkg-query -W -f='${Version}' "$srcpkg" 2>/dev/null || stat -c %Y "$tarball")
ccver=$(gcc --version | head -n1)
# The recipe below is part of the key too: bump when it changes the result.
recipe=1
key=$( {
	cat "$frag"
	echo "source $srcpkg $srcver"
	echo "cc $ccver"
	echo "recipe $recipe"
} | sha256sum | cut -c1-16)

mkdir -p "$out"
out=$(cd "$out" && pwd)
cache_root=${X4_CACHE:-/var/cache/x4step}
if ! mkdir -p "$cache_root" 2>/dev/null || [ ! -w "$cache_root" ]; then
	say "cannot use cache $cache_root, building under $out"
	cache_root=$out
fi
cache=$cache_root/debugkernel-$key
tree=$cache/linux
mkdir -p "$cache"

# One build per key at a time (CI and a developer may race).
exec 9>"$cache/lock"
flock 9

if [ -f "$cache/done" ] && [ -f "$tree/arch/x86/boot/bzImage" ] && [ -d "$cache/modroot/lib/modules" ]; then
	release=$(cat "$cache/done")
	say "reusing cached debug kernel $release (key $key) in $cache"
else
	rm -rf "$tree" "$cache/modroot" "$cache/done"
	log=$cache/build.log
	: >"$log"
	t0=$(date +%s)
	say "unpacking $tarball into $cache (key $key)"
	mkdir -p "$tree"
	# Documentation's subdirectories are not needed (Documentation/Kconfig is).
	tar -xJf "$tarball" -C "$tree" --strip-components=1 --exclude='linux-source-6.1/Documentation/*/*'
	t1=$(date +%s)
	say "configuring: tinyconfig + $(basename "$frag")"
	(
		cd "$tree"
		make tinyconfig &&
			scripts/kconfig/merge_config.sh -m .config "$frag" &&
			make olddefconfig
	) >>"$log" 2>&1 || die "configuration failed, see $log"

	# Options whose silent loss would make the debug kernel pointless.
	need=$(sed -n 's/^\(CONFIG_[A-Z0-9_]*\)=\([ym]\)$/\1=\2/p' "$frag")
	lost=""
	for opt in $need; do
		grep -qx "$opt" "$tree/.config" || lost="$lost $opt"
	done
	if [ -n "$lost" ]; then
		for opt in $lost; do
			say "config lost $opt (now: $(grep -E "^(# )?${opt%%=*}[= ]" "$tree/.config" || echo absent))"
		done
		die "olddefconfig dropped options from $(basename "$frag"); fix the fragment"
	fi
	grep -q '^CONFIG_LOCALVERSION="-x4debug"$' "$tree/.config" || die "CONFIG_LOCALVERSION lost"

	say "building bzImage and modules with -j$jobs (log: $log)"
	(cd "$tree" && make -j"$jobs" bzImage modules) >>"$log" 2>&1 || {
		tail -n 30 "$log" >&2
		die "kernel build failed, see $log"
	}
	release=$(cd "$tree" && make -s kernelrelease)
	(cd "$tree" && make modules_install INSTALL_MOD_PATH="$cache/modroot") >>"$log" 2>&1 ||
		die "modules_install failed, see $log"
	# For out-of-tree modules: the tree as built already has what
	# modules_prepare makes; make sure of it anyway (cheap when up to date).
	(cd "$tree" && make -j"$jobs" modules_prepare) >>"$log" 2>&1 || die "modules_prepare failed, see $log"
	t2=$(date +%s)
	echo "unpack $((t1 - t0))s, configure+build $((t2 - t1))s, total $((t2 - t0))s with -j$jobs on $(nproc) CPUs" >"$cache/build-time"
	echo "$release" >"$cache/done"
	say "built $release in $((t2 - t0))s ($(cat "$cache/build-time"))"
	# Keep this and the newest other finished build (about 1.7 GB each);
	# skip any that another build.sh holds.
	# shellcheck disable=SC2012 # our own directory names
	for old in $(ls -1dt "$cache_root"/debugkernel-*/done 2>/dev/null | tail -n +3); do
		old=$(dirname "$old")
		[ "$old" != "$cache" ] || continue
		(flock -n 9 && rm -rf "$old" && echo "debugkernel: removed old build $old" >&2) 9>>"$old/lock" || true
	done
fi

modsrc=$cache/modroot/lib/modules/$release
for m in parport parport_pc; do
	[ -n "$(find "$modsrc/kernel/drivers/parport" -name "$m.ko*" 2>/dev/null)" ] ||
		die "$m.ko missing under $modsrc"
done

# Results in OUTDIR.
echo "$release" >"$out/release"
cp "$tree/arch/x86/boot/bzImage" "$out/bzImage"
ln -sfn "$tree" "$out/kdir"
rm -rf "$out/modroot"
mkdir -p "$out/modroot/lib/modules"
cp -a "$modsrc" "$out/modroot/lib/modules/"
for f in build.log build-time; do [ -f "$cache/$f" ] && cp "$cache/$f" "$out/$f"; done

# Install where run-guest.sh and run-suite.sh look (root only).
if [ "$(id -u)" -eq 0 ]; then
	install -m 0644 "$tree/arch/x86/boot/bzImage" "/boot/vmlinuz-$release"
	install -m 0644 "$tree/System.map" "/boot/System.map-$release"
	install -m 0644 "$tree/.config" "/boot/config-$release"
	rm -rf "/lib/modules/$release"
	cp -a "$modsrc" "/lib/modules/$release"
	# run-guest.sh looks for uinput and evdev in these directories (built in
	# here): a missing directory makes its find fail under pipefail.
	mkdir -p "/lib/modules/$release/kernel/drivers/input/misc"
	rm -f "/lib/modules/$release/build" "/lib/modules/$release/source"
	ln -s "$tree" "/lib/modules/$release/build"
	ln -s "$tree" "/lib/modules/$release/source"
	say "installed /boot/vmlinuz-$release and /lib/modules/$release (build -> $tree)"
else
	say "not root: not installed; kernel $out/bzImage, modules $out/modroot, tree $out/kdir"
fi
echo "$release"
