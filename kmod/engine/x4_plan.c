// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: profile mathematics (x4_plan.h). The profile is the
 * X4Step manual's (chapter 2) with the thesis' analytic step times, and
 * ProStep4's v0/a0/vm/ae/ve ramps in the same closed forms.
 */
#include "x4_plan.h"

#ifdef __KERNEL__
#include <linux/string.h>
#else
#include <string.h>
#endif

u64 x4_isqrt_from(u64 x, u64 x0)
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
	return x4_isqrt_from(x, 1ull << ((64 - __builtin_clzll(x) + 1) / 2));
}

/*
 * sqrt(x) of x in a ramp's units (4^sh ns^2), in ns. est: a value at or
 * above the root in the ramp's units (0: none).
 */
static u64 ramp_root(const struct x4_ramp *r, u64 x, u64 est)
{
	u64 q = est ? x4_isqrt_from(x, est) : x4_isqrt(x);

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

u64 x4_plan_time(const struct x4_plan *p, u64 n)
{
	if (n >= p->n_decel)
		return p->t_last + p->dec.s_ns -
		       ramp_u(&p->dec, p->last - n, 0);
	if (n < p->n_cruise)
		return ramp_u(&p->acc, n, 0) - p->acc.s_ns;
	return x4_plan_cruise_time(p, n);
}

u64 x4_plan_ramp_next(const struct x4_plan *p, u64 n1, u64 t_prev)
{
	u64 u;

	if (n1 >= p->n_decel) {
		/* The previous u is the estimate. */
		u = (p->t_last + p->dec.s_ns - t_prev) >> p->dec.sh;
		return p->t_last + p->dec.s_ns -
		       ramp_u(&p->dec, p->last - n1, u + 1);
	}
	u = (t_prev + p->acc.s_ns) >> p->acc.sh;
	if (u)
		u += x4_div(p->acc.k, 2 * u) + 1;
	return ramp_u(&p->acc, n1, u) - p->acc.s_ns;
}

/* One side of a profile's ramp: from or to rest speed v, acceleration a. */
static void plan_ramp(struct x4_ramp *r, u64 v, u64 a, u64 vm)
{
	u64 s, rem;

	r->sh = 0;
	/* u never exceeds vm / a: keep it below 2^31 units. */
	while ((x4_div(vm * X4_NSEC_PER_SEC, a) >> r->sh) >= (1ull << 31))
		r->sh++;
	s = x4_div(v * X4_NSEC_PER_SEC, a << r->sh);
	rem = v * X4_NSEC_PER_SEC - s * (a << r->sh);
	/* (s + rem / D)^2 to a unit: the fraction matters when units are us */
	r->c = s * s + x4_div(2 * s * rem + x4_div(rem * rem, a << r->sh),
			      a << r->sh);
	r->k = x4_div(2 * X4_NSEC_PER_SEC * X4_NSEC_PER_SEC, a << (2 * r->sh));
	r->s_ns = ramp_u(r, 0, 0);
}

/*
 * (x - y)^2 / (2 a vm) in ns: how much later than "at vm from 0" a ramp ends.
 * (x - y)^2 * 10^9 fits 64 bits while x < 135818 steps/s.
 */
_Static_assert(X4_VEL_MAX <= 135000, "ramp_lag() overflows");
static u64 ramp_lag(u64 x, u64 y, u64 a, u64 vm)
{
	return a ? x4_div((x - y) * (x - y) * X4_NSEC_PER_SEC, 2 * a * vm) : 0;
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
 * Whether d step intervals leave room for vm: d >= up2 / 2 a0 + down2 / 2 ae,
 * exactly. The ceilings sa and sd of the two terms settle it but where the
 * fractions add up; there the products stay below 2^55 (d < sa + sd, so
 * 2 a0 ae d < (a0 + ae) vm^2 + 4 a0 ae <= 2.1e16 at X4_VEL_MAX 100000).
 */
static bool room_for_vm(u64 d, u64 sa, u64 sd, u64 up2, u64 down2, u64 a0,
			u64 ae)
{
	if (d >= sa + sd)
		return true;
	if (!a0 || !ae)
		return false; /* one ramp: d >= sa + sd is exact for whole d */
	return 2 * a0 * ae * d >= ae * up2 + a0 * down2;
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
void x4_plan_profile(struct x4_plan *p, u64 steps, const struct x4_profile *f)
{
	u64 d = steps - 1, vm = f->vm, a0 = f->a0, ae = f->ae;
	u64 v0 = a0 ? f->v0 : vm, ve = ae ? f->ve : vm;
	u64 up2 = vm * vm - v0 * v0, down2 = vm * vm - ve * ve;
	u64 sa = a0 ? x4_div(up2 + 2 * a0 - 1, 2 * a0) : 0;
	u64 sd = ae ? x4_div(down2 + 2 * ae - 1, 2 * ae) : 0;
	u64 v1, vp2;

	p->kind = X4_PLAN_PROFILE;
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
	p->c_num = X4_NSEC_PER_SEC;
	p->c_den = 2 * vm;
	p->c_base = ramp_lag(vm, v0, a0, vm);
	/* A single step: at v0, or what the ramp reaches in half a step. */
	v1 = v0 ? v0 : x4_isqrt(a0);
	p->single_half_ns = x4_div(X4_NSEC_PER_SEC, 2 * (v1 < vm ? v1 : vm));
	if (room_for_vm(d, sa, sd, up2, down2, a0, ae)) {
		p->n_cruise = v0 < vm ? x4_div(up2, 2 * a0) + 1 : 0;
		p->n_decel = ve < vm ? d - x4_div(down2, 2 * ae) : d + 1;
		p->t_last = x4_plan_cruise_time(p, d) + ramp_lag(vm, ve, ae, vm);
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
 *  - short: too short for freq: accelerate over R = floor((D - P) / 2)
 *    whole steps, run the D - 2R >= P (P or P + 1) intervals between the
 *    ramps at the speed reached, brake mirrored; P = X4_PLATEAU_STEPS;
 *  - tiny: D <= P + 1 intervals (too few for a ramp of a whole step on
 *    each side) run at min(freq, sqrt(a)), the speed the ramp reaches
 *    after half a step, so short jogs never start with a jerk.
 * D = steps - 1 is the number of step intervals.
 */
void x4_plan_x4step(struct x4_plan *p, u64 steps, u32 freq, u32 ramp)
{
	u64 na2000 = (u64)freq * ramp; /* 2000 x steps of one ramp */
	u64 na = x4_div(na2000, 2000); /* whole steps of one ramp */
	u64 d = steps ? steps - 1 : 0;
	u64 x2, t_a, interval;

	memset(&p->acc, 0, sizeof(p->acc));
	memset(&p->prof, 0, sizeof(p->prof));
	p->kind = X4_PLAN_X4STEP;
	p->endless = !steps;
	p->last = steps ? d : X4_NO_STEP;
	p->acc.k = ramp ? x4_div(2000000000000000ull * ramp, freq) : 0;
	p->dec = p->acc;
	p->n_decel = p->endless ? X4_NO_STEP : d + 1;
	p->c_base = 0;
	p->c_m0 = 0;
	p->c_num = X4_NSEC_PER_SEC;
	p->c_den = 2ull * freq;
	p->t_last = 0;
	p->brake_steps = 0;
	p->n_cruise = 0;
	p->single_half_ns = x4_div(X4_NSEC_PER_SEC, 2ull * freq);

	if (!ramp)
		return;
	if (p->endless || 2000 * d >= 2 * na2000 + 2000 * X4_PLATEAU_STEPS) {
		p->n_cruise = na + 1;
		p->c_base = 500000ull * ramp;
		p->brake_steps = (u32)(na2000 > na * 2000 ? na + 1 : na);
		if (!p->endless) {
			p->n_decel = d - na;
			p->t_last = x4_div(d * X4_NSEC_PER_SEC, freq) +
				    1000000ull * ramp;
		}
	} else if (d >= X4_PLATEAU_STEPS + 2) {
		/* Both ramps of whole steps: an odd rest lengthens the plateau. */
		x2 = (d - X4_PLATEAU_STEPS) & ~1ull;
		t_a = x4_isqrt(x2 * p->acc.k / 2);
		p->n_cruise = x2 / 2 + 1;
		p->n_decel = d - x2 / 2;
		p->c_base = t_a;
		p->c_m0 = x2;
		p->c_num = t_a;
		p->c_den = 2 * x2;
		p->t_last = x4_div(t_a * (d + x2), x2);
		p->brake_steps = (u32)(x2 / 2);
	} else {
		interval = x4_isqrt(p->acc.k / 2);
		if (interval < x4_div(X4_NSEC_PER_SEC, freq))
			interval = x4_div(X4_NSEC_PER_SEC, freq);
		p->c_num = interval;
		p->c_den = 2;
		p->single_half_ns = interval / 2;
		p->brake_steps = 1;
	}
}

void x4_plan_axes(struct x4_plan *p, const s64 *steps)
{
	u32 longest = 0;
	u8 axes = 0, dirs = 0, leader = 0;
	int i;

	/* One pass: a path's segment start runs this in the timer. */
	for (i = 0; i < X4_AXES; i++) {
		s64 s = steps[i];
		u32 n = (u32)(s < 0 ? -s : s);

		p->abs_steps[i] = n;
		p->sign[i] = s < 0 ? -1 : 1;
		p->bres_inc[i] = 2ull * n;
		axes |= (n != 0) << i;
		dirs |= n && s > 0 ? X4_DIR_BIT(i) : 0;
		if (n > longest) {
			longest = n;
			leader = (u8)i;
		}
	}
	p->bres_inc[leader] = 0; /* the leader steps every time */
	p->bres_2l = 2ull * longest;
	p->axes = axes;
	p->dirs = dirs;
	p->leader = leader;
}

void x4_plan_search(struct x4_plan *p, u32 v, u32 ae, u32 ve)
{
	const struct x4_profile f = { v, v, v, 0, 0 };

	x4_plan_profile(p, 1, &f); /* constant speed v */
	p->endless = true;
	p->last = X4_NO_STEP;
	p->n_decel = X4_NO_STEP;
	p->prof.ae = ae;
	p->prof.ve = ve;
	if (ae)
		plan_ramp(&p->dec, ve, ae, v);
}

/*
 * Leader steps from step nb to rest (or to ve) along the plan's
 * deceleration, rounded up so that the stop never needs more than it;
 * 0: no ramp.
 */
static u64 brake_steps(const struct x4_plan *p, u64 nb)
{
	const struct x4_profile *f = &p->prof;
	u64 v2, ve2 = (u64)f->ve * f->ve;

	if (p->kind == X4_PLAN_X4STEP) {
		if (!p->dec.k)
			return 0;
		/* v^2 / 2a = nb while accelerating from rest */
		return nb < p->n_cruise ? nb : p->brake_steps;
	}
	/* From the speed at nb down to ve. */
	v2 = nb < p->n_cruise ? (u64)f->v0 * f->v0 + 2ull * f->a0 * nb :
				(u64)f->vm * f->vm;
	if (!f->ae || v2 <= ve2)
		return 0;
	return x4_div(v2 - ve2 + 2ull * f->ae - 1, 2ull * f->ae);
}

bool x4_plan_brake(struct x4_plan *p, u64 nb, u64 t_nb)
{
	u64 d;

	if (nb >= p->n_decel)
		return true; /* already braking */
	d = brake_steps(p, nb);
	if (!d)
		return false;
	if (!p->endless && nb + d >= p->last)
		return true; /* the planned ramp ends sooner */
	p->endless = false;
	p->last = nb + d;
	p->n_decel = nb;
	p->t_last = t_nb + ramp_u(&p->dec, d, 0) - p->dec.s_ns;
	return true;
}
