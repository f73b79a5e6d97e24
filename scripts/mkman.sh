#!/bin/sh
# SPDX-License-Identifier: GPL-2.0
# Man pages from the texts the project keeps anyway, so that they cannot
# drift apart from them:
#   mkman.sh x4ctl X4CTL VERSION OUT.1     x4ctl(1) from `x4ctl --help` and
#                                          `x4ctl help COMMAND` of every command
#   mkman.sh header VERSION OUT.3 HEADER...  x4step(3) from the doc comments
#                                          (/** ... */) of the C headers
#   mkman.sh machine VERSION OUT.5         x4step-machine(5) from machines/README.md
#   mkman.sh x4grbl X4GRBL VERSION OUT.1   x4grbl(1) from `x4grbl --help` and docs/grbl.md
# ENVIRONMENT comes from docs/simulator.md's table, EXAMPLES from the help
# texts' examples and examples/ (scripts/md2man.py turns Markdown to roff).
# The texts are kept as they are (no-fill blocks): what --help shows is what
# man shows. tests/man/check-man.sh checks that.
set -eu
top=$(cd "$(dirname "$0")/.." && pwd)

# Text to roff, line by line: backslashes, minus signs, and lines that roff
# would take for requests.
esc() { sed -e 's/\\/\\e/g' -e 's/-/\\-/g' -e "s/^[.']/\\\\\\&&/"; }

# A no-fill block of standard input.
block() {
	echo ".nf"
	esc
	echo ".fi"
}

x4ctl_page() {
	bin=$1 version=$2
	main=$("$bin" --help)
	cat <<EOF
.TH X4CTL 1 "" "x4ctl $version" "User Commands"
.SH NAME
x4ctl \\- stepper motors on the PC parallel port (x4step), and X4Step's test program
.SH SYNOPSIS
EOF
	# The Usage lines, then the rest of the help.
	printf '%s\n' "$main" | sed -n '/^Usage:/,/^$/p' | sed '/^$/d' | block
	echo ".SH DESCRIPTION"
	printf '%s\n' "$main" | sed '1,/^$/d' | block
	echo ".SH COMMANDS"
	# Every command the overview lists ("  NAME ..." after "Commands:").
	cmds=$(printf '%s\n' "$main" | sed -n '/^Commands:/,/^Run /s/^  \([a-z][a-z-]*\)\( .*\)\{0,1\}$/\1/p')
	for c in $cmds; do
		echo ".SS $c"
		"$bin" help "$c" | block
	done
	cat <<'EOF'
.SH ENVIRONMENT
.TP
.B X4STEP_MACHINE
the machine file of the commands that take \fB\-\-machine\fR, when it is not given
EOF
	"$top/scripts/md2man.py" "$top/docs/simulator.md" "Names and settings"
	echo ".SH EXAMPLES"
	# The examples of every command's help, in the order of the overview.
	for c in $cmds; do
		"$bin" help "$c" | sed -n '/^Examples\{0,1\}:/,/^[^ E]/{/^[^ E]/d;s/^Examples\{0,1\}: *//;/^$/d;p}'
	done | sed 's/^ *//' | block
	cat <<'EOF'
.SH FILES
.TP
.I /dev/x4stepN
the port parportN (LPT N+1); group lp may open it
.SH SEE ALSO
.BR x4step (3),
.BR x4step\-machine (5)
EOF
}

