# SPDX-License-Identifier: GPL-2.0
# The steps in a VCD of x4step's simulated port (X4STEP_SIM_VCD), from the
# pins: one line per motor 1..4: "MOTOR NET_STEPS FIRST_NS LAST_NS" (the
# times of its first and last rising clock edge, "-" if it made none). A
# step goes up while the motor's direction pin is HIGH.
#   awk -f vcd-steps.awk run.vcd
$1 == "$var" && $5 ~ /_(clk|dir)[1-4]$/ { id[$4] = substr($5, length($5) - 3) }
/^#/ { t = substr($0, 2) }
/^[01x]/ {
	k = substr($0, 2)
	if (!(k in id)) next
	v = substr($0, 1, 1)
	m = substr(id[k], 4)
	if (id[k] ~ /^dir/) {
		dir[m] = v
	} else {
		if (v == "1" && level[m] == "0") {
			pos[m] += dir[m] == "1" ? 1 : -1
			if (!(m in first)) first[m] = t
			last[m] = t
		}
		level[m] = v
	}
}
END {
	for (m = 1; m <= 4; m++)
		printf "%d %d %s %s\n", m, pos[m], (m in first) ? first[m] : "-", (m in last) ? last[m] : "-"
}
