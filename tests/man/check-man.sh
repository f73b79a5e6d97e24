#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# The man pages say what their sources say (scripts/mkman.sh): x4ctl.1, as
# groff renders it, holds every line of `x4ctl --help` and of `x4ctl help
# COMMAND` for each command; x4step.3 has a section for every function the
# C headers declare, and every constant they document.
# Both have an ENVIRONMENT entry for every variable the library and x4ctl
# read (getenv), and x4step-machine.5 names every key the machine file
# parser knows (lib/machine/machine.cpp's x4step_keys).
#   check-man.sh X4CTL X4CTL.1 X4STEP.3 X4STEP-MACHINE.5 HEADER...
set -eu
bin=$1 x4ctl_page=$2 lib_page=$3 machine_page=$4
shift 4
top=$(cd "$(dirname "$0")/../.." && pwd)
failed=0
fail() {
	echo "FAIL $1"
	failed=1
}
render() { groff -man -Tascii -P-cbou -ww "$1" 2>&1 | sed 's/^ *//'; }

page=$(render "$x4ctl_page")
# Each help text, line by line (leading blanks aside), is in the page.
has_lines() { # WHAT TEXT
	printf '%s\n' "$2" | sed 's/^ *//; /^$/d' | while IFS= read -r line; do
		printf '%s\n' "$page" | grep -qxF -- "$line" || {
			echo "FAIL x4ctl.1 lacks this line of $1: $line"
			return 1
		}
	done
}
has_lines "x4ctl --help" "$("$bin" --help)" || failed=1
cmds=$("$bin" --help | sed -n '/^Commands:/,/^Run /s/^  \([a-z][a-z-]*\)\( .*\)\{0,1\}$/\1/p')
[ "$(printf '%s\n' "$cmds" | wc -l)" -ge 20 ] || fail "x4ctl --help lists only: $cmds"
for c in $cmds; do
	has_lines "x4ctl help $c" "$("$bin" help "$c")" || failed=1
done

page=$(render "$lib_page")
for h in "$@"; do
	# shellcheck disable=SC2013 # one function name a line: words
	for f in $(sed -n 's/^[a-z][a-z ]* \**\(X4[A-Za-z]*\)(.*);$/\1/p' "$h"); do
		printf '%s\n' "$page" | grep -q "^[a-z][a-z ]* \**$f(" || fail "x4step.3 lacks $f() of $h"
	done
	# shellcheck disable=SC2013 # one macro name a line: words
	for d in $(sed -n 's/^#define \([A-Za-z0-9_]*\) .*\/\*\*<.*/\1/p' "$h"); do
		printf '%s\n' "$page" | grep -q "^$d " || fail "x4step.3 lacks $d of $h"
	done
done
# The variables x4ctl and the library read; the library's are in x4step.3 too.
# The lines of a section of a page (headings are the lines not indented).
section() { groff -man -Tascii -P-cbou -ww "$1" 2>&1 | sed -n "/^$2\$/,/^[A-Z][A-Z ]*\$/p" | sed 's/^ *//'; }
# shellcheck disable=SC2013 # one variable name a line: words
for v in $(grep -rhoE 'getenv\("X4STEP_[A-Z_]+"' "$top/lib" "$top/tools" | sed 's/.*"\(.*\)"/\1/' | sort -u); do
	section "$x4ctl_page" ENVIRONMENT | grep -q "^$v\b" || fail "x4ctl.1's ENVIRONMENT lacks $v"
	if grep -rq "getenv(\"$v\"" "$top/lib"; then
		section "$lib_page" ENVIRONMENT | grep -q "^$v\b" || fail "x4step.3's ENVIRONMENT lacks $v"
	fi
done
section "$lib_page" EXAMPLES | grep -qF 'int err = X4Init(LPT1);' || fail "x4step.3's EXAMPLES lacks examples/first.c"
section "$x4ctl_page" EXAMPLES | grep -q '^x4ctl gcode ' || fail "x4ctl.1's EXAMPLES lacks the help texts' examples"
# Every key of the machine file.
keys=$(sed -n '/x4step_keys\[\] = {/,/^};/s/^ *{"[A-Z0-9_]*", "\([A-Z0-9_]*\)"},$/\1/p' "$top/lib/machine/machine.cpp")
[ "$(printf '%s\n' "$keys" | wc -l)" -ge 20 ] || fail "found only these machine file keys: $keys"
for k in $keys; do
	section "$machine_page" KEYS | grep -q "^$k\b" || fail "x4step-machine.5's KEYS lacks $k"
done
[ "$failed" = 0 ] && echo "PASS the man pages hold the help texts, the headers' API, the environment and the machine file's keys"
exit "$failed"
