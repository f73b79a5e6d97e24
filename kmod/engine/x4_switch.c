// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: reference and limit switches, and reference runs
 * (ProStep4). Which inputs end a channel's move, what a hit does to the
 * axes (errors, sync, ambiguity on shared inputs), and the two phases of
 * a reference run. Calls the channels (x4_chan.c) to start and cut moves;
 * the engine's event machine (x4_engine.c) calls x4_switch_halted() at a step a
 * switch forbids and x4_switch_home_next() at a run's end, and acts on what the
 * latter returns.
 */
#include "x4_chan.h"
#include "x4_switch.h"

/* The limit input that axis i of running channel c watches, or 0. */
static u8 watched_limit(const struct x4_engine *e, const struct x4_chan *c,
			int i)
{
	if (c->phase == X4_IDLE || !(c->run.axes & (1u << i)))
		return 0;
	return x4_chan_limit_bit(e, &c->run, i) & c->halt_mask;
}

/*
 * A limit switch is active: every running move toward it ends before its
 * next step, on this very tick. The hit goes to each axis that was moving
 * toward that input; ambiguous when there were several.
 */
static noinline void limits_hit(struct x4_engine *e, u8 hit)
{
	u8 watchers[X4_INPUTS] = { 0 };
	struct x4_chan *c;
	u8 bit;
	int i;

	for (c = e->ch; c < e->ch + X4_AXES; c++) {
		for (i = 0; i < X4_AXES; i++) {
			bit = watched_limit(e, c, i);
			if (bit)
				watchers[__builtin_ctz(bit)]++;
		}
	}
	for (c = e->ch; c < e->ch + X4_AXES; c++) {
		for (i = 0; i < X4_AXES; i++) {
			bit = watched_limit(e, c, i) & hit;
			if (!bit)
				continue;
			e->err[i] |= c->run.sign[i] > 0 ? X4_AXERR_LIMIT_POS :
							  X4_AXERR_LIMIT_NEG;
			if (watchers[__builtin_ctz(bit)] > 1)
				e->err[i] |= X4_AXERR_AMBIGUOUS;
			/* The partners stop too, without a ramp. */
			e->sync &= (u8)~c->run.axes;
			x4_chan_cut(c);
		}
	}
}

/* Start reference run phase `phase` of the axis of channel c. */
static void home_phase(struct x4_engine *e, struct x4_chan *c, int axis,
		       u8 phase, s32 vref, u64 now_ns)
{
	const struct x4_profile *ax = &e->prof[axis];
	s64 steps[X4_AXES] = { 0 };
	u32 v = x4_abs_s32(vref);

	steps[axis] = vref < 0 ? -(s64)c->sref : (s64)c->sref;
	x4_plan_axes(&c->run, steps);
	/* Phase 1 may brake past REF; phase 2 stops where REF changes. */
	if (phase == X4_HOME_PHASE1 && c->home_brake)
		x4_plan_search(&c->run, v, ax->ae, ax->ve < v ? ax->ve : v);
	else
		x4_plan_search(&c->run, v, 0, v);
	c->home = phase;
	c->ref_found = false;
	x4_chan_begin(e, c, now_ns);
	/* The budget holds the faster phase for the whole reference run. */
	if (c->rate < c->home_rate)
		c->rate = c->home_rate;
}

/* Switches that channel c watches (hit) are active at its step tick. */
void x4_switch_halted(struct x4_engine *e, struct x4_chan *c, u8 hit)
{
	int axis = c->run.leader;

	if (!(hit & c->ref_bit) || !c->home) {
		limits_hit(e, hit & (u8)~(c->home ? c->ref_bit : 0));
		return;
	}
	if (c->home == X4_HOME_PHASE1) {
		/*
		 * Stop before this step, or brake past REF with it first;
		 * x4_switch_home_next() follows when the axis stands.
		 */
		c->ref_found = true;
		c->halt_mask &= (u8)~c->ref_bit;
		x4_chan_halt(c, true);
		return;
	}
	/* Phase 2: REF changed at this step: the coordinate's zero. */
	e->steps[axis] = 0;
	e->pos_base[axis] = 0;
	e->sync |= (u8)(1u << axis);
	x4_chan_cut(c);
}

/*
 * Channel c's move ended: phase 2 follows phase 1 that found REF, from
 * rest. A brake that ran off the switch (REF no longer active: a cam
 * shorter than the brake) ends the run: phase 2 would find the far edge.
 */
