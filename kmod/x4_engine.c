// SPDX-License-Identifier: GPL-2.0
/*
 * x4step engine core. See x4_engine.h for the model; the profile is the
 * X4Step manual's (chapter 2) with the thesis' analytic step times.
 */
#include "x4_engine.h"

#ifdef __KERNEL__
#include <linux/math64.h>
#include <linux/string.h>
#define x4_div(a, b) div64_u64((a), (b))
#else
#include <string.h>
#define x4_div(a, b) ((a) / (b))
/* noinline: defined by the build (CMakeLists.txt), as the kernel does */
#endif

#define NSEC_PER_SEC_U64 1000000000ull
#define NO_STEP (~(u64)0)

/* floor(sqrt(x)) by Newton's method from an estimate x0 > 0. */
static u64 isqrt_from(u64 x, u64 x0)
{
	u64 r, next;

	if (!x)
		return 0;
	/* One step from any positive guess lands at or above the root. */
	r = (x0 + x4_div(x, x0)) / 2;
	for (;;) {
		next = (r + x4_div(x, r)) / 2;
		if (next >= r)
			return r;
		r = next;
	}
}

u64 x4_isqrt(u64 x)
{
	if (!x)
		return 0;
	/* 2^ceil(bits/2) is at or above the root. */
	return isqrt_from(x, 1ull << ((64 - __builtin_clzll(x) + 1) / 2));
}

/*
 * sqrt(x) of x in a ramp's units (4^sh ns^2), in ns. est: a value at or
 * above the root in the ramp's units (0: none).
 */
static u64 ramp_root(const struct x4_ramp *r, u64 x, u64 est)
{
	u64 q = est ? isqrt_from(x, est) : x4_isqrt(x);

	if (!r->sh)
		return q;
	/* The fraction below one unit, from the remainder (to < 1 ns). */
	return (q << r->sh) + x4_div((x - q * q) << r->sh, 2 * q + 1);
}

/* u(m) = sqrt(c + m k) of a ramp side, in ns; est as for ramp_root(). */
static u64 ramp_u(const struct x4_ramp *r, u64 m, u64 est)
{
	return ramp_root(r, r->c + m * r->k, est);
}

static u64 cruise_time(const struct x4_plan *p, u64 n)
{
	return p->c_base + x4_div((2 * n - p->c_m0) * p->c_num, p->c_den);
}

u64 x4_plan_time(const struct x4_plan *p, u64 n)
{
	if (n >= p->n_decel)
		return p->t_last + p->dec.s_ns -
		       ramp_u(&p->dec, p->last - n, 0);
	if (n < p->n_cruise)
		return ramp_u(&p->acc, n, 0) - p->acc.s_ns;
	return cruise_time(p, n);
}

int x4_ramp_check(s32 freq_hz, s32 ramp_ms)
{
	if (freq_hz > X4_FREQ_MAX_HZ)
		return X4_ERR_FREQ_TOO_HIGH;
	if (freq_hz < X4_FREQ_MIN_HZ)
		return X4_ERR_FREQ_TOO_LOW;
	if (ramp_ms > X4_RAMP_MAX_MS)
		return X4_ERR_RAMP_TOO_HIGH;
	if (ramp_ms < 0)
		return X4_ERR_PARAM_FAIL;
	if (ramp_ms > freq_hz)
		return X4_ERR_RAMP_FREQ;
	return X4_OK;
}

/*
 * Arguments are checked before state, in this order (documented in
 * x4step.h): frequency, ramp, paths; then loaded, then active.
 */
int x4_move_check(const struct x4_move *m)
{
	int ret = x4_ramp_check(m->freq_hz, m->ramp_ms);
	bool any = false;
	int i;

	if (ret)
		return ret;
	for (i = 0; i < X4_AXES; i++) {
		if (m->steps[i] > X4_STEPS_MAX || m->steps[i] < -X4_STEPS_MAX)
			return X4_ERR_STEPS_TOO_HIGH;
		any |= m->steps[i] != 0;
	}
	return any ? X4_OK : X4_ERR_NO_STEPS;
}

int x4_profile_check(const struct x4_profile *p)
{
	if (!p->vm || p->vm > X4_VEL_MAX || p->v0 > p->vm || p->ve > p->vm ||
	    p->a0 > X4_ACC_MAX || p->ae > X4_ACC_MAX ||
	    (p->a0 && (u64)p->vm > (u64)X4_RAMP_TIME_MAX_S * p->a0) ||
	    (p->ae && (u64)p->vm > (u64)X4_RAMP_TIME_MAX_S * p->ae))
		return X4_ERR_PARAM_FAIL;
	return X4_OK;
}

/* One side of a profile's ramp: from or to rest speed v, acceleration a. */
static void plan_ramp(struct x4_ramp *r, u64 v, u64 a, u64 vm)
{
	u64 s, rem;

	r->sh = 0;
	/* u never exceeds vm / a: keep it below 2^31 units. */
	while ((x4_div(vm * NSEC_PER_SEC_U64, a) >> r->sh) >= (1ull << 31))
		r->sh++;
	s = x4_div(v * NSEC_PER_SEC_U64, a << r->sh);
	rem = v * NSEC_PER_SEC_U64 - s * (a << r->sh);
	/* (s + rem / D)^2 to a unit: the fraction matters when units are us */
	r->c = s * s + x4_div(2 * s * rem + x4_div(rem * rem, a << r->sh),
			      a << r->sh);
	r->k = x4_div(2 * NSEC_PER_SEC_U64 * NSEC_PER_SEC_U64, a << (2 * r->sh));
	r->s_ns = ramp_u(r, 0, 0);
}

/* (x - y)^2 / (2 a vm) in ns: how much later than "at vm from 0" a ramp ends. */
static u64 ramp_lag(u64 x, u64 y, u64 a, u64 vm)
{
	return a ? x4_div((x - y) * (x - y) * NSEC_PER_SEC_U64, 2 * a * vm) : 0;
}

