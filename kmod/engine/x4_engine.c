// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: the top level, the engine's API (x4_engine.h). The
 * commands that start, brake and stop moves; the event state machine that
 * turns a running plan into clock, direction and control edges (SETUP,
 * RISE, FALL, END); Bresenham for the minor axes; and the rule that a late
 * event moves the rest of its channel's schedule instead of shortening a
 * pulse or space. Calls the levels below: the channels (x4_chan.c), the
 * switches (x4_switch.c) at a step a switch forbids, the phase output
 * (x4_phase.c) in SMC mode, the path (x4_path.c) at a piece's end. They
 * never call it: what they report back (a path that goes on, a reference
 * run's phase 2) they return, and this level acts on it.
 */
#include "x4_chan.h"
#include "x4_engine.h"

#ifdef __KERNEL__
#include <linux/string.h>
#else
#include <string.h>
/* noinline: defined by the build (CMakeLists.txt), as the kernel does */
#endif

void x4_engine_init(struct x4_engine *e)
{
	static const struct x4_profile prof = { 0, 0, 1000, 1000, 1000 };
	int i;

	memset(e, 0, sizeof(*e));
	e->cur = e->ch;
	e->timing.dir_setup_ns = X4_DIR_SETUP_NS;
	e->budget = X4_WRITE_BUDGET;
	e->path.override = 100;
	for (i = 0; i < X4_AXES; i++)
		e->prof[i] = prof;
}

int x4_engine_configure(struct x4_engine *e, const struct x4_timing *t,
			u8 mode)
{
	if (x4_timing_check(t, mode))
		return X4_ERR_PARAM_FAIL;
	if (x4_engine_busy(e) || x4_path_active(e))
		return X4_ERR_IS_ACTIVE;
	e->timing = *t;
	e->mode = mode;
	return X4_OK;
}

u8 x4_engine_chan_axes(const struct x4_engine *e, int i)
{
	return e->ch[i].path ? x4_chan_mode_axes(e) : e->ch[i].run.axes;
}

/* After an event of channel e->cur: the common case is that it runs alone. */
static inline void schedule(struct x4_engine *e, const struct x4_chan *c)
{
	if (e->solo && c->phase != X4_IDLE) {
		e->due = c->t_pending;
		e->ctl = (u8)((e->ctl & (X4_CTL_SIGNAL1 | X4_CTL_SIGNAL2)) |
			      c->ctl);
		return;
	}
	x4_chan_schedule_all(e);
}

/* Channel i runs the moves whose lowest axis is i. */
static struct x4_chan *chan_of(struct x4_engine *e, u8 axes)
{
	return &e->ch[__builtin_ctz(axes)];
}

int x4_engine_load(struct x4_engine *e, const struct x4_move *m)
{
	int ret = x4_move_check(m);
	s64 steps[X4_AXES];
	int i;

	if (!ret)
		ret = x4_chan_freq_check(e, m->freq_hz);
	if (!ret && x4_chan_phase_mode(e) && m->steps[3])
		ret = X4_ERR_PARAM_FAIL; /* the SMC boards drive 3 motors */
	if (ret)
		return ret;
	if (e->loaded)
		return X4_ERR_IS_LOADED;
	for (i = 0; i < X4_AXES; i++)
		steps[i] = m->steps[i];
	x4_plan_axes(&e->next, steps);
	x4_plan_x4step(&e->next, e->next.abs_steps[e->next.leader],
		     (u32)m->freq_hz, (u32)m->ramp_ms);
	e->loaded = true;
	return X4_OK;
}

int x4_engine_start(struct x4_engine *e, u64 now_ns)
{
	struct x4_chan *c;

	if (!e->loaded)
		return X4_ERR_NOT_LOADED;
	if (x4_chan_busy_axes(e) & e->next.axes)
		return X4_ERR_IS_ACTIVE;
	if (x4_chan_budget_check(e, x4_chan_plan_rate(e, &e->next)))
		return X4_ERR_RATE_BUDGET;
	c = chan_of(e, e->next.axes);
	c->run = e->next;
	c->home = 0;
	e->loaded = false;
	x4_chan_fold_steps(e, 0x0f); /* X4Start clears every step counter */
	x4_chan_begin(e, c, now_ns);
	return X4_OK;
}

int x4_engine_endless(struct x4_engine *e, s32 axis, bool negative,
		      s32 freq_hz, s32 ramp_ms, u64 now_ns)
{
	s64 steps[X4_AXES] = { 0 };
	struct x4_chan *c;
	int ret;

	if (axis < 1 || axis > X4_AXES ||
	    !(x4_chan_mode_axes(e) & (1u << (axis - 1))))
		return X4_ERR_PARAM_FAIL;
	ret = x4_ramp_check(freq_hz, ramp_ms);
	if (!ret)
		ret = x4_chan_freq_check(e, freq_hz);
	if (ret)
		return ret;
	if (e->loaded)
		return X4_ERR_IS_LOADED;
	if (x4_chan_busy_axes(e) & (1u << (axis - 1)))
		return X4_ERR_IS_ACTIVE;
	if (x4_chan_budget_check(e,
				 (u64)freq_hz * x4_chan_writes_per_step(e, 1)))
		return X4_ERR_RATE_BUDGET;
	c = &e->ch[axis - 1];
	steps[axis - 1] = negative ? -1 : 1;
	x4_plan_axes(&c->run, steps);
	x4_plan_x4step(&c->run, 0, (u32)freq_hz, (u32)ramp_ms);
	c->home = 0;
	x4_chan_fold_steps(e, 0x0f);
	x4_chan_begin(e, c, now_ns);
	return X4_OK;
}

int x4_engine_set_profile(struct x4_engine *e, s32 axis,
			  const struct x4_profile *p)
{
	if (axis < 1 || axis > X4_AXES || x4_profile_check(p))
		return X4_ERR_PARAM_FAIL;
	e->prof[axis - 1] = *p; /* for the axis' next move */
	return X4_OK;
}

int x4_engine_plan_goto(const struct x4_engine *e, u8 axes,
			const s32 *target, bool relative, struct x4_goto *g)
{
	s64 steps[X4_AXES];
	int i, ret;

	if (!axes || axes & ~x4_chan_mode_axes(e))
		return X4_ERR_PARAM_FAIL;
	g->axes = axes;
	g->moving = 0;
	g->rate = 0;
	for (i = 0; i < X4_AXES; i++) {
		if (!(axes & (1u << i)))
			continue;
		ret = x4_chan_freq_check(e, (s32)e->prof[i].vm);
		if (ret)
			return ret;
	}
	if (x4_chan_busy_axes(e) & axes)
		return X4_ERR_IS_ACTIVE;
	for (i = 0; i < X4_AXES; i++) {
		g->from[i] = x4_chan_position(e, i);
		steps[i] = relative ? (s64)target[i] :
				      (s64)target[i] - g->from[i];
		if (!(axes & (1u << i)) || !steps[i])
			continue; /* not commanded, or there already */
		g->moving |= 1u << i;
		/* A profile move's top speed is at most vm. */
		g->rate += (u64)e->prof[i].vm * x4_chan_writes_per_step(e, 1);
	}
	if (x4_chan_budget_check(e, g->rate))
		return X4_ERR_RATE_BUDGET;
	for (i = 0; i < X4_AXES; i++) {
		s64 one[X4_AXES] = { 0 };

		if (!(g->moving & (1u << i)))
			continue;
		one[i] = steps[i];
		x4_plan_axes(&g->plan[i], one);
		x4_plan_profile(&g->plan[i], g->plan[i].abs_steps[i], &e->prof[i]);
	}
	return X4_OK;
}

int x4_engine_start_goto(struct x4_engine *e, const struct x4_goto *g,
			 u64 now_ns)
{
	int i;

	if (x4_chan_busy_axes(e) & g->axes)
		return X4_ERR_IS_ACTIVE;
	if (x4_chan_budget_check(e, g->rate))
		return X4_ERR_RATE_BUDGET;
	for (i = 0; i < X4_AXES; i++)
		if (g->axes & (1u << i) && x4_chan_position(e, i) != g->from[i])
			return X4_ERR_PARAM_FAIL; /* planned from elsewhere */
	for (i = 0; i < X4_AXES; i++) {
		struct x4_chan *c = &e->ch[i];

		if (!(g->axes & (1u << i)))
			continue;
		if (!(g->moving & (1u << i))) {
			e->err[i] = 0;
			continue;
		}
		c->run = g->plan[i];
		c->home = 0;
		x4_chan_begin(e, c, now_ns);
	}
	return X4_OK;
}

#ifndef __KERNEL__ /* the module plans on a copy: x4step_motion_goto() */
int x4_engine_goto(struct x4_engine *e, u8 axes, const s32 *target,
		   bool relative, u64 now_ns)
{
	struct x4_goto g;
	int ret = x4_engine_plan_goto(e, axes, target, relative, &g);

	return ret ? ret : x4_engine_start_goto(e, &g, now_ns);
}
#endif

void x4_engine_set_signal(struct x4_engine *e, u8 signal_bit, bool high)
{
	if (high)
		e->ctl |= signal_bit;
	else
		e->ctl &= (u8)~signal_bit;
}

/*
 * Rounded Bresenham for axis i: never more than 1/2 step off the line.
 * The leader and the axes that do not move add 0 and never step.
 */
static inline u8 minor_step(struct x4_engine *e, struct x4_chan *c, int i)
{
	const struct x4_plan *p = &c->run;

	c->bres[i] += p->bres_inc[i];
	if (c->bres[i] < p->bres_2l)
		return 0;
	c->bres[i] -= p->bres_2l;
	e->steps[i] += p->sign[i];
	return X4_CLK_BIT(i);
}

/* Clock bits of leader step n: the leader and the minors due now. */
static u8 step_axes(struct x4_engine *e, struct x4_chan *c)
{
	const struct x4_plan *p = &c->run;

	e->steps[p->leader] += p->sign[p->leader];
	/* Unrolled: this runs at every step. */
	_Static_assert(X4_AXES == 4, "four minor_step() calls");
	return X4_CLK_BIT(p->leader) | minor_step(e, c, 0) |
	       minor_step(e, c, 1) | minor_step(e, c, 2) | minor_step(e, c, 3);
}

/*
 * The SETUP event: the directions (phase mode: the patterns) go out, the
 * first step (n, at T(n): a path's piece begins before its step 1) follows
 * after the setup time. At a path's junction the path does not wait as a
 * whole: only an axis whose direction changed does, at its own next step
 * (dir_wait()).
 */
static noinline void begin_setup(struct x4_engine *e, struct x4_chan *c,
				 u64 now_ns)
{
	const struct x4_plan *p = &c->run;

	c->ctl = p->n_cruise ? X4_CTL_AKTIV | X4_CTL_BOOST : X4_CTL_AKTIV;
	if (c->dir_fresh) { /* a path's junction: it goes on (dir_wait()) */
		c->dir_ready = now_ns + e->timing.dir_setup_ns;
	} else if (now_ns > c->t_pending) {
		/*
		 * A start from rest (a move, a path, a resume): count the
		 * setup time from when the directions go out, not from the
		 * request, which a late timer or the path's planning delayed.
		 */
		c->origin = now_ns + e->timing.dir_setup_ns;
	}
	c->phase = c->no_steps ? X4_END : X4_RISE;
	c->t_pending = c->origin + c->t_cur;
	if (x4_chan_phase_mode(e))
		x4_phase_move(e, c, now_ns);
	else /* axes that do not move keep their direction level */
		e->data = (u8)((e->data & ~x4_chan_dir_bits(p->axes)) |
				p->dirs);
}

/* Channel c's move has ended (a reference run may go on to phase 2). */
static void end_move(struct x4_engine *e, struct x4_chan *c)
{
	bool path_goes_on = false;

	if (c->home && x4_switch_home_next(e, c))
		return;
	if (c->path)
		path_goes_on = x4_path_ended(e, c);
	c->dir_fresh = 0;
	c->home = 0;
	c->ctl = 0;
	c->phase = X4_IDLE;
	c->halt_mask = 0;
	c->deferred = 0;
	e->ends++;
	if (path_goes_on) { /* segments came while it ended */
		/* The motors stay on, as through any junction. */
		x4_path_kick(e, c->t_pending);
		return;
	}
	if (x4_chan_phase_mode(e))
		x4_phase_rest(e, c);
}

/*
 * Channel c's next step is due before `earliest`, the first instant that
 * keeps its low time (or phase step) at the minimum: the event before was
 * late. Move the rest of its schedule, rather than catch up with a burst
 * of short pulses that a driver would lose.
 */
static bool keep_min(struct x4_engine *e, struct x4_chan *c, u64 earliest)
{
	u64 d;

	if (c->phase != X4_RISE || c->t_pending >= earliest)
		return false;
	d = earliest - c->t_pending;
	c->origin += d;
	c->t_pending += d;
	if (!e->edge_shifted)
		e->shifts++; /* an edge counts once (x4_engine_written) */
	e->edge_shifted = true;
	e->shifted_ns += d;
	return true;
}

/* Step n + 1 rises next. */
static inline void next_step(struct x4_chan *c)
{
	c->n++;
	c->t_cur = c->t_next;
	c->phase = X4_RISE;
	c->t_pending = c->origin + c->t_cur;
}

/*
 * After the last step of a path's piece, at t: the next piece's step 1.
 * Where directions change, they go out after the hold time (a SETUP).
 */
static void path_goes_on(struct x4_engine *e, struct x4_chan *c, u64 t)
{
	next_step(c);
	if (c->dir_fresh) {
		c->phase = X4_SETUP;
		c->t_pending = t + e->timing.dir_hold_ns;
	} else if (!x4_chan_phase_mode(e)) {
		keep_min(e, c, t + c->space_min);
	}
}

/* After the last step: end now, or after the hold (and settle) time. */
static noinline void last_step_done(struct x4_engine *e, struct x4_chan *c,
				    u64 t)
{
	if (c->path && x4_path_next(e, c)) {
		path_goes_on(e, c, t);
		return;
	}
	if (!e->timing.dir_hold_ns && !x4_chan_phase_mode(e)) {
		end_move(e, c);
		return;
	}
	/* Phase mode: give the motor its last step period to settle. */
	c->phase = X4_END;
	c->t_pending = t + e->timing.dir_hold_ns +
		       (x4_chan_phase_mode(e) ? 2 * c->half_ns : 0);
}

/* After step n's clock fell (or its pattern went out): what comes next. */
static inline void step_done(struct x4_engine *e, struct x4_chan *c, u64 t)
{
	if (c->n >= c->run.last)
		last_step_done(e, c, t);
	else
		next_step(c);
}

/*
 * The shortest a time planned `planned` ns long may become when its start
 * was late: `min`, or half the plan where the plan is shorter than that (a
 * move faster than the X4Step clock: timer jitter must not shift it all).
 */
static u64 min_of(u64 planned, u64 min)
{
	return planned >= min ? min : planned / 2;
}

/*
 * The fall of the step that rose at now_ns (planned at t_step), and the
 * shortest low time after it, `interval` after t_step the next step's
 * rise. Minimums count from the real edges: a configured pulse or space
 * as configured; otherwise min_of() the plan and X4_CLOCK_MIN_NS (or the
 * configured pulse, for the space).
 */
static inline void rise_times(struct x4_engine *e, struct x4_chan *c,
			      u64 t_step, u64 now_ns, u64 interval)
{
	const struct x4_timing *t = &e->timing;
	u64 high = c->half_ns; /* at most half the interval */

	if (!(t->pulse_ns | t->space_ns)) {
		/* The common case, at every step: no configured times. */
		c->high_min = min_of(high, X4_CLOCK_MIN_NS);
		c->space_min = min_of(interval - high, X4_CLOCK_MIN_NS);
	} else {
		if (t->pulse_ns)
			high = t->pulse_ns;
		c->high_min = t->pulse_ns ? high :
			min_of(high, X4_CLOCK_MIN_NS);
		c->space_min = t->space_ns ? t->space_ns :
			min_of(interval > high ? interval - high : 0,
			       t->pulse_ns ? t->pulse_ns : X4_CLOCK_MIN_NS);
	}
	c->t_pending = t_step + high;
	if (c->t_pending < now_ns + c->high_min)
		c->t_pending = now_ns + c->high_min;
}

/*
 * A path's axis whose direction changed would step before its setup time
 * has passed: the step, and the rest of the schedule, wait. Only such an
 * axis' step waits: at a reversal within a circle the minor axis is slow
 * and its next step usually comes later anyway.
 */
static noinline bool dir_wait(struct x4_chan *c, u64 t_step, u64 now_ns)
{
	const struct x4_plan *p = &c->run;
	u8 due = X4_CLK_BIT(p->leader);
	int i;

	if ((now_ns > t_step ? now_ns : t_step) >= c->dir_ready) {
		c->dir_fresh = 0;
		return false;
	}
	for (i = 0; i < X4_AXES; i++)
		if (p->bres_inc[i] && c->bres[i] + p->bres_inc[i] >= p->bres_2l)
			due |= X4_CLK_BIT(i);
	if (!(due & c->dir_fresh))
		return false;
	c->origin += c->dir_ready - t_step;
	c->t_pending = c->dir_ready;
	return true;
}

static void rise(struct x4_engine *e, struct x4_chan *c, u64 now_ns)
{
	const struct x4_plan *p = &c->run;
	u64 t_step = c->origin + c->t_cur;
	u8 hit = (e->inputs ^ c->halt_flip) & c->halt_mask;
	u64 interval;
	bool ramp;

	if (hit) {
		x4_switch_halted(e, c, hit);
		return;
	}
	if (c->home && !c->ref_found && c->n >= c->sref) {
		/*
		 * Step sref + 1 of a reference phase: sref travelled
		 * without finding the switch.
		 */
		e->err[p->leader] |= X4_AXERR_REF_TRAVEL;
		x4_chan_cut(c);
		return;
	}
	/* A probing segment's input (e->levels: sampled for this tick). */
	if ((e->levels ^ c->probe_flip) & c->probe_mask &&
	    x4_path_probe_hit(e, c))
		return;
	if (c->dir_fresh && dir_wait(c, t_step, now_ns))
		return;
	c->stepping = step_axes(e, c);
	if (c->n < p->last) {
		c->t_next = x4_plan_next(&c->run, c->n + 1, c->t_cur, &ramp);
		c->ctl = ramp ? X4_CTL_AKTIV | X4_CTL_BOOST : X4_CTL_AKTIV;
		interval = c->t_next - c->t_cur;
		c->half_ns = interval / 2;
	} else {
		if (!c->n)
			c->half_ns = p->single_half_ns;
		else if (c->path) /* the next piece begins at its end speed */
			c->half_ns = x4_path_end_half(e, c->half_ns);
		/* (A move's last step keeps the step time of the one before.) */
		interval = 2 * c->half_ns;
	}

	if (now_ns < t_step)
		now_ns = t_step;
	e->fired = c;
	e->edge_shifted = false;
	if (x4_chan_phase_mode(e)) {
		x4_phase_walk(e, c);
		step_done(e, c, now_ns);
		c->space_min = min_of(2 * c->half_ns, 2 * X4_CLOCK_MIN_NS);
		keep_min(e, c, now_ns + c->space_min);
		x4_phase_step(e, c, t_step);
		return;
	}
	e->data |= c->stepping;
	c->phase = X4_FALL;
	rise_times(e, c, t_step, now_ns, interval);
}

/* Step n's clock falls and step n + 1 follows (the hot path, with rise()). */
static inline void fall(struct x4_engine *e, struct x4_chan *c, u64 now_ns)
{
	e->data &= (u8)~c->stepping;
	next_step(c);
	e->fired = c;
	e->edge_shifted = false;
	keep_min(e, c, now_ns + c->space_min);
}

/* Step n's clock rises (the hot path's other half, with fall()). */
static noinline void rise_event(struct x4_engine *e, struct x4_chan *c,
				u64 now_ns)
{
	rise(e, c, now_ns);
	schedule(e, c);
}

/*
 * The events that are not a step's (x4_engine_fire() has those), and what
 * runs next.
 */
static noinline void fire_event(struct x4_engine *e, struct x4_chan *c,
				u64 now_ns)
{
	switch (c->phase) {
	case X4_RISE: /* x4_engine_fire()'s */
		break;
	case X4_FALL: /* of the last step: the hold counts from the real edge */
		e->data &= (u8)~c->stepping;
		last_step_done(e, c, now_ns > c->t_pending ? now_ns : c->t_pending);
		break;
	case X4_SETUP:
		begin_setup(e, c, now_ns);
		break;
	case X4_END:
		end_move(e, c);
		break;
	case X4_QUEUED:
		x4_phase_queued(e, c);
		break;
	case X4_IDLE:
		break;
	}
	schedule(e, c);
}

/*
 * Apply the pending event (due at x4_engine_due(), fired at now_ns) and
 * plan the next.
 */
void x4_engine_fire(struct x4_engine *e, u64 now_ns)
{
	struct x4_chan *c = e->cur;

	if (c->phase == X4_RISE) {
		rise_event(e, c, now_ns);
		return;
	}
	if (c->phase != X4_FALL || c->n >= c->run.last) {
		fire_event(e, c, now_ns);
		return;
	}
	fall(e, c, now_ns);
	/* A lone move's next step: its ramp state (ctl) is unchanged. */
	if (e->solo)
		e->due = c->t_pending;
	else
		x4_chan_schedule_all(e);
}

/*
 * The step edge just fired reached the port at t_ns, a little after the
 * time x4_engine_fire() was given: its pulse or space counts from here.
 */
void x4_engine_written(struct x4_engine *e, u64 t_ns)
{
	struct x4_chan *c = e->fired;

	if (!c)
		return;
	e->fired = NULL;
	if (c->phase == X4_FALL && c->t_pending < t_ns + c->high_min)
		c->t_pending = t_ns + c->high_min;
	else if (!keep_min(e, c, t_ns + c->space_min))
		return;
	schedule(e, c);
}

/*
 * How late the pending event may fire before the rest of its channel's
 * schedule moves (keep_min()): a step's clock edge whose pulse or space
 * is at its minimum has none, and a late timer then makes the whole move
 * slower. The glue arms its timer early for such an edge and waits out
 * the rest (x4step_port.c). A rise's slack spans its step: its pulse
 * and the space after it, as the step before them had them; a fall's,
 * the space before the next step's rise. Other events move nothing that
 * follows: X4_NO_STEP.
 */
u64 x4_engine_slack(const struct x4_engine *e)
{
	const struct x4_chan *c = e->cur;
	u64 next, need;

	if (x4_chan_phase_mode(e) || !c->n)
		return X4_NO_STEP; /* no pulse; the first step has no before */
	if (c->phase == X4_RISE) {
		next = 2 * c->half_ns;
		need = c->high_min + c->space_min;
	} else if (c->phase == X4_FALL) {
		next = c->origin + c->t_cur + 2 * c->half_ns;
		if (c->n < c->run.last)
			next = c->origin + c->t_next;
		need = c->t_pending + c->space_min;
	} else {
		return X4_NO_STEP;
	}
	return next > need ? next - need : 0;
}

/*
 * Emergency stop of channel c: no further step, its clocks drop now, its
 * axes lose their synchronization. The caller writes the port, then fires
 * what x4_engine_busy() still has.
 */
static void stop_chan(struct x4_engine *e, struct x4_chan *c)
{
	e->data &= (u8)~(c->run.axes ? x4_chan_clk_bits(c->run.axes) : 0);
	e->sync &= (u8)~c->run.axes;
	c->home = 0;
	c->path_cut = c->path;
	c->t_pending = 0;
	end_move(e, c); /* phase mode: the rest patterns are queued, due at once */
}

/* Brake (or stop) the moves of the axes in `axes`. */
int x4_engine_halt(struct x4_engine *e, u8 axes, bool stop)
{
	int ret = X4_ERR_NOT_ACTIVE;
	int i;

	/*
	 * A path at rest (held, or queued): a stop flushes it; a brake holds
	 * a queued one that has not started yet.
	 */
	if ((stop || e->path.state == X4_PATH_IDLE) && !e->ch[0].path &&
	    x4_path_active(e) && axes & x4_chan_mode_axes(e))
		ret = x4_path_hold(e, stop);
	for (i = 0; i < X4_AXES; i++) {
		struct x4_chan *c = &e->ch[i];

		if (c->phase == X4_IDLE || !(x4_engine_chan_axes(e, i) & axes))
			continue;
		ret = X4_OK;
		/*
		 * A reference run in its pause before phase 2 (or before its
		 * first step) has no ramp to brake along: it ends at once,
		 * rather than at its start 50 ms ahead.
		 */
		if (stop || (c->phase == X4_SETUP && c->home)) {
			stop_chan(e, c);
		} else if (c->path) {
			x4_path_hold(e, false); /* along the path */
		} else {
			c->home = 0;
			x4_chan_halt(c, true);
		}
	}
	x4_chan_schedule_all(e);
	return ret;
}

int x4_engine_brake(struct x4_engine *e)
{
	return x4_engine_halt(e, 0x0f, false);
}

int x4_engine_stop(struct x4_engine *e)
{
	return x4_engine_halt(e, 0x0f, true);
}

int x4_engine_set_position(struct x4_engine *e, u8 axes, const s32 *pos)
{
	int i;

	if (!axes || axes > 0x0f)
		return X4_ERR_PARAM_FAIL;
	x4_engine_halt(e, axes, true);
	for (i = 0; i < X4_AXES; i++) {
		if (!(axes & (1u << i)))
			continue;
		e->steps[i] = 0;
		e->pos_base[i] = (u32)pos[i];
		e->err[i] = 0;
		e->sync |= (u8)(1u << i);
	}
	return X4_OK;
}