# The doc comments of C headers: each function's comment under its
# prototype, the constants with their /**< */ notes, the file comments as
# the description.
header_page() {
	version=$1
	shift
	cat <<EOF
.TH X4STEP 3 "" "libx4step $version" "Library Functions Manual"
.SH NAME
x4step \\- the X4Step C API: stepper motors on the PC parallel port
.SH SYNOPSIS
.nf
.B #include <x4step.h>
.B #include <x4step_ext.h>
.PP
Link with \\fI\\-lx4step\\fP (pkg-config x4step).
.fi
EOF
	for h in "$@"; do
		echo ".SH $(basename "$h" | tr '[:lower:]' '[:upper:]' | sed 's/-/\\-/g')"
		awk '
		function flush_text(   i) {
			for (i = 1; i <= n; i++) print text[i]
			n = 0
		}
		# A comment line: lists and @return start a new line.
		function add(line) {
			sub(/^ +/, "", line)
			sub(/^@brief /, "", line)
			if (line ~ /^@file/) { file = 1; return }
			if (line ~ /^(- |@return)/) text[++n] = "@BR"
			sub(/^@return/, "Returns:", line)
			if (line != "" || n) text[++n] = line
		}
		/^ *\/\*\*</ { next }
		/\/\*\*/ && !/\/\*\*</ {
			incomment = 1; n = 0; file = 0
			line = $0; sub(/.*\/\*\* ?/, "", line)
			if (line ~ /\*\//) { sub(/ *\*\/.*/, "", line); incomment = 0; pending = 1 }
			add(line)
			if (!incomment && file) { flush_text(); pending = 0 }
			next
		}
		incomment {
			line = $0
			if (line ~ /\*\//) { sub(/ *\*\/.*/, "", line); incomment = 0; pending = 1 }
			sub(/^ *\* ?/, "", line)
			add(line)
			if (!incomment && file) { flush_text(); pending = 0 }
			next
		}
		# Prototypes that share a comment (X4MovePos, X4MoveNeg) share its section.
		hold && /^[a-z].*\(.*\);$/ { print "@B " $0; next }
		hold { flush_text(); hold = 0 }
		pending && /^[a-z].*\(.*\);$/ {
			print "@SS " $0
			pending = 0; hold = 1; next
		}
		pending && /^#define/ { print "@SS " $2; flush_text(); pending = 0 }
		pending && /^$/ { flush_text(); pending = 0; next }
		/^#define [A-Za-z0-9_]+ .*\/\*\*</ {
			note = $0; sub(/.*\/\*\*< */, "", note); sub(/ *\*\/.*/, "", note)
			value = $0; sub(/^#define [A-Za-z0-9_]+ +/, "", value); sub(/ *\/\*\*<.*/, "", value)
			print "@TP " $2 " " value ": " note
		}
		' "$h" | while IFS= read -r line; do
			case "$line" in
			"@SS "*) echo ".SS"; printf '%s\n' "${line#@SS }" | esc | sed 's/^/.B /' ;;
			"@TP "*) echo ".TP"; printf '%s\n' "${line#@TP }" | esc ;;
			@BR) echo ".br" ;;
			"@B "*) echo ".br"; printf '%s\n' "${line#@B }" | esc | sed 's/^/.B /' ;;
			*) printf '%s\n' "$line" | esc ;;
			esac
		done
	done
	echo ".SH ENVIRONMENT"
	"$top/scripts/md2man.py" "$top/docs/simulator.md" "Names and settings"
	echo ".SH EXAMPLES"
	echo "The X4Step manual's first example (examples/first.c):"
	block <"$top/examples/first.c"
	"$top/scripts/md2man.py" "$top/examples/README.md" "Build"
	cat <<'EOF'
.SH SEE ALSO
.BR x4ctl (1),
.BR x4step\-machine (5);
the C++ API in
.IR x4step.hpp ,
the kernel interface in
.IR x4step/uapi/linux/x4step.h .
EOF
}

# x4step-machine(5): the machine files' document.
machine_page() {
	cat <<EOF
.TH X4STEP\-MACHINE 5 "" "x4step $1" "File Formats"
.SH NAME
x4step\-machine \- machine files: a machine in real units for x4ctl
EOF
	"$top/scripts/md2man.py" "$top/machines/README.md"
	cat <<'EOF'
.SH SEE ALSO
.BR x4ctl (1),
.BR x4step (3)
EOF
}

# x4grbl(1): its help, then docs/grbl.md.
x4grbl_page() {
	help=$("$1" --help)
	cat <<EOF
.TH X4GRBL 1 "" "x4grbl $2" "User Commands"
.SH NAME
x4grbl \\- a GRBL 1.1 controller for G\\-code senders on an x4step machine
.SH SYNOPSIS
EOF
	printf '%s\n' "$help" | sed -n '1p' | sed 's/^usage: //' | block
	echo ".SH OPTIONS"
	printf '%s\n' "$help" | sed '1,2d' | block
	"$top/scripts/md2man.py" "$top/docs/grbl.md"
	cat <<'EOF'
.SH SEE ALSO
.BR x4ctl (1),
.BR x4step\-machine (5)
EOF
}

case "${1:-}" in
x4ctl) x4ctl_page "$2" "$3" >"$4" ;;
x4grbl) x4grbl_page "$2" "$3" >"$4" ;;
machine) machine_page "$2" >"$3" ;;
header)
	version=$2 out=$3
	shift 3
	header_page "$version" "$@" >"$out"
	;;
*)
	echo "usage: $0 x4ctl X4CTL VERSION OUT | x4grbl X4GRBL VERSION OUT | header VERSION OUT HEADER... | machine VERSION OUT" >&2
	exit 2
	;;
esac