/*
 * The time a ramp side takes for num / den steps (a fraction) from its
 * rest speed, in ns: u(num / den) - u(0), with m k split so that nothing
 * overflows (num % den < den, k % den < den, den <= 4e6).
 */
static u64 ramp_frac(const struct x4_ramp *r, u64 num, u64 den)
{
	u64 m = x4_div(num, den), f = num - m * den;
	u64 kq = x4_div(r->k, den), kr = r->k - kq * den;
	u64 x = r->c + m * r->k + f * kq + x4_div(f * kr, den);

	return ramp_root(r, x, 0) - r->s_ns;
}

/*
 * Plan a profile move (ProStep4) of `steps` >= 1 steps. Four shapes:
 *  - trapezoid: v0 up to vm with a0, cruise, down to ve with ae;
 *  - triangle: too short for vm: turn where the ramps meet (vp);
 *  - too short to brake from v0 to ve: start at the speed from which
 *    the ramp just reaches ve, and brake all the way;
 *  - too short to accelerate to ve: accelerate all the way.
 * A side with a = 0 has no ramp: it starts (or stops) at vm.
 */
static void plan_prof(struct x4_plan *p, u64 steps, const struct x4_profile *f)
{
	u64 d = steps - 1, vm = f->vm, a0 = f->a0, ae = f->ae;
	u64 v0 = a0 ? f->v0 : vm, ve = ae ? f->ve : vm;
	u64 up2 = vm * vm - v0 * v0, down2 = vm * vm - ve * ve;
	u64 sa = a0 ? x4_div(up2 + 2 * a0 - 1, 2 * a0) : 0;
	u64 sd = ae ? x4_div(down2 + 2 * ae - 1, 2 * ae) : 0;
	u64 v1, vp2;

	p->endless = false;
	p->last = d;
	p->prof = *f;
	p->prof.v0 = (u32)v0;
	p->prof.ve = (u32)ve;
	p->brake_steps = 0;
	if (a0)
		plan_ramp(&p->acc, v0, a0, vm);
	if (ae)
		plan_ramp(&p->dec, ve, ae, vm);
	p->c_m0 = 0;
	p->c_num = NSEC_PER_SEC_U64;
	p->c_den = 2 * vm;
	p->c_base = ramp_lag(vm, v0, a0, vm);
	/* A single step: at v0, or what the ramp reaches in half a step. */
	v1 = v0 ? v0 : x4_isqrt(a0);
	p->single_half_ns = x4_div(NSEC_PER_SEC_U64, 2 * (v1 < vm ? v1 : vm));
	if (d >= sa + sd) {
		p->n_cruise = v0 < vm ? x4_div(up2, 2 * a0) + 1 : 0;
		p->n_decel = ve < vm ? d - x4_div(down2, 2 * ae) : d + 1;
		p->t_last = cruise_time(p, d) + ramp_lag(vm, ve, ae, vm);
		return;
	}
	vp2 = a0 && ae ? x4_div(ae * (v0 * v0 + 2 * a0 * d) + a0 * ve * ve,
				a0 + ae) : 0;
	if (!a0 || (ae && vp2 < v0 * v0)) {
		/* Brake all the way, from where the ramp reaches ve. */
		p->n_cruise = 0;
		p->n_decel = 0;
		p->t_last = ramp_u(&p->dec, d, 0) - p->dec.s_ns;
	} else if (!ae || vp2 < ve * ve) {
		p->n_cruise = d + 1; /* accelerate all the way */
		p->n_decel = d + 1;
	} else {
		/*
		 * The ramps meet after (2 ae d + ve^2 - v0^2) / 2 (a0 + ae)
		 * steps of acceleration: exact, not from the rounded vp2.
		 */
		u64 den = 2 * (a0 + ae);
		u64 num_a = 2 * ae * d + ve * ve - v0 * v0;
		u64 num_d = 2 * a0 * d + v0 * v0 - ve * ve;

		p->n_cruise = x4_div(num_a, den) + 1;
		p->n_decel = p->n_cruise;
		p->t_last = ramp_frac(&p->acc, num_a, den) +
			    ramp_frac(&p->dec, num_d, den);
	}
}

/*
 * Plan an X4Step move's leader schedule for `steps` steps (0: endless) at
 * freq_hz with ramp_ms ramps. Four shapes:
 *  - no ramp: constant frequency from the first step;
 *  - trapezoid: ramps of freq*ramp/2000 steps around a cruise at freq;
 *  - short: too short for freq: accelerate over (D - P) / 2 steps, run
 *    X4_PLATEAU_STEPS (P) steps at the speed reached, brake mirrored;
 *  - tiny: D <= P steps run at min(freq, sqrt(a)), the speed the ramp
 *    reaches after half a step, so short jogs never start with a jerk.
 * D = steps - 1 is the number of step intervals.
 */
