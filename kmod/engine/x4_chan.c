// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: the channels (x4_chan.h), the lowest level that knows the
 * engine's state. Begin a channel's move, brake it along its ramp or cut
 * it; which axes the running moves hold; whether a move fits the port's
 * timing (its frequency) and write budget; which switches end it; which
 * channel's event is due next. Calls only the plan maths (x4_plan.c): the
 * levels above (x4_switch.c, x4_path.c, x4_phase.c, x4_status.c, then
 * x4_engine.c on top) call these, never the other way, and what a
 * channel's end means the level on top decides.
 */
#include "x4_chan.h"

/*
 * Whether steps at freq_hz fit the port's timing: a fixed pulse plus the
 * minimum space, or half a period each for the symmetric clock.
 */
int x4_chan_freq_check(const struct x4_engine *e, s32 freq_hz)
{
	u64 period = x4_div(X4_NSEC_PER_SEC, (u64)freq_hz);
	const struct x4_timing *t = &e->timing;

	if (e->mode != X4_MODE_CLOCK_DIR)
		return X4_OK; /* phase patterns have no pulse */
	if (t->pulse_ns ? t->pulse_ns + t->space_ns > period :
			  t->space_ns > period / 2)
		return X4_ERR_FREQ_TOO_HIGH;
	return X4_OK;
}

/* The axes an output mode drives, as a mask. */
u8 x4_chan_mode_axes(const struct x4_engine *e)
{
	return x4_chan_phase_mode(e) ? 0x07 : 0x0f;
}

/* The axes of the running moves; an active path owns them all. */
u8 x4_chan_busy_axes(const struct x4_engine *e)
{
	u8 axes = 0;
	int i;

	if (x4_chan_path_active(e))
		return x4_chan_mode_axes(e);
	for (i = 0; i < X4_AXES; i++)
		if (e->busy & (1u << i))
			axes |= e->ch[i].run.axes;
	return axes;
}

/* Port writes of one leader step: clock up and down, or a phase pattern per motor. */
u32 x4_chan_writes_per_step(const struct x4_engine *e, u8 axes)
{
	u32 n = 0;

	if (!x4_chan_phase_mode(e))
		return 2;
	for (; axes; axes &= axes - 1)
		n++;
	return n;
}

/*
 * Port writes per second of plan p at its top speed: the cruise interval
 * (2 c_num / c_den ns) is the shortest of every shape.
 */
u32 x4_chan_plan_rate(const struct x4_engine *e, const struct x4_plan *p)
{
	u64 steps = x4_div(p->c_den * X4_NSEC_PER_SEC + 2 * p->c_num - 1,
			   2 * p->c_num);

	return (u32)(steps * x4_chan_writes_per_step(e, p->axes));
}

/* Whether moves needing `add` more writes per second fit the budget. */
int x4_chan_budget_check(const struct x4_engine *e, u64 add)
{
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (e->busy & (1u << i))
			add += e->ch[i].rate;
	return e->budget && add > e->budget ? X4_ERR_RATE_BUDGET : X4_OK;
}

/* Start counting the axes' steps afresh; their coordinates stay. */
void x4_chan_fold_steps(struct x4_engine *e, u8 axes)
{
	int i;

	for (i = 0; i < X4_AXES; i++) {
		if (!(axes & (1u << i)))
			continue;
		e->pos_base[i] += (u32)e->steps[i];
		e->steps[i] = 0;
	}
}

/* The earliest event of all channels is the next; the outputs of all. */
void x4_chan_schedule_all(struct x4_engine *e)
{
	u64 due = X4_NO_STEP;
	u8 busy = 0, ctl = 0;
	int i;

	for (i = 0; i < X4_AXES; i++) {
		const struct x4_chan *c = &e->ch[i];

		if (c->phase == X4_IDLE)
			continue;
		busy |= 1u << i;
		ctl |= c->ctl;
		if (c->t_pending < due) {
			due = c->t_pending;
			e->cur = &e->ch[i];
		}
	}
	e->busy = busy;
	e->solo = busy && !(busy & (busy - 1));
	e->due = due;
	e->ctl = (u8)((e->ctl & (X4_CTL_SIGNAL1 | X4_CTL_SIGNAL2)) | ctl);
}

