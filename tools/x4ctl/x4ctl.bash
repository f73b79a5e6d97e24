# SPDX-License-Identifier: GPL-2.0
# bash completion for x4ctl. The commands and options come from x4ctl's own
# help (x4ctl --help, x4ctl help COMMAND), so they never drift from it.
# Installed as share/bash-completion/completions/x4ctl.

# The commands x4ctl --help lists.
_x4ctl_commands() {
	"$1" --help 2>/dev/null | sed -n '/^Commands:/,/^Run /s/^  \([a-z][a-z-]*\)\( .*\)\{0,1\}$/\1/p'
}

_x4ctl() {
	local cur prev cmd i bin=${COMP_WORDS[0]}
	cur=${COMP_WORDS[COMP_CWORD]}
	prev=${COMP_WORDS[COMP_CWORD - 1]}
	COMPREPLY=()
	case $prev in
	-p | --port)
		mapfile -t COMPREPLY < <(compgen -W '1 2 3 4' -- "$cur")
		return
		;;
	-d | --device)
		mapfile -t COMPREPLY < <(compgen -f -- "${cur:-/dev/x4step}")
		return
		;;
	-m | --machine | --svg)
		mapfile -t COMPREPLY < <(compgen -f -- "$cur")
		return
		;;
	esac
	# The command: the first word that is neither an option nor -p/-d's value.
	cmd=
	for ((i = 1; i < COMP_CWORD; i++)); do
		case ${COMP_WORDS[i]} in
		-p | --port | -d | --device) ((i++)) ;;
		-*) ;;
		*)
			cmd=${COMP_WORDS[i]}
			break
			;;
		esac
	done
	if [[ -z $cmd ]]; then
		if [[ $cur == -* ]]; then
			mapfile -t COMPREPLY < <(compgen -W "$("$bin" --help 2>/dev/null | grep -o -- '--[a-z][a-z0-9-]*' | sort -u)" -- "$cur")
		else
			mapfile -t COMPREPLY < <(compgen -W "$(_x4ctl_commands "$bin")" -- "$cur")
		fi
		return
	fi
	if [[ $cur == -* ]]; then
		mapfile -t COMPREPLY < <(compgen -W "$("$bin" help "$cmd" 2>/dev/null | sed -n 's/^ *\(-[a-z], \)\{0,1\}\(--[a-z][a-z0-9-]*\).*/\2/p')" -- "$cur")
		return
	fi
	case $cmd in
	help) mapfile -t COMPREPLY < <(compgen -W "$(_x4ctl_commands "$bin")" -- "$cur") ;;
	mode) mapfile -t COMPREPLY < <(compgen -W 'clock-dir smc-phase smc-hold' -- "$cur") ;;
	run | gcode) mapfile -t COMPREPLY < <(compgen -f -- "$cur") ;;
	machine)
		if [[ ${COMP_WORDS[COMP_CWORD - 1]} == machine ]]; then
			mapfile -t COMPREPLY < <(compgen -W 'check import' -- "$cur")
		else
			mapfile -t COMPREPLY < <(compgen -f -- "$cur")
		fi
		;;
	out) mapfile -t COMPREPLY < <(compgen -W '1 2 on off' -- "$cur") ;;
	jog) mapfile -t COMPREPLY < <(compgen -W '1 2 3 4 + - X+ X- Y+ Y- Z+ Z- A+ A- B+ B- C+ C-' -- "$cur") ;;
	home) mapfile -t COMPREPLY < <(compgen -W '1 2 3 4 X Y Z A B C' -- "$cur") ;;
	touch-off) mapfile -t COMPREPLY < <(compgen -W 'X=0 Y=0 Z=0 A=0 B=0 C=0' -- "$cur") ;;
	esac
}
complete -F _x4ctl x4ctl
