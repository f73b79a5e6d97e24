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

static u64 cruise_time(const struct x4_plan *p, u64 n)
{
	return p->c_base + x4_div((2 * n - p->c_m0) * p->c_num, p->c_den);
}

u64 x4_plan_time(const struct x4_plan *p, u64 n)
{
	if (n >= p->n_decel)
		return p->t_last - x4_isqrt((p->last - n) * p->k_ns2);
	if (n < p->n_cruise)
		return x4_isqrt(n * p->k_ns2);
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

/*
 * Plan the leader's schedule for `steps` steps (0: endless) at freq_hz
 * with ramp_ms ramps. Four shapes:
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

	p->endless = !steps;
	p->last = steps ? d : NO_STEP;
	p->k_ns2 = ramp ? x4_div(2000000000000000ull * ramp, freq) : 0;
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
		t_a = x4_isqrt(x2 * p->k_ns2 / 2);
		p->n_cruise = x2 / 2 + 1;
		p->n_decel = d - x2 / 2;
		p->c_base = t_a;
		p->c_m0 = x2;
		p->c_num = t_a;
		p->c_den = 2 * x2;
		p->t_last = x4_div(t_a * (d + x2), x2);
		p->brake_steps = (u32)((x2 + 1) / 2);
	} else {
		interval = x4_isqrt(p->k_ns2 / 2);
		if (interval < x4_div(NSEC_PER_SEC_U64, freq))
			interval = x4_div(NSEC_PER_SEC_U64, freq);
		p->c_num = interval;
		p->c_den = 2;
		p->single_half_ns = interval / 2;
		p->brake_steps = 1;
	}
}

static void plan_axes(struct x4_plan *p, const s32 *steps)
{
	u32 longest = 0;
	int i;

	p->dirs = 0;
	p->axes = 0;
	p->leader = 0;
	for (i = 0; i < X4_AXES; i++) {
		u32 n = steps[i] < 0 ? (u32)-steps[i] : (u32)steps[i];

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
	p->bres_2l = 2 * longest;
	for (i = 0; i < X4_AXES; i++)
		p->bres_inc[i] = i == p->leader ? 0 : 2 * p->abs_steps[i];
}

void x4_engine_init(struct x4_engine *e)
{
	memset(e, 0, sizeof(*e));
	e->timing.dir_setup_ns = X4_DIR_SETUP_NS;
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

int x4_engine_load(struct x4_engine *e, const struct x4_move *m)
{
	int ret = x4_move_check(m);

	if (!ret)
		ret = timing_check(e, m->freq_hz);
	if (!ret && e->mode != X4_MODE_CLOCK_DIR && m->steps[3])
		ret = X4_ERR_PARAM_FAIL; /* the SMC boards drive 3 motors */
	if (ret)
		return ret;
	if (e->loaded)
		return X4_ERR_IS_LOADED;
	plan_axes(&e->next, m->steps);
	plan_profile(&e->next, e->next.abs_steps[e->next.leader],
		     (u32)m->freq_hz, (u32)m->ramp_ms);
	e->loaded = true;
	return X4_OK;
}

/* Begin the move in e->run: directions and AKTIV go out at now_ns. */
static void begin(struct x4_engine *e, u64 now_ns)
{
	int i;

	e->phase = X4_SETUP;
	e->no_steps = false;
	e->n = 0;
	e->t_cur = 0;
	e->t_pending = now_ns;
	e->origin = now_ns + e->timing.dir_setup_ns;
	for (i = 0; i < X4_AXES; i++) {
		e->steps[i] = 0;
		e->bres[i] = e->run.bres_2l / 2;
	}
}

int x4_engine_start(struct x4_engine *e, u64 now_ns)
{
	if (!e->loaded)
		return X4_ERR_NOT_LOADED;
	if (x4_engine_busy(e))
		return X4_ERR_IS_ACTIVE;
	e->run = e->next;
	e->loaded = false;
	begin(e, now_ns);
	return X4_OK;
}

int x4_engine_endless(struct x4_engine *e, s32 axis, bool negative,
		      s32 freq_hz, s32 ramp_ms, u64 now_ns)
{
	s32 steps[X4_AXES] = { 0 };
	int ret;

	if (axis < 1 || axis > X4_AXES ||
	    (e->mode != X4_MODE_CLOCK_DIR && axis > X4_SMC_AXES))
		return X4_ERR_PARAM_FAIL;
	ret = x4_ramp_check(freq_hz, ramp_ms);
	if (!ret)
		ret = timing_check(e, freq_hz);
	if (ret)
		return ret;
	if (e->loaded)
		return X4_ERR_IS_LOADED;
	if (x4_engine_busy(e))
		return X4_ERR_IS_ACTIVE;
	steps[axis - 1] = negative ? -1 : 1;
	plan_axes(&e->run, steps);
	plan_profile(&e->run, 0, (u32)freq_hz, (u32)ramp_ms);
	begin(e, now_ns);
	return X4_OK;
}