/* Begin the move in c->run: directions go out at now_ns. */
void x4_chan_begin(struct x4_engine *e, struct x4_chan *c, u64 now_ns)
{
	int i;

	c->phase = X4_SETUP;
	c->no_steps = false;
	c->path = false;
	c->path_cut = false;
	c->dir_fresh = 0;
	c->probe_mask = 0; /* a path's probing segment arms it after this */
	c->n = 0;
	c->t_cur = 0;
	c->ctl = 0;
	c->t_pending = now_ns;
	c->origin = now_ns + e->timing.dir_setup_ns;
	c->rate = x4_chan_plan_rate(e, &c->run);
	x4_chan_bres_start(c);
	x4_chan_arm_switches(e, c);
	for (i = 0; i < X4_AXES; i++)
		if (c->run.axes & (1u << i))
			e->err[i] = 0; /* a new command to the axis */
	x4_chan_fold_steps(e, c->run.axes);
	x4_chan_schedule_all(e);
}

/*
 * Channel c makes no step from leader step nb (due at t_nb) on but those
 * of a brake along its plan's ramp (ramp), or none at all. The pending
 * event keeps its time, so the glue never has to re-arm its timer: only
 * what happens at that time changes.
 */
static void stop_from(struct x4_chan *c, u64 nb, u64 t_nb, bool ramp)
{
	if (ramp && x4_plan_brake(&c->run, nb, t_nb))
		return;
	/* No ramp to follow: step nb - 1 was the last. */
	if (c->phase == X4_SETUP)
		c->no_steps = true;
	else if (c->phase == X4_RISE)
		c->phase = X4_END; /* at the time step nb was due */
	else
		c->run.last = nb - 1;
}

/* Brake channel c along its ramp (ramp), or end it at its pending event. */
void x4_chan_halt(struct x4_chan *c, bool ramp)
{
	switch (c->phase) {
	case X4_IDLE:
	case X4_END:
		break;
	case X4_SETUP:
		stop_from(c, 0, 0, ramp);
		break;
	case X4_RISE:
		stop_from(c, c->n, c->t_cur, ramp);
		break;
	case X4_FALL:
		if (c->n < c->run.last)
			stop_from(c, c->n + 1, c->t_next, ramp);
		break;
	case X4_QUEUED: /* what comes after this instant's writes */
		c->phase = c->phase_after;
		x4_chan_halt(c, ramp);
		c->phase_after = c->phase;
		c->phase = X4_QUEUED;
		break;
	}
}

/* No further step of channel c: it ends at its pending event. */
void x4_chan_cut(struct x4_chan *c)
{
	c->home = 0;
	c->path_cut = c->path;
	x4_chan_halt(c, false);
}

/*
 * Which switches end the move of channel c: the limits its axes move
 * toward, and in a reference run the REF input. A limit that is active
 * already while the axis backs off the opposite limit on the same input
 * (switches in parallel) is armed once it has been released.
 */
void x4_chan_arm_switches(struct x4_engine *e, struct x4_chan *c)
{
	const struct x4_plan *p = &c->run;
	int i;

	c->halt_mask = 0;
	c->halt_flip = 0;
	c->deferred = 0;
	for (i = 0; i < X4_AXES; i++) {
		u8 bit = x4_chan_limit_bit(e, p, i), back;

		if (!(p->axes & (1u << i)) || !bit)
			continue;
		back = p->sign[i] > 0 ? e->err[i] & X4_AXERR_LIMIT_NEG &&
					x4_chan_input_bit(e->sw.minus[i]) == bit :
					e->err[i] & X4_AXERR_LIMIT_POS &&
					x4_chan_input_bit(e->sw.plus[i]) == bit;
		if (back && (e->inputs & bit))
			c->deferred |= bit;
		else
			c->halt_mask |= bit;
	}
	if (!c->home)
		return;
	c->halt_mask |= c->ref_bit;
	c->deferred &= (u8)~c->ref_bit;
	/* Phase 1 ends when REF is active, phase 2 when it changes. */
	if (c->home == X4_HOME_PHASE2)
		c->halt_flip = e->inputs & c->ref_bit;
}