static void plan_profile(struct x4_plan *p, u64 steps, u32 freq, u32 ramp)
{
	u64 na2000 = (u64)freq * ramp; /* 2000 x steps of one ramp */
	u64 d = steps ? steps - 1 : 0;
	u64 x2, t_a, interval;

	memset(&p->acc, 0, sizeof(p->acc));
	memset(&p->prof, 0, sizeof(p->prof));
	p->endless = !steps;
	p->last = steps ? d : NO_STEP;
	p->acc.k = ramp ? x4_div(2000000000000000ull * ramp, freq) : 0;
	p->dec = p->acc;
	p->n_decel = p->endless ? NO_STEP : d + 1;
	p->c_base = 0;
	p->c_m0 = 0;
	p->c_num = NSEC_PER_SEC_U64;
	p->c_den = 2ull * freq;
	p->t_last = 0;
	p->brake_steps = 0;
	p->n_cruise = 0;
	p->single_half_ns = x4_div(NSEC_PER_SEC_U64, 2ull * freq);

	if (!ramp)
		return;
	if (p->endless || 2000 * d >= 2 * na2000 + 2000 * X4_PLATEAU_STEPS) {
		p->n_cruise = na2000 / 2000 + 1;
		p->c_base = 500000ull * ramp;
		p->brake_steps = (u32)((na2000 + 1999) / 2000);
		if (!p->endless) {
			p->n_decel = d - na2000 / 2000;
			p->t_last = x4_div(d * NSEC_PER_SEC_U64, freq) +
				    1000000ull * ramp;
		}
	} else if (d > X4_PLATEAU_STEPS) {
		x2 = d - X4_PLATEAU_STEPS;
		t_a = x4_isqrt(x2 * p->acc.k / 2);
		p->n_cruise = x2 / 2 + 1;
		p->n_decel = d - x2 / 2;
		p->c_base = t_a;
		p->c_m0 = x2;
		p->c_num = t_a;
		p->c_den = 2 * x2;
		p->t_last = x4_div(t_a * (d + x2), x2);
		p->brake_steps = (u32)((x2 + 1) / 2);
	} else {
		interval = x4_isqrt(p->acc.k / 2);
		if (interval < x4_div(NSEC_PER_SEC_U64, freq))
			interval = x4_div(NSEC_PER_SEC_U64, freq);
		p->c_num = interval;
		p->c_den = 2;
		p->single_half_ns = interval / 2;
		p->brake_steps = 1;
	}
}

static void plan_axes(struct x4_plan *p, const s64 *steps)
{
	u32 longest = 0;
	int i;

	p->dirs = 0;
	p->axes = 0;
	p->leader = 0;
	for (i = 0; i < X4_AXES; i++) {
		u32 n = (u32)(steps[i] < 0 ? -steps[i] : steps[i]);

		p->abs_steps[i] = n;
		p->sign[i] = steps[i] < 0 ? -1 : 1;
		if (!n)
			continue;
		p->axes |= 1u << i;
		if (steps[i] > 0)
			p->dirs |= X4_DIR_BIT(i);
		if (n > longest) {
			longest = n;
			p->leader = (u8)i;
		}
	}
	p->bres_2l = 2ull * longest;
	for (i = 0; i < X4_AXES; i++)
		p->bres_inc[i] = i == p->leader ? 0 : 2ull * p->abs_steps[i];
}

void x4_engine_init(struct x4_engine *e)
{
	static const struct x4_profile prof = { 0, 0, 1000, 1000, 1000 };
	int i;

	memset(e, 0, sizeof(*e));
	e->cur = e->ch;
	e->timing.dir_setup_ns = X4_DIR_SETUP_NS;
	e->budget = X4_WRITE_BUDGET;
	for (i = 0; i < X4_AXES; i++)
		e->prof[i] = prof;
}

int x4_engine_configure(struct x4_engine *e, const struct x4_timing *t,
			u8 mode)
{
	if (t->pulse_ns > X4_TIMING_MAX_NS ||
	    (t->pulse_ns && t->pulse_ns < X4_PULSE_MIN_NS) ||
	    t->space_ns > X4_TIMING_MAX_NS ||
	    t->dir_setup_ns > X4_TIMING_MAX_NS ||
	    t->dir_hold_ns > X4_TIMING_MAX_NS || mode > X4_MODE_SMC_PHASE_HOLD)
		return X4_ERR_PARAM_FAIL;
	if (x4_engine_busy(e))
		return X4_ERR_IS_ACTIVE;
	e->timing = *t;
	e->mode = mode;
	return X4_OK;
}

/*
 * Whether steps at freq_hz fit the port's timing: a fixed pulse plus the
 * minimum space, or half a period each for the symmetric clock.
 */
static int timing_check(const struct x4_engine *e, s32 freq_hz)
{
	u64 period = x4_div(NSEC_PER_SEC_U64, (u64)freq_hz);
	const struct x4_timing *t = &e->timing;

	if (e->mode != X4_MODE_CLOCK_DIR)
		return X4_OK; /* phase patterns have no pulse */
	if (t->pulse_ns ? t->pulse_ns + t->space_ns > period :
			  t->space_ns > period / 2)
		return X4_ERR_FREQ_TOO_HIGH;
	return X4_OK;
}

static bool phase_mode(const struct x4_engine *e)
{
	return e->mode != X4_MODE_CLOCK_DIR;
}

/* The axes an output mode drives, as a mask. */
static u8 mode_axes(const struct x4_engine *e)
{
	return phase_mode(e) ? 0x07 : 0x0f;
}

/* The axes of the running moves. */
static u8 busy_axes(const struct x4_engine *e)
{
	u8 axes = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (e->busy & (1u << i))
			axes |= e->ch[i].run.axes;
	return axes;
}

/* Port writes of one leader step: clock up and down, or a phase pattern per motor. */
static u32 writes_per_step(const struct x4_engine *e, u8 axes)
{
	u32 n = 0;

	if (!phase_mode(e))
		return 2;
	for (; axes; axes &= axes - 1)
		n++;
	return n;
}

/*
 * Port writes per second of plan p at its top speed: the cruise interval
 * (2 c_num / c_den ns) is the shortest of every shape.
 */
static u32 plan_rate(const struct x4_engine *e, const struct x4_plan *p)
{
	u64 steps = x4_div(p->c_den * NSEC_PER_SEC_U64 + 2 * p->c_num - 1,
			   2 * p->c_num);

	return (u32)(steps * writes_per_step(e, p->axes));
}

/* Whether moves needing `add` more writes per second fit the budget. */
static int budget_check(const struct x4_engine *e, u64 add)
{
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (e->busy & (1u << i))
			add += e->ch[i].rate;
	return e->budget && add > e->budget ? X4_ERR_RATE_BUDGET : X4_OK;
}

static s32 position(const struct x4_engine *e, int i)
{
	return (s32)(e->pos_base[i] + (u32)e->steps[i]);
}

