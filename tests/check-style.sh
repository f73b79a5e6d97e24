#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Static checks: the module is checkpatch-clean, sparse-clean and W=1
# warning-free on every kernel; user space is clang-format clean.
# Prints PASS/FAIL lines; exits non-zero if any failed.
set -u
top=$(cd "$(dirname "$0")/.." && pwd)
out=$top/build/style
mkdir -p "$out"
fail=0
result() { # STATUS NAME
	if [ "$1" -eq 0 ]; then echo "PASS $2"; else echo "FAIL $2"; fail=1; fi
}

# checkpatch.pl comes with Debian's kernel source; unpack just the script.
cp_dir=$out/checkpatch
if [ ! -x "$cp_dir/scripts/checkpatch.pl" ]; then
	tarball=$(ls /usr/src/linux-source-*.tar.xz 2>/dev/null | sort -V | tail -n 1)
	mkdir -p "$cp_dir"
	tar -xJf "$tarball" -C "$cp_dir" --strip-components=1 --wildcards \
		'*/scripts/checkpatch.pl' '*/scripts/spelling.txt' \
		'*/scripts/const_structs.checkpatch'
fi
checkpatch="$cp_dir/scripts/checkpatch.pl --no-tree -q -f"
kfiles=$(cd "$top" && git ls-files 'kmod/*.[ch]' 'tests/kmod/*.[ch]' include/uapi | grep -v x4step_compat.h)
(cd "$top" && $checkpatch $kfiles &&
	$checkpatch --ignore LINUX_VERSION_CODE,CONSTANT_COMPARISON kmod/x4step_compat.h) \
	>"$out/checkpatch.log" 2>&1
st=$?
cat "$out/checkpatch.log"
result $st "checkpatch (kmod, uapi, tests/kmod)"

# Build with W=1 and sparse (C=2: check every file) against each kernel.
for hdr in $(ls -d /usr/src/linux-headers-*-amd64 | sort -V); do
	kver=${hdr#/usr/src/linux-headers-}
	src=$out/$kver
	rm -rf "$src"
	mkdir -p "$src"
	cp -r "$top/kmod" "$top/include" "$top/Kbuild" "$src/"
	make -s -C "$hdr" M="$src" W=1 C=2 modules >"$out/build-$kver.log" 2>&1
	st=$?
	# Anything the compiler or sparse says is a failure (BTF note aside).
	grep -v -e '^Skipping BTF' -e '^  ' "$out/build-$kver.log" | grep -q . && st=1
	cat "$out/build-$kver.log" | grep -v '^Skipping BTF'
	result $st "module builds with W=1, sparse-clean on $kver"
done

# User space follows .clang-format.
files=$(cd "$top" && git ls-files 'lib/*.cpp' 'include/*.hpp' 'tools/*.cpp' 'tests/*.cpp' 'tools/*.hpp' 'tests/*.h')
(cd "$top" && clang-format --dry-run -Werror $files) >"$out/clang-format.log" 2>&1
st=$?
head -20 "$out/clang-format.log"
result $st "clang-format (user space)"
exit $fail
