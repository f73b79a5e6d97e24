/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: the commands' arguments, their limits and the checks of
 * them. Pure functions without state: the module runs them on every ioctl
 * argument, and libx4step links this unit alone (not the engine) to give
 * the same answers before it asks the kernel.
 */
#ifndef X4_CHECK_H
#define X4_CHECK_H

#include "x4_types.h"

#define X4_AXES 4
#define X4_FREQ_MIN_HZ 10
#define X4_FREQ_MAX_HZ 20000
#define X4_RAMP_MAX_MS 1000
#define X4_STEPS_MAX 16777216
#define X4_DIR_SETUP_NS 100000u /* manual 5.2 */
#define X4_TIMING_MAX_NS 1000000u /* any configured time: at most 1 ms */
#define X4_PULSE_MIN_NS 1000u /* a configured pulse: at least 1 us */

/* Results: the numbers of the documented X4Step API. */
enum x4_result {
	X4_OK = 0,
	X4_ERR_NO_STEPS = 1,
	X4_ERR_FREQ_TOO_HIGH = 2,
	X4_ERR_FREQ_TOO_LOW = 3,
	X4_ERR_RAMP_TOO_HIGH = 4,
	X4_ERR_RAMP_FREQ = 5,
	X4_ERR_LPT_NOT_FOUND = 6,
	X4_ERR_NOT_ACTIVE = 7,
	X4_ERR_PARAM_FAIL = 8,
	X4_ERR_INIT_NOT_DONE = 9,
	X4_ERR_IS_ACTIVE = 10,
	X4_ERR_NOT_LOADED = 11,
	X4_ERR_IS_LOADED = 12,
	X4_ERR_STEPS_TOO_HIGH = 13,
	/*
	 * Not an X4Step code: the moves of the port together would need more
	 * port writes per second than its budget. The API reports it as
	 * X4_ERR_FREQ_TOO_HIGH; the module's errno for it is ERANGE.
	 */
	X4_ERR_RATE_BUDGET = 64,
};

/* An interpolated X4Load move. */
struct x4_move {
	s32 steps[X4_AXES];
	s32 freq_hz;
	s32 ramp_ms;
};

/*
 * The ramp of an axis' own moves (ProStep4): start at v0, accelerate with
 * a0 to vm, decelerate with ae to ve (steps/s, steps/s^2; 0: no ramp).
 */
struct x4_profile {
	u32 v0;
	u32 ve;
	u32 vm;
	u32 a0;
	u32 ae;
};
/*
 * The fastest profile move, reference run or path leader (steps/s): the
 * ceiling measured in QEMU -icount (tests/qemu/speed/speed_bench.cpp, `make
 * bench`): every edge, lateness as a bare hrtimer's, up to 160 000 steps/s;
 * at 200 000 the callback no longer keeps up. 100 000 leaves that margin
 * for PCs with slower port writes, one axis at it fits the default write
 * budget, and the ramp maths stay in 64 bits (x4_plan.c) up to 135 000.
 */
#define X4_VEL_MAX 100000
#define X4_ACC_MAX 1000000
#define X4_RAMP_TIME_MAX_S 3600 /* vm / a: keeps the ramp math in 64 bits */

/* A ramp between rest and v at a (0: none) takes longer than the limit. */
static inline bool x4_ramp_too_long(u32 v, u32 a)
{
	return a && (u64)v > (u64)X4_RAMP_TIME_MAX_S * a;
}

/*
 * Step timing of a port (driver boards need their own). pulse_ns 0 is
 * the X4Step behaviour: a symmetric clock (high = low time).
 */
struct x4_timing {
	u32 pulse_ns; /* clock high time, 0: half the step period */
	u32 space_ns; /* minimum clock low time between steps */
	u32 dir_setup_ns; /* directions out before the first step */
	u32 dir_hold_ns; /* directions held after the last step */
};

/* Output modes of a port. */
enum x4_output_mode {
	X4_MODE_CLOCK_DIR = 0, /* step and direction signals (X4Step) */
	X4_MODE_SMC_PHASE = 1, /* SMC800/SMC1500 half-step phase patterns */
	X4_MODE_SMC_PHASE_HOLD = 2, /* the same, reduced current at rest */
};

/*
 * A path segment (x4_path.h) as written by user space: the axes move by
 * `steps`, along `length` path units (any unit: user space chooses), at
 * path speeds (units/s) up to v_max, entering at most at v_entry (the
 * corner before it allows no more), accelerating and braking with accel
 * (units/s^2). The leader axis' steps lie at equal path distances. A
 * probing segment (probe) ends where the path's probe input changes to
 * the state it waits for (x4_path.h).
 */
struct x4_segment {
	s32 steps[X4_AXES];
	u32 length;
	u32 v_max;
	u32 v_entry;
	u32 accel;
	u64 tag;
	u8 probe; /* enum x4_probe */
};

/* What a probing segment waits for on the path's probe input. */
enum x4_probe {
	X4_PROBE_NONE, /* not a probing segment */
	X4_PROBE_TOWARD, /* the input becomes active (G38.2, G38.3) */
	X4_PROBE_AWAY, /* the input becomes inactive (G38.4, G38.5) */
};

#define X4_PATH_RAMP_MAX_S 1800 /* v_max / accel: 200 % fits the ramp math */
#define X4_PATH_VALUE_MAX 0x7fffffffu /* lengths, speeds: squares fit 64 bits */

/* |v|, also of S32_MIN (2^31). */
static inline u32 x4_abs_s32(s32 v)
{
	return v < 0 ? (u32)-(s64)v : (u32)v;
}

/* A segment's leader steps: the largest |steps[i]|. */
static inline u32 x4_segment_leader(const struct x4_segment *s)
{
	u32 leader = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (x4_abs_s32(s->steps[i]) > leader)
			leader = x4_abs_s32(s->steps[i]);
	return leader;
}

/* Reference run phases (x4_switch_home). */
#define X4_HOME_PHASE1 1
#define X4_HOME_PHASE2 2
#define X4_HOME_AUTO (X4_HOME_PHASE1 | X4_HOME_PHASE2)
#define X4_HOME_BRAKE 4 /* phase 1 brakes past REF along the axis' ae */

int x4_ramp_check(s32 freq_hz, s32 ramp_ms);
/* An X4Load move: frequency, ramp, then paths (the order of x4step.h). */
int x4_move_check(const struct x4_move *m);
int x4_profile_check(const struct x4_profile *p);
int x4_timing_check(const struct x4_timing *t, u8 mode);
/* A reference run's own arguments (not its axis, switch or output mode). */
int x4_home_check(u8 phases, s32 vref1, s32 vref2, u32 sref);
/*
 * A path segment's own arguments, whatever the port (the module checks
 * every record with it, libx4step every segment before it writes), in
 * this order: steps (X4_ERR_STEPS_TOO_HIGH, X4_ERR_NO_STEPS); `reserved`,
 * the record's fields that must be 0, and the values, the probe mode
 * among them (X4_ERR_PARAM_FAIL);
 * the leader's rate at v_max above X4_VEL_MAX (X4_ERR_RATE_BUDGET).
 */
int x4_segment_check(const struct x4_segment *s, u32 reserved);

#endif /* X4_CHECK_H */
