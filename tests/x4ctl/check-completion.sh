#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# bash completion of x4ctl (tools/x4ctl/x4ctl.bash): it parses, registers
# itself, and completes commands, options and values from x4ctl's help.
#   check-completion.sh COMPLETION_FILE X4CTL_DIR
set -u
file=$1
PATH=$2:$PATH
failed=0
bash -n "$file" || { echo "FAIL bash -n $file"; exit 1; }
# shellcheck source=/dev/null
source "$file"
[[ $(complete -p x4ctl) == "complete -F _x4ctl x4ctl" ]] || { echo "FAIL complete -p x4ctl: $(complete -p x4ctl)"; failed=1; }

# expect "WORDS..." "REPLIES": completing the last word gives exactly these.
expect() {
	read -r -a COMP_WORDS <<<"$1"
	[[ $1 == *" " ]] && COMP_WORDS+=("")
	COMP_CWORD=$((${#COMP_WORDS[@]} - 1))
	_x4ctl
	local got="${COMPREPLY[*]}"
	if [[ $got == "$2" ]]; then echo "PASS '$1' -> $got"; else echo "FAIL '$1' -> '$got', want '$2'"; failed=1; fi
}
expect "x4ctl st" "stop status"
expect "x4ctl li" "list limits"
expect "x4ctl -p 2 status --j" "--json"
expect "x4ctl -p " "1 2 3 4"
expect "x4ctl mode smc" "smc-phase smc-hold"
expect "x4ctl machine " "check import"
expect "x4ctl machine i" "import"
expect "x4ctl help wa" "watch"
expect "x4ctl halt --st" "--stop"
expect "x4ctl halt --s" "--stop --sim"
expect "x4ctl list -" "--json --sim --help"
expect "x4ctl --ver" "--version"
# The operator's commands in machine units (issue 20).
expect "x4ctl pa" "path panel"
expect "x4ctl help pa" "path panel"
expect "x4ctl jog X" "X+ X-"
expect "x4ctl jog --d" "--distance --device"
expect "x4ctl jog --fe" "--feed"
expect "x4ctl home --m" "--machine"
expect "x4ctl home --machine /dev/nul" "/dev/null"
expect "x4ctl home -m /dev/null Z" "Z"
expect "x4ctl panel --" "--machine --feed --port --device --sim --help"
# touch-off (issue 30): a command with a hyphen, and its operands.
expect "x4ctl tou" "touch-off"
expect "x4ctl touch-off -m /dev/null Z" "Z=0"
exit "$failed"
