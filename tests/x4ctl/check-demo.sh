#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
# make demo's part program (scripts/demo.sh: machine= and program=) on its
# machine file, on the host: x4ctl gcode --check passes it (soft limits
# included), and on the simulated port in virtual time it runs to its end,
# its steps (the VCD, read by gcode_sim_check) ending at exactly
# round(programmed end x SCALE) and within ARC_TOLERANCE + 1 step of the
# path. So the demo's QEMU run cannot fail on the program itself.
#   check-demo.sh X4CTL SIM_CHECK SOURCE_DIR
set -u
x4ctl=$1 sim_check=$2 top=$3
# shellcheck source=tests/x4ctl/check-lib.sh
. "$(dirname "$0")/check-lib.sh"

# The files the demo runs, as scripts/demo.sh names them.
machine=$(sed -n 's/^machine=\([^ ]*\)$/\1/p' "$top/scripts/demo.sh")
program=$(sed -n 's/^program=\([^ ]*\)$/\1/p' "$top/scripts/demo.sh")
[ -f "$top/$machine" ] && [ -f "$top/$program" ]
check "scripts/demo.sh names its machine ($machine) and program ($program)" $?
machine=$top/$machine program=$top/$program

"$x4ctl" gcode --check --machine "$machine" "$program" >"$dir/out" 2>&1
st=$?
cat "$dir/out"
[ $st -eq 0 ] && grep -q ': OK: [0-9]* lines, [0-9]* segments' "$dir/out"
check "x4ctl gcode --check passes it on its machine" $?

X4STEP_SIM_TIME=virtual X4STEP_SIM_VCD=$dir/run.vcd timeout 60 \
	"$x4ctl" --sim gcode --machine "$machine" "$program" </dev/null >"$dir/out" 2>&1
st=$?
cat "$dir/out"
[ $st -eq 0 ] && grep -q '^gcode: done in [0-9:]*, estimated [0-9:]*, at ' "$dir/out"
check "it runs to its end on the simulated port" $?
"$sim_check" "$machine" "$program" "$dir/run.vcd"
check "its steps: the programmed end exactly, within ARC_TOLERANCE + 1 step of the path" $?
exit $failed