/*
 * Decelerate from leader step nb (whose time t_nb is already fixed) to
 * rest along the ramp. The pending event keeps its time, so the glue never
 * has to re-arm its timer: only what happens at that time changes.
 */
static void brake_from(struct x4_engine *e, u64 nb, u64 t_nb)
{
	struct x4_plan *p = &e->run;
	u64 d;

	if (nb >= p->n_decel)
		return; /* already braking */
	if (!p->k_ns2)
		d = 0;
	else if (nb < p->n_cruise)
		d = nb; /* v^2 / 2a = nb while accelerating from rest */
	else
		d = p->brake_steps;
	if (!d) {
		/* No ramp to follow: step nb - 1 was the last. */
		if (e->phase == X4_SETUP)
			e->no_steps = true;
		else if (e->phase == X4_RISE)
			e->phase = X4_END; /* at the time step nb was due */
		else
			p->last = nb - 1;
		return;
	}
	if (!p->endless && nb + d >= p->last)
		return; /* the planned ramp ends sooner */
	p->endless = false;
	p->last = nb + d;
	p->n_decel = nb;
	p->t_last = t_nb + x4_isqrt(d * p->k_ns2);
}

int x4_engine_brake(struct x4_engine *e)
{
	switch (e->phase) {
	case X4_IDLE:
		return X4_ERR_NOT_ACTIVE;
	case X4_SETUP:
		brake_from(e, 0, 0);
		break;
	case X4_RISE:
		brake_from(e, e->n, e->t_cur);
		break;
	case X4_FALL:
		if (e->n < e->run.last)
			brake_from(e, e->n + 1, e->t_next);
		break;
	case X4_END:
		break;
	case X4_QUEUED: /* brake what comes after this instant's writes */
		e->phase = e->phase_after;
		if (e->phase != X4_IDLE)
			x4_engine_brake(e);
		e->phase_after = e->phase;
		e->phase = X4_QUEUED;
		break;
	}
	return X4_OK;
}

void x4_engine_set_signal(struct x4_engine *e, u8 signal_bit, bool high)
{
	if (high)
		e->ctl |= signal_bit;
	else
		e->ctl &= (u8)~signal_bit;
}

/* Clock bits of leader step n: the leader and the minors due now. */
static u8 step_axes(struct x4_engine *e)
{
	const struct x4_plan *p = &e->run;
	u8 clk = X4_CLK_BIT(p->leader);
	int i;

	e->steps[p->leader] += p->sign[p->leader];
	/* Rounded Bresenham: never more than 1/2 step off the line. */
	for (i = 0; i < X4_AXES; i++) {
		if (!p->bres_inc[i])
			continue; /* the leader, or an axis that does not move */
		e->bres[i] += p->bres_inc[i];
		if (e->bres[i] >= p->bres_2l) {
			e->bres[i] -= p->bres_2l;
			e->steps[i] += p->sign[i];
			clk |= X4_CLK_BIT(i);
		}
	}
	return clk;
}

/*
 * T(n + 1), from T(n) in e->t_cur, in O(1). BOOST is high for the
 * interval when T(n + 1) lies on a ramp.
 */
