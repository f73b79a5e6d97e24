/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: reference and limit switches, and reference runs
 * (x4_switch.c), above the channels (x4_chan.h) and below the commands
 * and the event machine (x4_engine.h).
 */
#ifndef X4_SWITCH_H
#define X4_SWITCH_H

#include "x4_state.h"

int x4_switch_home(struct x4_engine *e, s32 axis, u8 phases, s32 vref1,
		   s32 vref2, u32 sref, u64 now_ns);
int x4_switch_set(struct x4_engine *e, const struct x4_switches *sw);
void x4_switch_sense(struct x4_engine *e, u8 levels);

/* The active switches at input levels (X4GetIn bits): after NO/NC. */
static inline u8 x4_switch_active(const struct x4_engine *e, u8 levels)
{
	return (levels ^ e->sw.nc) & ((1u << X4_INPUTS) - 1);
}

/*
 * For the event machine (x4_engine.c): a step of channel c that switches
 * (hit) forbid; and at the end of a reference run's phase 1, whether
 * phase 2 begins (true) or the run ends.
 */
void x4_switch_halted(struct x4_engine *e, struct x4_chan *c, u8 hit);
bool x4_switch_home_next(struct x4_engine *e, struct x4_chan *c);

#endif /* X4_SWITCH_H */
