#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Static checks: the module is checkpatch-clean, sparse-clean and W=1
# warning-free on every kernel; user space is clang-format clean; shell
# scripts pass shellcheck; the docs' links and test map hold.
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
	# shellcheck disable=SC2012 # sorted by version, names without spaces
	tarball=$(ls /usr/src/linux-source-*.tar.xz 2>/dev/null | sort -V | tail -n 1)
	mkdir -p "$cp_dir"
	tar -xJf "$tarball" -C "$cp_dir" --strip-components=1 --wildcards \
		'*/scripts/checkpatch.pl' '*/scripts/spelling.txt' \
		'*/scripts/const_structs.checkpatch'
fi
checkpatch="$cp_dir/scripts/checkpatch.pl --no-tree -q -f"
kfiles=$(cd "$top" && git ls-files 'kmod/*.[ch]' 'tests/qemu/fixtures/*.[ch]' include/uapi | grep -v x4step_compat.h)
# shellcheck disable=SC2086 # the command with its options, and the files, are words
(cd "$top" && $checkpatch $kfiles &&
	$checkpatch --ignore LINUX_VERSION_CODE,CONSTANT_COMPARISON kmod/x4step_compat.h) \
	>"$out/checkpatch.log" 2>&1
st=$?
cat "$out/checkpatch.log"
result $st "checkpatch (kmod, uapi, tests/qemu/fixtures)"

# Build with W=1 and sparse (C=2: check every file) against each kernel.
# shellcheck disable=SC2012 # sorted by version, names without spaces
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
	grep -v '^Skipping BTF' "$out/build-$kver.log"
	result $st "module builds with W=1, sparse-clean on $kver"
	"$top/tests/check-layers.sh" glue "$src/kmod"
	result $? "kernel glue: each file calls only the files below it ($kver)"
done

# 32-bit kernels have no 64-bit division in their libgcc: a raw '/' or '%'
# on u64 in the engine makes the module fail to link there (__udivdi3). The
# engine divides through x4_div() (div64_u64 in the kernel). Each engine
# file is compiled as user space for i386, where such divisions call the
# helpers below, with X4_DIV_EXTERN defined: under it the engine declares
# its user-space x4_div() as an external function (x4_div64_u64()),
# so that only raw divisions call a helper. Functions named x4_div* may
# (a user-space x4_div defined in the engine itself); -fno-inline keeps it
# out of its callers and -ffunction-sections names the functions that do.
# (An engine whose user-space x4_div is still the macro a / b fails here
# for every x4_div() too.)
m32=$out/m32
rm -rf "$m32"
mkdir -p "$m32"
if [ -d "$top/kmod/engine" ]; then
	efiles=$(ls "$top"/kmod/engine/*.c)
else
	efiles=$top/kmod/x4_engine.c
fi
if ! printf '#include <stdint.h>\n#include <string.h>\n' |
	gcc -m32 -x c -c -o /dev/null - >"$m32/probe.log" 2>&1; then
	cat "$m32/probe.log"
	echo "gcc -m32 cannot compile user space for i386: install gcc-multilib (scripts/deps.sh test)"
	result 1 "32-bit: gcc -m32 unavailable, engine's 64-bit divisions not checked"
else
	st=0
	for f in $efiles; do
		o=$m32/$(basename "$f" .c).o
		if ! gcc -m32 -O2 -fno-inline -ffunction-sections -DX4_DIV_EXTERN \
			'-Dnoinline=__attribute__((noinline))' -I"$(dirname "$f")" -I"$top/kmod" -I"$top/include/uapi" \
			-c "$f" -o "$o" >"$m32/build.log" 2>&1; then
			cat "$m32/build.log"
			echo "${f#"$top"/}: does not compile with gcc -m32"
			st=1
			continue
		fi
		helpers=$(nm -u "$o" | awk '$2 ~ /^__(u?div|u?mod)di3$/ { print $2 }' | sort -u | tr '\n' ' ' | sed 's/ $//')
		[ -n "$helpers" ] || continue
		# The functions whose code calls them (relocation section .rel.text.FN).
		fns=$(readelf -rW "$o" | awk '
			/^Relocation section/ { s = $3; gsub(/[\047]/, "", s); sub(/^\.rela?\.text\.?/, "", s) }
			/__(u?div|u?mod)di3/ && s !~ /^x4_div/ { print (s == "" ? "?" : s) }' | sort -u | tr '\n' ' ' | sed 's/ $//')
		[ -n "$fns" ] || continue
		echo "${f#"$top"/}: 64-bit division ($helpers) in: $fns"
		st=1
	done
	[ $st -eq 0 ] || echo "divide u64 with x4_div(), never with '/' or '%' (they need libgcc's helpers on 32-bit kernels)"
	result $st "32-bit: the engine calls no 64-bit division helper (gcc -m32, __udivdi3 and co.)"
fi

# The engine's levels call only downward (kmod/engine/sources.mk).
"$top/tests/check-layers.sh"
result $? "engine: each level calls only the levels below it (tests/check-layers.sh)"

# User space follows .clang-format.
# Every C++ file and header, and the C API's headers (the uapi header is kernel style).
files=$(cd "$top" && git ls-files 'lib/*.cpp' 'lib/*.hpp' 'include/*.hpp' 'include/*.h' 'tools/*.cpp' 'tools/*.hpp' \
	'tests/*.cpp' 'tests/*.hpp' 'tests/*.h' | grep -v '^include/uapi/')
# shellcheck disable=SC2086 # the tracked files, names without spaces
(cd "$top" && clang-format --dry-run -Werror $files) >"$out/clang-format.log" 2>&1
st=$?
head -20 "$out/clang-format.log"
result $st "clang-format (user space)"

# Every shell script (by name, or by its #! line) passes shellcheck;
# a warning that does not apply is disabled on its line, with the reason.
shfiles=$(cd "$top" && git ls-files | while read -r f; do
	case ${f##*/} in
	*.sh) echo "$f" ;;
	*.* | Kbuild | Makefile) ;; # other languages
	*) head -n 1 "$f" 2>/dev/null | grep -qE '^#! ?/bin/(ba)?sh|^#! ?/usr/bin/env (ba)?sh' && echo "$f" ;;
	esac
done)
if command -v shellcheck >/dev/null; then
	# shellcheck disable=SC2086 # the tracked files, names without spaces
	(cd "$top" && shellcheck $shfiles) >"$out/shellcheck.log" 2>&1
	st=$?
	head -n 40 "$out/shellcheck.log"
else
	echo "shellcheck is missing: install it (scripts/deps.sh test)"
	st=1
fi
result $st "shellcheck ($(printf "%s\n" "$shfiles" | grep -c .) shell scripts)"

# The documentation points at files that exist, inside the tree, and
# tests/README.md maps every source file to its tests.
"$top/tests/check-docs.py" "$top"
result $? "docs: relative links and file paths in Markdown exist, every source file mapped to its tests"
exit $fail
