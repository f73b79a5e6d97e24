/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: profile mathematics. A plan is the leader axis' schedule
 * of one move, computed once when the move is loaded or started, so that
 * running it costs O(1) per step: T(n), the time of leader step n, comes
 * from n in closed form (thesis eq. 4.6), in integer nanoseconds, and no
 * error accumulates. Pure functions on a plan; they call nothing but each
 * other (x4_plan.c), and know nothing of channels, ports or switches.
 */
#ifndef X4_PLAN_H
#define X4_PLAN_H

#include "x4_check.h"

/*
 * Short X4Step moves that cannot reach their frequency still run at least
 * this many step intervals at constant speed between the ramps (manual,
 * chapter 2): two full steps of a half-stepping drive, enough for the rotor
 * to follow the change from accelerating to braking torque without being
 * torn off. One more where the rest of the distance is odd, so that both
 * ramps take whole steps and mirror each other.
 */
#define X4_PLATEAU_STEPS 4
#define X4_NO_STEP (~(u64)0)

/*
 * One side of a ramp: the time to reach step m from the ramp's virtual
 * rest point is u(m) = sqrt(c + m * k), with c and k in units of 4^sh ns^2
 * (sh > 0 only for ramps longer than about 2 s, whose squares would not
 * fit 64 bits in ns^2). s_ns = u(0): a start (or stop) at non-zero speed.
 */
struct x4_ramp {
	u64 c;
	u64 k;
	u64 s_ns;
	u8 sh;
};

/* What a plan's ramps are, and so how it brakes. */
enum x4_plan_kind {
	/*
	 * X4Step (X4Load, endless moves): from and to rest, linear in
	 * frequency with a = freq / ramp, or no ramp at all.
	 */
	X4_PLAN_X4STEP,
	/*
	 * ProStep4 (an axis' own moves): v0 -a0-> vm -ae-> ve, struct
	 * x4_profile; a reference run's search (x4_plan_search()) too.
	 */
	X4_PLAN_PROFILE,
};

/*
 * The leader axis' schedule. T(n) is the time of leader step n (n = 0 is
 * the first step, T(0) = 0) relative to the move's origin:
 *   n <  n_cruise: T(n) = u_acc(n) - acc.s_ns                 (accelerate)
 *   n <  n_decel:  T(n) = c_base + (2n - c_m0) * c_num / c_den    (cruise)
 *   n >= n_decel:  T(n) = t_last - (u_dec(last - n) - dec.s_ns)    (brake)
 * X4Step moves ramp from and to rest (c = s = 0) with k = 2 / a in ns^2
 * per step, a = freq / ramp (thesis eq. 4.6).
 */
struct x4_plan {
	u8 kind; /* enum x4_plan_kind */
	u64 last; /* index of the last leader step; X4_NO_STEP: endless */
	struct x4_ramp acc;
	struct x4_ramp dec;
	u64 n_cruise;
	u64 n_decel;
	u64 c_base;
	u64 c_m0;
	u64 c_num;
	u64 c_den;
	u64 t_last;
	u64 bres_2l; /* 2 * leader steps (a goto's can pass 2^32) */
	u64 single_half_ns; /* high time of a one-step move */
	u32 brake_steps; /* X4Step: steps to stop from cruise along the ramp */
	struct x4_profile prof; /* X4_PLAN_PROFILE: its ramp */
	u32 abs_steps[X4_AXES];
	u64 bres_inc[X4_AXES]; /* 2 * steps of a minor axis, else 0 */
	u8 dirs; /* direction bits of the axes that move */
	u8 leader;
	u8 axes; /* axes with a non-zero path */
	s8 sign[X4_AXES];
	bool endless;
};

/* Data register: axis i has direction on bit 2i, clock on bit 2i+1. */
#define X4_DIR_BIT(axis) ((u8)(1u << (2 * (axis))))
#define X4_CLK_BIT(axis) ((u8)(2u << (2 * (axis))))
#define X4_CLK_MASK 0xaa
#define X4_DIR_MASK 0x55

u64 x4_isqrt(u64 x);
/* floor(sqrt(x)) by Newton's method from an estimate x0 > 0 (any). */
u64 x4_isqrt_from(u64 x, u64 x0);

/* The axes' paths (signed steps): leader, directions, Bresenham increments. */
void x4_plan_axes(struct x4_plan *p, const s64 *steps);
/* An X4Step move of `steps` leader steps (0: endless). */
void x4_plan_x4step(struct x4_plan *p, u64 steps, u32 freq_hz, u32 ramp_ms);
/* A ProStep4 move of `steps` >= 1 leader steps. */
void x4_plan_profile(struct x4_plan *p, u64 steps, const struct x4_profile *f);

/*
 * A reference run's search: leader steps at the constant speed v without
 * end (the channel counts the travel), able to brake along ae to ve when
 * asked (ae 0: it cannot; it stops).
 */
void x4_plan_search(struct x4_plan *p, u32 v, u32 ae, u32 ve);

/* T(n), from n alone. */
u64 x4_plan_time(const struct x4_plan *p, u64 n);
/* T(n1) on a ramp, from T(n1 - 1) = t_prev as the root's first estimate. */
u64 x4_plan_ramp_next(const struct x4_plan *p, u64 n1, u64 t_prev);

/*
 * Brake from leader step nb (due at t_nb) to rest, or to the profile's ve,
 * along the plan's deceleration; a plan braking already keeps its ramp.
 * False when the plan has no ramp to brake along: then step nb must not
 * come.
 */
bool x4_plan_brake(struct x4_plan *p, u64 nb, u64 t_nb);

static inline u64 x4_plan_cruise_time(const struct x4_plan *p, u64 n)
{
	return p->c_base + x4_div((2 * n - p->c_m0) * p->c_num, p->c_den);
}

/*
 * T(n1) from T(n1 - 1) = t_prev, in O(1): the running engine's next step.
 * *ramp: step n1 lies on a ramp (BOOST).
 */
static inline u64 x4_plan_next(struct x4_plan *p, u64 n1, u64 t_prev,
			       bool *ramp)
{
	u64 m, q;

	*ramp = n1 >= p->n_decel || n1 < p->n_cruise;
	if (*ramp)
		return x4_plan_ramp_next(p, n1, t_prev);
	/* Rebase so that endless moves never overflow. */
	m = 2 * n1 - p->c_m0;
	if (m >= p->c_den) {
		q = x4_div(m, p->c_den);
		p->c_m0 += q * p->c_den;
		p->c_base += q * p->c_num;
	}
	return x4_plan_cruise_time(p, n1);
}

#endif /* X4_PLAN_H */
