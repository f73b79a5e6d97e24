// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: what an axis is doing, for GET_AXES and the library's
 * axes status: coordinate, ProStep4 state and error bits, and its speed
 * from the step interval it runs at. Reads the engine; changes nothing.
 */
#include "x4_chan.h"
#include "x4_status.h"

/* The step interval channel c runs at, between its RISE and FALL events. */
static u64 step_interval(const struct x4_chan *c)
{
	const struct x4_plan *p = &c->run;

	if (c->phase == X4_FALL && c->n < p->last)
		return c->t_next - c->t_cur;
	if (c->phase == X4_FALL || c->n)
		return 2 * c->half_ns;
	/* Before the first step: the interval the move starts with. */
	return p->last ? x4_plan_time(p, 1) - x4_plan_time(p, 0) :
			 2 * p->single_half_ns;
}

void x4_status_axis(const struct x4_engine *e, int axis,
		    struct x4_axis_state *st)
{
	u8 bit = (u8)(1u << axis);
	u64 interval;
	int i;

	st->position = x4_chan_position(e, axis);
	st->error = e->err[axis];
	st->state = (e->sync & bit ? X4_AX_SYNC : 0) |
		    (st->error ? X4_AX_ERROR : 0);
	st->velocity = 0;
	for (i = 0; i < X4_AXES; i++) {
		const struct x4_chan *c = &e->ch[i];
		const struct x4_plan *p = &c->run;

		if (c->phase == X4_IDLE || !(p->axes & bit))
			continue;
		st->state |= X4_AX_RUN;
		if (c->home)
			st->state |= c->home == X4_HOME_PHASE1 ? X4_AX_REF1 :
								 X4_AX_REF2;
		if (c->phase != X4_RISE && c->phase != X4_FALL)
			continue;
		if (c->n >= p->n_decel)
			st->state |= X4_AX_DECEL;
		else if (c->n < p->n_cruise)
			st->state |= X4_AX_ACCEL;
		else
			st->state |= X4_AX_CRUISE;
		interval = step_interval(c);
		if (interval)
			st->velocity = (u32)x4_div(X4_NSEC_PER_SEC *
						   p->abs_steps[axis],
						   interval *
						   p->abs_steps[p->leader]);
	}
}