static u64 next_time(struct x4_engine *e)
{
	struct x4_plan *p = &e->run;
	u64 n1 = e->n + 1;
	u64 m, q;

	if (n1 >= p->n_decel) {
		e->ctl |= X4_CTL_BOOST;
		/* sqrt((last - n) k) = t_last - T(n) is the estimate. */
		return p->t_last - isqrt_from((p->last - n1) * p->k_ns2,
					      p->t_last - e->t_cur);
	}
	if (n1 < p->n_cruise) {
		e->ctl |= X4_CTL_BOOST;
		if (!e->t_cur)
			return x4_isqrt(n1 * p->k_ns2);
		return isqrt_from(n1 * p->k_ns2,
				  e->t_cur + p->k_ns2 / (2 * e->t_cur) + 1);
	}
	e->ctl &= (u8)~X4_CTL_BOOST;
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

static bool phase_mode(const struct x4_engine *e)
{
	return e->mode != X4_MODE_CLOCK_DIR;
}

/*
 * Writes due at time t: the first now, the rest queued at the same t,
 * before whatever e->phase and e->t_pending were going to be next.
 */
static void emit(struct x4_engine *e, const u8 *bytes, int n, u64 t)
{
	int i;

	e->data = bytes[0];
	if (n < 2)
		return;
	e->queued = 0;
	e->qhead = 0;
	for (i = 1; i < n; i++)
		e->queue[e->queued++] = bytes[i];
	e->phase_after = e->phase;
	e->t_after = e->t_pending;
	e->phase = X4_QUEUED;
	e->t_pending = t;
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

static noinline void smc_energize(struct x4_engine *e, u64 now_ns)
{
	u8 bytes[X4_SMC_AXES];

	emit(e, bytes, smc_patterns(e, e->run.axes, false, bytes), now_ns);
}

static noinline void begin_setup(struct x4_engine *e, u64 now_ns)
{
	const struct x4_plan *p = &e->run;

	e->ctl |= X4_CTL_AKTIV;
	if (p->n_cruise)
		e->ctl |= X4_CTL_BOOST;
	/* Count the setup time from when the directions really go out. */
	if (now_ns > e->t_pending)
		e->origin = now_ns + e->timing.dir_setup_ns;
	e->phase = e->no_steps ? X4_END : X4_RISE;
	e->t_pending = e->origin;
	if (phase_mode(e))
		smc_energize(e, now_ns);
	else /* axes that do not move keep their direction level */
		e->data = (u8)((e->data & ~dir_bits(p->axes)) | p->dirs);
}

static noinline void smc_rest(struct x4_engine *e, u64 t)
{
	u8 bytes[X4_SMC_AXES];

	emit(e, bytes, x4_engine_rest_writes(e, bytes), t);
}

static void end(struct x4_engine *e)
{
	u64 t = e->t_pending;

	e->ctl &= (u8)~(X4_CTL_AKTIV | X4_CTL_BOOST);
	e->phase = X4_IDLE;
	if (phase_mode(e))
		smc_rest(e, t);
}

/* After the last step: end now, or after the hold (and settle) time. */
static noinline void last_step_done(struct x4_engine *e, u64 t)
{
	if (!e->timing.dir_hold_ns && !phase_mode(e)) {
		end(e);
		return;
	}
	/* Phase mode: give the motor its last step period to settle. */
	e->phase = X4_END;
	e->t_pending = t + e->timing.dir_hold_ns +
		       (phase_mode(e) ? 2 * e->half_ns : 0);
}

/* After step n's clock fell (or its pattern went out): what comes next. */
static inline void step_done(struct x4_engine *e, u64 t)
{
	if (e->n >= e->run.last) {
		last_step_done(e, t);
		return;
	}
	e->n++;
	e->t_cur = e->t_next;
	e->phase = X4_RISE;
	e->t_pending = e->origin + e->t_cur;
}

/* Phase mode: walk the table of each motor that steps, write them. */
static noinline void smc_step(struct x4_engine *e, u64 t)
{
	u8 bytes[X4_SMC_AXES];
	int m;

	for (m = 0; m < X4_SMC_AXES; m++)
		if (e->stepping & X4_CLK_BIT(m))
			e->smc_phase[m] = (e->smc_phase[m] + e->run.sign[m]) & 7;
	emit(e, bytes, smc_patterns(e, clk_axes(e->stepping), false, bytes), t);
}

static noinline void rise(struct x4_engine *e, u64 now_ns)
{
	const struct x4_plan *p = &e->run;
	u64 t_step = e->origin + e->t_cur;

	e->stepping = step_axes(e);
	if (e->n < p->last) {
		e->t_next = next_time(e);
		e->half_ns = (e->t_next - e->t_cur) / 2;
	} else if (!e->n) {
		e->half_ns = p->single_half_ns;
	}
	/* (The last step keeps the step time of the one before.) */

	if (phase_mode(e)) {
		step_done(e, t_step);
		smc_step(e, t_step);
		return;
	}
	e->data |= e->stepping;
	e->phase = X4_FALL;
	/* A configured pulse is a minimum: count it from the real edge. */
	e->t_pending = e->timing.pulse_ns ?
		(now_ns > t_step ? now_ns : t_step) + e->timing.pulse_ns :
		t_step + e->half_ns;
}

/*
 * Apply the pending event (due at x4_engine_due(), fired at now_ns) and
 * plan the next.
 */
void x4_engine_fire(struct x4_engine *e, u64 now_ns)
{
	/* The two hot cases first: a clock edge falls, a step rises. */
	if (e->phase == X4_FALL) {
		e->data &= X4_DIR_MASK; /* only stepping clocks were high */
		step_done(e, e->t_pending);
		/* A configured space is a minimum too: from the real edge. */
		if (e->timing.space_ns && e->phase == X4_RISE &&
		    now_ns + e->timing.space_ns > e->t_pending)
			e->t_pending = now_ns + e->timing.space_ns;
	} else if (e->phase == X4_RISE) {
		rise(e, now_ns);
	} else if (e->phase == X4_SETUP) {
		begin_setup(e, now_ns);
	} else if (e->phase == X4_END) {
		end(e);
	} else if (e->phase == X4_QUEUED) {
		/* More writes of the same instant (phase mode). */
		e->data = e->queue[e->qhead++];
		if (e->qhead == e->queued) {
			e->phase = e->phase_after;
			e->t_pending = e->t_after;
		}
	}
}

/*
 * Emergency stop: no further step; clocks, BOOST and AKTIV drop now. The
 * caller writes the port, then fires what x4_engine_busy() still has.
 */
int x4_engine_stop(struct x4_engine *e)
{
	if (e->phase == X4_IDLE)
		return X4_ERR_NOT_ACTIVE;
	e->data &= X4_DIR_MASK;
	e->t_pending = 0;
	end(e); /* phase mode: the rest patterns are queued, due at once */
	return X4_OK;
}
