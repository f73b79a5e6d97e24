# SPDX-License-Identifier: GPL-2.0
# The engine's sources, written once: kmod/Kbuild includes this file,
# CMakeLists.txt reads it, and tests/check-layers.sh checks that each
# level calls only the levels below it. One level a line, the lowest
# first: the argument checks (which libx4step links alone), the plan
# maths, the channels, the parts that run on them, the engine's commands
# and event machine, and what the glue makes of requests and events.
x4_level0 := x4_check.c
x4_level1 := x4_plan.c
x4_level2 := x4_chan.c
x4_level3 := x4_switch.c x4_path.c x4_phase.c x4_status.c
x4_level4 := x4_engine.c
x4_level5 := x4_req.c x4_track.c
x4_engine_src := $(x4_level0) $(x4_level1) $(x4_level2) $(x4_level3) \
		 $(x4_level4) $(x4_level5)
