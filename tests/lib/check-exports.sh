#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# libx4step.so exports the C API and libx4stepcxx.so the C++ API, nothing
# else (no engine, no std:: instantiations), under sonames that agree with
# the file names. Usage: check-exports.sh LIBDIR
set -u
dir=${1:?usage: check-exports.sh LIBDIR}
fail=0
check() { # LIB SONAME FILTER: every defined dynamic symbol passes FILTER
	lib=$dir/$1
	soname=$(readelf -d "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
	real=$(basename "$(readlink -f "$lib")")
	case "$real" in
	"$2".*) ;;
	*) echo "$1: file $real does not carry its soname $2" && fail=1 ;;
	esac
	[ "$soname" = "$2" ] || { echo "$1: soname '$soname', want $2" && fail=1; }
	bad=$(nm -D --defined-only "$lib" | awk '$2 != "A" { print $3 }' | c++filt | sed 's/@@.*//' | grep -Ev "$3")
	[ -z "$bad" ] || { echo "$1 exports what is not its API:" && echo "$bad" | head -20 && fail=1; }
	n=$(nm -D --defined-only "$lib" | awk '$2 != "A"' | wc -l)
	echo "$1: $n symbols, soname $soname, file $real"
}
check libx4step.so libx4step.so.1 '^X4[A-Z][A-Za-z]*$'
check libx4stepcxx.so libx4stepcxx.so.1 '^((typeinfo (name )?for |vtable for )?x4step::[^(]|x4step::[a-z_]+\()'
exit $fail