bool x4_switch_home_next(struct x4_engine *e, struct x4_chan *c)
{
	int axis = c->run.leader;

	if (c->home != X4_HOME_PHASE1 || !c->ref_found)
		return false;
	if (c->home_brake && !(e->inputs & c->ref_bit)) {
		e->err[axis] |= X4_AXERR_REF_PASSED;
		return false;
	}
	if (!c->home_next)
		return false;
	home_phase(e, c, axis, X4_HOME_PHASE2, c->vref2,
		   c->t_pending + X4_HOME_SETTLE_NS);
	c->ctl = X4_CTL_AKTIV; /* the run goes on through the pause */
	return true;
}

int x4_switch_home(struct x4_engine *e, s32 axis, u8 phases, s32 vref1,
		   s32 vref2, u32 sref, u64 now_ns)
{
	const struct x4_profile *ax;
	struct x4_chan *c;
	u32 vmax, rate;
	int ret;

	if (axis < 1 || axis > X4_AXES ||
	    !(x4_chan_mode_axes(e) & (1u << (axis - 1))) ||
	    x4_home_check(phases, vref1, vref2, sref) || !e->sw.ref[axis - 1])
		return X4_ERR_PARAM_FAIL;
	/* Phase 1's brake must fit the ramp limits (at most an hour). */
	ax = &e->prof[axis - 1];
	if (phases & X4_HOME_BRAKE && phases & X4_HOME_PHASE1 &&
	    x4_ramp_too_long(x4_abs_s32(vref1), ax->ae))
		return X4_ERR_PARAM_FAIL;
	ret = x4_chan_freq_check(e, phases & X4_HOME_PHASE1 ?
				 x4_abs_s32(vref1) : 1);
	if (!ret)
		ret = x4_chan_freq_check(e, phases & X4_HOME_PHASE2 ?
					 x4_abs_s32(vref2) : 1);
	if (ret)
		return ret;
	if (x4_chan_busy_axes(e) & (1u << (axis - 1)))
		return X4_ERR_IS_ACTIVE;
	vmax = phases & X4_HOME_PHASE1 ? x4_abs_s32(vref1) : 0;
	if (phases & X4_HOME_PHASE2 && x4_abs_s32(vref2) > vmax)
		vmax = x4_abs_s32(vref2);
	rate = vmax * x4_chan_writes_per_step(e, 1);
	if (x4_chan_budget_check(e, rate))
		return X4_ERR_RATE_BUDGET;
	c = &e->ch[axis - 1];
	c->home_rate = rate;
	c->sref = sref;
	c->vref2 = vref2;
	c->ref_bit = x4_chan_input_bit(e->sw.ref[axis - 1]);
	c->home_next = (phases & X4_HOME_AUTO) == X4_HOME_AUTO;
	c->home_brake = phases & X4_HOME_BRAKE;
	e->sync &= (u8)~(1u << (axis - 1));
	if (phases & X4_HOME_PHASE1)
		home_phase(e, c, axis - 1, X4_HOME_PHASE1, vref1, now_ns);
	else
		home_phase(e, c, axis - 1, X4_HOME_PHASE2, vref2, now_ns);
	return X4_OK;
}

int x4_switch_set(struct x4_engine *e, const struct x4_switches *sw)
{
	int i;

	if (sw->nc >= 1u << X4_INPUTS)
		return X4_ERR_PARAM_FAIL;
	for (i = 0; i < X4_AXES; i++)
		if (sw->ref[i] > X4_INPUTS || sw->plus[i] > X4_INPUTS ||
		    sw->minus[i] > X4_INPUTS)
			return X4_ERR_PARAM_FAIL;
	if (e->busy)
		return X4_ERR_IS_ACTIVE;
	e->sw = *sw;
	return X4_OK;
}

/*
 * The input pin levels (X4GetIn bits, 1 = HIGH), sampled by the glue on
 * every tick while a move watches switches, and before a move starts.
 */
void x4_switch_sense(struct x4_engine *e, u8 levels)
{
	int i;

	e->levels = levels;
	e->inputs = x4_switch_active(e, levels);
	for (i = 0; i < X4_AXES; i++) {
		struct x4_chan *c = &e->ch[i];
		u8 released = c->deferred & (u8)~e->inputs;

		c->halt_mask |= released; /* backed off: armed again */
		c->deferred &= (u8)~released;
	}
}