/* Start counting the axes' steps afresh; their coordinates stay. */
static void fold_steps(struct x4_engine *e, u8 axes)
{
	int i;

	for (i = 0; i < X4_AXES; i++) {
		if (!(axes & (1u << i)))
			continue;
		e->pos_base[i] += (u32)e->steps[i];
		e->steps[i] = 0;
	}
}

/* The input bit of an input number 1..5, 0 for none. */
static u8 input_bit(u8 input)
{
	return input ? (u8)(1u << (input - 1)) : 0;
}

/* The limit switch input that axis i of plan p moves toward. */
static u8 limit_bit(const struct x4_engine *e, const struct x4_plan *p, int i)
{
	return input_bit(p->sign[i] > 0 ? e->sw.plus[i] : e->sw.minus[i]);
}

/* The earliest event of all channels is the next; the outputs of all. */
static void schedule_all(struct x4_engine *e)
{
	u64 due = NO_STEP;
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

/* After an event of channel e->cur: the common case is that it runs alone. */
static inline void schedule(struct x4_engine *e, const struct x4_chan *c)
{
	if (e->solo && c->phase != X4_IDLE) {
		e->due = c->t_pending;
		e->ctl = (u8)((e->ctl & (X4_CTL_SIGNAL1 | X4_CTL_SIGNAL2)) |
			      c->ctl);
		return;
	}
	schedule_all(e);
}

/*
 * Which switches end the move of channel c: the limits its axes move
 * toward, and in a reference run the REF input. A limit that is active
 * already while the axis backs off the opposite limit on the same input
 * (switches in parallel) is armed once it has been released.
 */
static void arm_switches(struct x4_engine *e, struct x4_chan *c)
{
	const struct x4_plan *p = &c->run;
	int i;

	c->halt_mask = 0;
	c->halt_flip = 0;
	c->deferred = 0;
	for (i = 0; i < X4_AXES; i++) {
		u8 bit = limit_bit(e, p, i), back;

		if (!(p->axes & (1u << i)) || !bit)
			continue;
		back = p->sign[i] > 0 ? e->err[i] & X4_AXERR_LIMIT_NEG &&
					input_bit(e->sw.minus[i]) == bit :
					e->err[i] & X4_AXERR_LIMIT_POS &&
					input_bit(e->sw.plus[i]) == bit;
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

/* Begin the move in c->run: directions go out at now_ns. */
static void begin(struct x4_engine *e, struct x4_chan *c, u64 now_ns)
{
	int i;

	c->phase = X4_SETUP;
	c->no_steps = false;
	c->n = 0;
	c->t_cur = 0;
	c->ctl = 0;
	c->t_pending = now_ns;
	c->origin = now_ns + e->timing.dir_setup_ns;
	c->rate = plan_rate(e, &c->run);
	for (i = 0; i < X4_AXES; i++)
		c->bres[i] = c->run.bres_2l / 2;
	arm_switches(e, c);
	for (i = 0; i < X4_AXES; i++)
		if (c->run.axes & (1u << i))
			e->err[i] = 0; /* a new command to the axis */
	fold_steps(e, c->run.axes);
	schedule_all(e);
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
		ret = timing_check(e, m->freq_hz);
	if (!ret && phase_mode(e) && m->steps[3])
		ret = X4_ERR_PARAM_FAIL; /* the SMC boards drive 3 motors */
	if (ret)
		return ret;
	if (e->loaded)
		return X4_ERR_IS_LOADED;
	for (i = 0; i < X4_AXES; i++)
		steps[i] = m->steps[i];
	plan_axes(&e->next, steps);
	plan_profile(&e->next, e->next.abs_steps[e->next.leader],
		     (u32)m->freq_hz, (u32)m->ramp_ms);
	e->loaded = true;
	return X4_OK;
}

int x4_engine_start(struct x4_engine *e, u64 now_ns)
{
	struct x4_chan *c;

	if (!e->loaded)
		return X4_ERR_NOT_LOADED;
	if (busy_axes(e) & e->next.axes)
		return X4_ERR_IS_ACTIVE;
	if (budget_check(e, plan_rate(e, &e->next)))
		return X4_ERR_RATE_BUDGET;
	c = chan_of(e, e->next.axes);
	c->run = e->next;
	c->home = 0;
	e->loaded = false;
	fold_steps(e, 0x0f); /* X4Start clears every step counter */
	begin(e, c, now_ns);
	return X4_OK;
}

int x4_engine_endless(struct x4_engine *e, s32 axis, bool negative,
		      s32 freq_hz, s32 ramp_ms, u64 now_ns)
{
	s64 steps[X4_AXES] = { 0 };
	struct x4_chan *c;
	int ret;

	if (axis < 1 || axis > X4_AXES || !(mode_axes(e) & (1u << (axis - 1))))
		return X4_ERR_PARAM_FAIL;
	ret = x4_ramp_check(freq_hz, ramp_ms);
	if (!ret)
		ret = timing_check(e, freq_hz);
	if (ret)
		return ret;
	if (e->loaded)
		return X4_ERR_IS_LOADED;
	if (busy_axes(e) & (1u << (axis - 1)))
		return X4_ERR_IS_ACTIVE;
	if (budget_check(e, (u64)freq_hz * writes_per_step(e, 1)))
		return X4_ERR_RATE_BUDGET;
	c = &e->ch[axis - 1];
	steps[axis - 1] = negative ? -1 : 1;
	plan_axes(&c->run, steps);
	plan_profile(&c->run, 0, (u32)freq_hz, (u32)ramp_ms);
	c->home = 0;
	fold_steps(e, 0x0f);
	begin(e, c, now_ns);
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

	if (!axes || axes & ~mode_axes(e))
		return X4_ERR_PARAM_FAIL;
	g->axes = axes;
	g->moving = 0;
	g->rate = 0;
	for (i = 0; i < X4_AXES; i++) {
		if (!(axes & (1u << i)))
			continue;
		ret = timing_check(e, (s32)e->prof[i].vm);
		if (ret)
			return ret;
	}
	if (busy_axes(e) & axes)
		return X4_ERR_IS_ACTIVE;
	for (i = 0; i < X4_AXES; i++) {
		g->from[i] = position(e, i);
		steps[i] = relative ? (s64)target[i] :
				      (s64)target[i] - g->from[i];
		if (!(axes & (1u << i)) || !steps[i])
			continue; /* not commanded, or there already */
		g->moving |= 1u << i;
		/* A profile move's top speed is at most vm. */
		g->rate += (u64)e->prof[i].vm * writes_per_step(e, 1);
	}
	if (budget_check(e, g->rate))
		return X4_ERR_RATE_BUDGET;
	for (i = 0; i < X4_AXES; i++) {
		s64 one[X4_AXES] = { 0 };

		if (!(g->moving & (1u << i)))
			continue;
		one[i] = steps[i];
		plan_axes(&g->plan[i], one);
		plan_prof(&g->plan[i], g->plan[i].abs_steps[i], &e->prof[i]);
	}
	return X4_OK;
}

int x4_engine_start_goto(struct x4_engine *e, const struct x4_goto *g,
			 u64 now_ns)
{
	int i;

	if (busy_axes(e) & g->axes)
		return X4_ERR_IS_ACTIVE;
	if (budget_check(e, g->rate))
		return X4_ERR_RATE_BUDGET;
	for (i = 0; i < X4_AXES; i++)
		if (g->axes & (1u << i) && position(e, i) != g->from[i])
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
		begin(e, c, now_ns);
	}
	return X4_OK;
}

#ifndef __KERNEL__ /* the module plans on a copy: x4_port_goto() */
int x4_engine_goto(struct x4_engine *e, u8 axes, const s32 *target,
		   bool relative, u64 now_ns)
{
	struct x4_goto g;
	int ret = x4_engine_plan_goto(e, axes, target, relative, &g);

	return ret ? ret : x4_engine_start_goto(e, &g, now_ns);
}
#endif

static u32 abs_s32(s32 v)
{
	return v < 0 ? (u32)-(s64)v : (u32)v;
}

/* Start reference run phase `phase` of the axis of channel c. */
static void home_phase(struct x4_engine *e, struct x4_chan *c, int axis,
		       u8 phase, s32 vref, u64 now_ns)
{
	s64 steps[X4_AXES] = { 0 };

	steps[axis] = vref < 0 ? -(s64)c->sref : (s64)c->sref;
	plan_axes(&c->run, steps);
	plan_profile(&c->run, (u64)c->sref + 1, abs_s32(vref), 0);
	c->home = phase;
	begin(e, c, now_ns);
	/* The budget holds the faster phase for the whole reference run. */
	if (c->rate < c->home_rate)
		c->rate = c->home_rate;
}

static bool vref_ok(s32 v)
{
	return v && v <= X4_VEL_MAX && v >= -X4_VEL_MAX;
}

int x4_home_check(u8 phases, s32 vref1, s32 vref2, u32 sref)
{
	if (!phases || phases & ~(X4_HOME_PHASE1 | X4_HOME_PHASE2) ||
	    (phases & X4_HOME_PHASE1 && !vref_ok(vref1)) ||
	    (phases & X4_HOME_PHASE2 && !vref_ok(vref2)) || !sref ||
	    sref > 0x7fffffff)
		return X4_ERR_PARAM_FAIL;
	return X4_OK;
}

int x4_engine_home(struct x4_engine *e, s32 axis, u8 phases, s32 vref1,
		   s32 vref2, u32 sref, u64 now_ns)
{
	struct x4_chan *c;
	u32 vmax, rate;
	int ret;

	if (axis < 1 || axis > X4_AXES ||
	    !(mode_axes(e) & (1u << (axis - 1))) ||
	    x4_home_check(phases, vref1, vref2, sref) || !e->sw.ref[axis - 1])
		return X4_ERR_PARAM_FAIL;
	ret = timing_check(e, phases & X4_HOME_PHASE1 ? abs_s32(vref1) : 1);
	if (!ret)
		ret = timing_check(e, phases & X4_HOME_PHASE2 ? abs_s32(vref2) : 1);
	if (ret)
		return ret;
	if (busy_axes(e) & (1u << (axis - 1)))
		return X4_ERR_IS_ACTIVE;
	vmax = phases & X4_HOME_PHASE1 ? abs_s32(vref1) : 0;
	if (phases & X4_HOME_PHASE2 && abs_s32(vref2) > vmax)
		vmax = abs_s32(vref2);
	rate = vmax * writes_per_step(e, 1);
	if (budget_check(e, rate))
		return X4_ERR_RATE_BUDGET;
	c = &e->ch[axis - 1];
	c->home_rate = rate;
	c->sref = sref;
	c->vref2 = vref2;
	c->ref_bit = input_bit(e->sw.ref[axis - 1]);
	c->home_next = phases == (X4_HOME_PHASE1 | X4_HOME_PHASE2);
	e->sync &= (u8)~(1u << (axis - 1));
	if (phases & X4_HOME_PHASE1)
		home_phase(e, c, axis - 1, X4_HOME_PHASE1, vref1, now_ns);
	else
		home_phase(e, c, axis - 1, X4_HOME_PHASE2, vref2, now_ns);
	return X4_OK;
}

/*
 * Decelerate channel c from leader step nb (whose time t_nb is already
 * fixed) to rest along the ramp. The pending event keeps its time, so the
 * glue never has to re-arm its timer: only what happens at that time
 * changes.
 */
static void brake_from(struct x4_chan *c, u64 nb, u64 t_nb)
{
	struct x4_plan *p = &c->run;
	const struct x4_profile *f = &p->prof;
	u64 d, v2;

	if (nb >= p->n_decel)
		return; /* already braking */
	if (f->vm) {
		/* A profile move: from the speed at nb down to ve. */
		v2 = nb < p->n_cruise ? (u64)f->v0 * f->v0 + 2ull * f->a0 * nb :
					(u64)f->vm * f->vm;
		d = f->ae && v2 > (u64)f->ve * f->ve ?
			x4_div(v2 - (u64)f->ve * f->ve + 2ull * f->ae - 1,
			       2ull * f->ae) : 0;
	} else if (!p->dec.k) {
		d = 0;
	} else if (nb < p->n_cruise) {
		d = nb; /* v^2 / 2a = nb while accelerating from rest */
	} else {
		d = p->brake_steps;
	}
	if (!d) {
		/* No ramp to follow: step nb - 1 was the last. */
		if (c->phase == X4_SETUP)
			c->no_steps = true;
		else if (c->phase == X4_RISE)
			c->phase = X4_END; /* at the time step nb was due */
		else
			p->last = nb - 1;
		return;
	}
	if (!p->endless && nb + d >= p->last)
		return; /* the planned ramp ends sooner */
	p->endless = false;
	p->last = nb + d;
	p->n_decel = nb;
	p->t_last = t_nb + ramp_u(&p->dec, d, 0) - p->dec.s_ns;
}

static void brake_chan(struct x4_chan *c)
{
	switch (c->phase) {
	case X4_IDLE:
	case X4_END:
		break;
	case X4_SETUP:
		brake_from(c, 0, 0);
		break;
	case X4_RISE:
		brake_from(c, c->n, c->t_cur);
		break;
	case X4_FALL:
		if (c->n < c->run.last)
			brake_from(c, c->n + 1, c->t_next);
		break;
	case X4_QUEUED: /* brake what comes after this instant's writes */
		c->phase = c->phase_after;
		brake_chan(c);
		c->phase_after = c->phase;
		c->phase = X4_QUEUED;
		break;
	}
}

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
 * T(n + 1), from T(n) in c->t_cur, in O(1). BOOST is high for the
 * interval when T(n + 1) lies on a ramp.
 */
static u64 next_time(struct x4_chan *c)
{
	struct x4_plan *p = &c->run;
	u64 n1 = c->n + 1;
	u64 m, q, u;

	if (n1 >= p->n_decel) {
		c->ctl = X4_CTL_AKTIV | X4_CTL_BOOST;
		/* The previous u is the estimate. */
		u = (p->t_last + p->dec.s_ns - c->t_cur) >> p->dec.sh;
		return p->t_last + p->dec.s_ns -
		       ramp_u(&p->dec, p->last - n1, u + 1);
	}
	if (n1 < p->n_cruise) {
		c->ctl = X4_CTL_AKTIV | X4_CTL_BOOST;
		u = (c->t_cur + p->acc.s_ns) >> p->acc.sh;
		if (u)
			u += x4_div(p->acc.k, 2 * u) + 1;
		return ramp_u(&p->acc, n1, u) - p->acc.s_ns;
	}
	c->ctl = X4_CTL_AKTIV;
	/* Rebase so that endless moves never overflow. */
	m = 2 * n1 - p->c_m0;
	if (m >= p->c_den) {
		q = x4_div(m, p->c_den);
		p->c_m0 += q * p->c_den;
		p->c_base += q * p->c_num;
	}
	return cruise_time(p, n1);
}

static u8 dir_bits(u8 axes)
{
	u8 bits = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (axes & (1u << i))
			bits |= X4_DIR_BIT(i);
	return bits;
}

/* The clock bits of the axes in `axes`. */
static u8 clk_bits(u8 axes)
{
	return (u8)(dir_bits(axes) << 1);
}

/* The axes whose clock bits are set in clk. */
static u8 clk_axes(u8 clk)
{
	u8 axes = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (clk & X4_CLK_BIT(i))
			axes |= 1u << i;
	return axes;
}

/*
 * SMC800/SMC1500 phase drive (SMCMOT.PAS): the half-step table MOTRUN and
 * MOTZERO (0 % on both phases). Per phase, bits 0-1 (A) and 3-4 (B) set
 * the current (11 0 %, 01 20 %, 10 60 %, 00 100 %), bits 2 and 5 its
 * direction; bits 6-7 select the motor.
 */
static const u8 smc_run[8] = { 0x03, 0x09, 0x38, 0x29, 0x27, 0x2d, 0x1c, 0x0d };
#define SMC_OFF 0x1b
#define SMC_SELECT(motor) ((u8)((motor) << 6))

/* Reduced holding current: phases at 100 % drop to 20 %. */
static u8 smc_hold(u8 pattern)
{
	if (!(pattern & 0x03))
		pattern |= 0x01;
	if (!(pattern & 0x18))
		pattern |= 0x08;
	return pattern;
}

/*
 * Writes due at time t: the first now, the rest queued at the same t,
 * before whatever c->phase and c->t_pending were going to be next.
 */
static void emit(struct x4_engine *e, struct x4_chan *c, const u8 *bytes,
		 int n, u64 t)
{
	int i;

	if (!n)
		return;
	e->data = bytes[0];
	if (n < 2)
		return;
	c->queued = 0;
	c->qhead = 0;
	for (i = 1; i < n; i++)
		c->queue[c->queued++] = bytes[i];
	c->phase_after = c->phase;
	c->t_after = c->t_pending;
	c->phase = X4_QUEUED;
	c->t_pending = t;
}

/* Phase-mode writes of the motors in `axes`: moving or resting. */
static int smc_patterns(const struct x4_engine *e, u8 axes, bool rest,
			u8 *bytes)
{
	int m, n = 0;

	for (m = 0; m < X4_SMC_AXES; m++) {
		u8 run = smc_run[e->smc_phase[m]];

		if (!(axes & (1u << m)))
			continue;
		if (rest)
			run = e->mode == X4_MODE_SMC_PHASE_HOLD ? smc_hold(run) :
								  SMC_OFF;
		bytes[n++] = run | SMC_SELECT(m);
	}
	return n;
}

int x4_engine_rest_writes(const struct x4_engine *e, u8 *bytes)
{
	if (!phase_mode(e)) {
		bytes[0] = e->data & X4_DIR_MASK;
		return 1;
	}
	return smc_patterns(e, 0x07, true, bytes);
}

static noinline void begin_setup(struct x4_engine *e, struct x4_chan *c,
				 u64 now_ns)
{
	const struct x4_plan *p = &c->run;
	u8 bytes[X4_SMC_AXES];

	c->ctl = p->n_cruise ? X4_CTL_AKTIV | X4_CTL_BOOST : X4_CTL_AKTIV;
	/* Count the setup time from when the directions really go out. */
	if (now_ns > c->t_pending)
		c->origin = now_ns + e->timing.dir_setup_ns;
	c->phase = c->no_steps ? X4_END : X4_RISE;
	c->t_pending = c->origin;
	if (phase_mode(e))
		emit(e, c, bytes, smc_patterns(e, p->axes, false, bytes), now_ns);
	else /* axes that do not move keep their direction level */
		e->data = (u8)((e->data & ~dir_bits(p->axes)) | p->dirs);
}

static void end(struct x4_engine *e, struct x4_chan *c)
{
	u8 bytes[X4_SMC_AXES], others = 0;
	int i;

	c->ctl = 0;
	c->phase = X4_IDLE;
	c->halt_mask = 0;
	c->deferred = 0;
	e->ends++;
	if (!phase_mode(e))
		return;
	/* Every motor not driven by another move goes to rest. */
	for (i = 0; i < X4_AXES; i++)
		if (e->ch[i].phase != X4_IDLE)
			others |= e->ch[i].run.axes;
	emit(e, c, bytes, smc_patterns(e, 0x07 & ~others, true, bytes),
	     c->t_pending);
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

/* After the last step: end now, or after the hold (and settle) time. */
static noinline void last_step_done(struct x4_engine *e, struct x4_chan *c,
				    u64 t)
{
	if (!e->timing.dir_hold_ns && !phase_mode(e)) {
		end(e, c);
		return;
	}
	/* Phase mode: give the motor its last step period to settle. */
	c->phase = X4_END;
	c->t_pending = t + e->timing.dir_hold_ns +
		       (phase_mode(e) ? 2 * c->half_ns : 0);
}

/* Step n + 1 rises next. */
static inline void next_step(struct x4_chan *c)
{
	c->n++;
	c->t_cur = c->t_next;
	c->phase = X4_RISE;
	c->t_pending = c->origin + c->t_cur;
}

/* After step n's clock fell (or its pattern went out): what comes next. */
static inline void step_done(struct x4_engine *e, struct x4_chan *c, u64 t)
{
	if (c->n >= c->run.last)
		last_step_done(e, c, t);
	else
		next_step(c);
}

/* Phase mode: walk the table of each motor that steps, write them. */
static noinline void smc_step(struct x4_engine *e, struct x4_chan *c, u64 t)
{
	u8 bytes[X4_SMC_AXES];
	int m;

	for (m = 0; m < X4_SMC_AXES; m++)
		if (c->stepping & X4_CLK_BIT(m))
			e->smc_phase[m] = (e->smc_phase[m] + c->run.sign[m]) & 7;
	emit(e, c, bytes, smc_patterns(e, clk_axes(c->stepping), false, bytes),
	     t);
}

/* No further step of channel c: it ends at its pending event. */
static void cut(struct x4_chan *c)
{
	struct x4_plan *p = &c->run;

	c->home = 0;
	switch (c->phase) {
	case X4_SETUP:
		c->no_steps = true;
		break;
	case X4_RISE:
		c->phase = X4_END;
		break;
	case X4_FALL:
		p->last = c->n;
		break;
	case X4_QUEUED:
		if (c->phase_after == X4_RISE)
			c->phase_after = X4_END;
		else if (c->phase_after == X4_SETUP)
			c->no_steps = true;
		else
			p->last = c->n;
		break;
	default:
		break;
	}
}

/* The limit input that axis i of running channel c watches, or 0. */
static u8 watched_limit(const struct x4_engine *e, const struct x4_chan *c,
			int i)
{
	if (c->phase == X4_IDLE || !(c->run.axes & (1u << i)))
		return 0;
	return limit_bit(e, &c->run, i) & c->halt_mask;
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
			cut(c);
		}
	}
}

/* Switches that channel c watches (hit) are active at its step tick. */
static noinline void halted(struct x4_engine *e, struct x4_chan *c, u8 hit)
{
	int axis = c->run.leader;

	if (!(hit & c->ref_bit) || !c->home) {
		limits_hit(e, hit & (u8)~(c->home ? c->ref_bit : 0));
		return;
	}
	if (c->home == X4_HOME_PHASE1 && c->home_next) {
		home_phase(e, c, axis, X4_HOME_PHASE2, c->vref2, c->t_pending);
		return;
	}
	if (c->home == X4_HOME_PHASE2) {
		e->steps[axis] = 0;
		e->pos_base[axis] = 0;
		e->sync |= (u8)(1u << axis);
	}
	cut(c);
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
 * shortest low time after it. Minimums count from the real edges: a
 * configured pulse or space as configured; otherwise min_of() the plan and
 * X4_CLOCK_MIN_NS (or the configured pulse, for the space).
 */
static inline void rise_times(struct x4_engine *e, struct x4_chan *c,
			      u64 t_step, u64 now_ns)
{
	const struct x4_timing *t = &e->timing;
	u64 high = t->pulse_ns ? t->pulse_ns : c->half_ns;
	u64 interval = 2 * c->half_ns;

	c->high_min = t->pulse_ns ? high : min_of(high, X4_CLOCK_MIN_NS);
	if (c->n < c->run.last)
		interval = c->t_next - c->t_cur;
	c->t_pending = t_step + high;
	if (c->t_pending < now_ns + c->high_min)
		c->t_pending = now_ns + c->high_min;
	c->space_min = t->space_ns ? t->space_ns :
		min_of(interval > high ? interval - high : 0,
		       t->pulse_ns ? t->pulse_ns : X4_CLOCK_MIN_NS);
}

static void rise(struct x4_engine *e, struct x4_chan *c, u64 now_ns)
{
	const struct x4_plan *p = &c->run;
	u64 t_step = c->origin + c->t_cur;
	u8 hit = (e->inputs ^ c->halt_flip) & c->halt_mask;

	if (hit) {
		halted(e, c, hit);
		return;
	}
	if (c->n >= p->last && c->home) {
		/*
		 * A reference run plans sref + 1 steps: sref travelled
		 * without finding the switch.
		 */
		e->err[p->leader] |= X4_AXERR_REF_TRAVEL;
		cut(c);
		return;
	}
	c->stepping = step_axes(e, c);
	if (c->n < p->last) {
		c->t_next = next_time(c);
		c->half_ns = (c->t_next - c->t_cur) / 2;
	} else if (!c->n) {
		c->half_ns = p->single_half_ns;
	}
	/* (The last step keeps the step time of the one before.) */

	if (now_ns < t_step)
		now_ns = t_step;
	e->fired = c;
	e->edge_shifted = false;
	if (phase_mode(e)) {
		step_done(e, c, now_ns);
		c->space_min = min_of(2 * c->half_ns, 2 * X4_CLOCK_MIN_NS);
		keep_min(e, c, now_ns + c->space_min);
		smc_step(e, c, t_step);
		return;
	}
	e->data |= c->stepping;
	c->phase = X4_FALL;
	rise_times(e, c, t_step, now_ns);
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

/* Every event but fall(), and what runs next. */
static noinline void fire_event(struct x4_engine *e, struct x4_chan *c,
				u64 now_ns)
{
	switch (c->phase) {
	case X4_RISE:
		rise(e, c, now_ns);
		break;
	case X4_FALL: /* of the last step: the hold counts from the real edge */
		e->data &= (u8)~c->stepping;
		last_step_done(e, c, now_ns > c->t_pending ? now_ns : c->t_pending);
		break;
	case X4_SETUP:
		begin_setup(e, c, now_ns);
		break;
	case X4_END:
		end(e, c);
		break;
	case X4_QUEUED: /* more writes of the same instant (phase mode) */
		e->data = c->queue[c->qhead++];
		if (c->qhead == c->queued) {
			c->phase = c->phase_after;
			c->t_pending = c->t_after;
		}
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

	if (c->phase != X4_FALL || c->n >= c->run.last) {
		fire_event(e, c, now_ns);
		return;
	}
	fall(e, c, now_ns);
	/* A lone move's next step: its ramp state (ctl) is unchanged. */
	if (e->solo)
		e->due = c->t_pending;
	else
		schedule_all(e);
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
 * Emergency stop of channel c: no further step, its clocks drop now, its
 * axes lose their synchronization. The caller writes the port, then fires
 * what x4_engine_busy() still has.
 */
static void stop_chan(struct x4_engine *e, struct x4_chan *c)
{
	e->data &= (u8)~(c->run.axes ? clk_bits(c->run.axes) : 0);
	e->sync &= (u8)~c->run.axes;
	c->home = 0;
	c->t_pending = 0;
	end(e, c); /* phase mode: the rest patterns are queued, due at once */
}

/* Brake (or stop) the moves of the axes in `axes`. */
int x4_engine_halt(struct x4_engine *e, u8 axes, bool stop)
{
	int ret = X4_ERR_NOT_ACTIVE;
	int i;

	for (i = 0; i < X4_AXES; i++) {
		struct x4_chan *c = &e->ch[i];

		if (c->phase == X4_IDLE || !(c->run.axes & axes))
			continue;
		ret = X4_OK;
		if (stop) {
			stop_chan(e, c);
		} else {
			c->home = 0;
			brake_chan(c);
		}
	}
	schedule_all(e);
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

int x4_engine_set_switches(struct x4_engine *e, const struct x4_switches *sw)
{
	int i;

	if (sw->nc >= 1u << X4_INPUTS)
		return X4_ERR_PARAM_FAIL;
	for (i = 0; i < X4_AXES; i++)
		if (sw->ref[i] > X4_INPUTS || sw->plus[i] > X4_INPUTS ||
		    sw->minus[i] > X4_INPUTS)
			return X4_ERR_PARAM_FAIL;
	if (x4_engine_busy(e))
		return X4_ERR_IS_ACTIVE;
	e->sw = *sw;
	return X4_OK;
}

/*
 * The input pin levels (X4GetIn bits, 1 = HIGH), sampled by the glue on
 * every tick while a move watches switches, and before a move starts.
 */
void x4_engine_sense(struct x4_engine *e, u8 levels)
{
	int i;

	e->inputs = (levels ^ e->sw.nc) & ((1u << X4_INPUTS) - 1);
	for (i = 0; i < X4_AXES; i++) {
		struct x4_chan *c = &e->ch[i];
		u8 released = c->deferred & (u8)~e->inputs;

		c->halt_mask |= released; /* backed off: armed again */
		c->deferred &= (u8)~released;
	}
}

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

void x4_engine_axis(const struct x4_engine *e, int axis,
		    struct x4_axis_state *st)
{
	u8 bit = (u8)(1u << axis);
	u64 interval;
	int i;

	st->position = position(e, axis);
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
			st->velocity = (u32)x4_div(NSEC_PER_SEC_U64 *
						   p->abs_steps[axis],
						   interval *
						   p->abs_steps[p->leader]);
	}
}
