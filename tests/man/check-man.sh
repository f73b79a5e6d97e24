#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# The man pages say what their sources say (tools/mkman.sh): x4ctl.1, as
# groff renders it, holds every line of `x4ctl --help` and of `x4ctl help
# COMMAND` for each command; x4step.3 has a section for every function the
# C headers declare, and every constant they document.
#   check-man.sh X4CTL X4CTL.1 X4STEP.3 HEADER...
set -eu
bin=$1 x4ctl_page=$2 lib_page=$3
shift 3
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
	for f in $(sed -n 's/^[a-z][a-z ]* \**\(X4[A-Za-z]*\)(.*);$/\1/p' "$h"); do
		printf '%s\n' "$page" | grep -q "^[a-z][a-z ]* \**$f(" || fail "x4step.3 lacks $f() of $h"
	done
	for d in $(sed -n 's/^#define \([A-Za-z0-9_]*\) .*\/\*\*<.*/\1/p' "$h"); do
		printf '%s\n' "$page" | grep -q "^$d " || fail "x4step.3 lacks $d of $h"
	done
done
[ "$failed" = 0 ] && echo "PASS the man pages hold the help texts and the headers' API"
exit "$failed"
