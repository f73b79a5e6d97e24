/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step engine core: turns X4Step moves into a stream of port events.
 *
 * Plain C with no kernel dependency, no floating point and no allocation:
 * the module runs it in its hrtimer callback and the host unit tests run
 * the very same code. Times are integer nanoseconds since the engine's
 * epoch (the glue maps them to ktime); every edge time is computed from
 * the step index directly, so error never accumulates.
 *
 * Output levels are logical pin levels (1 = HIGH at the connector); the
 * port glue applies hardware inversions and user polarity in one place.
 */
#ifndef X4_ENGINE_H
#define X4_ENGINE_H

#ifdef __KERNEL__
#include <linux/types.h>
#else
#include <stdbool.h>
#include <stdint.h>
typedef uint8_t u8;
typedef int8_t s8;
typedef uint32_t u32;
typedef int32_t s32;
typedef uint64_t u64;
typedef int64_t s64;
#endif

#define X4_AXES 4
#define X4_FREQ_MIN_HZ 10
#define X4_FREQ_MAX_HZ 20000
#define X4_RAMP_MAX_MS 1000
#define X4_STEPS_MAX 16777216
/*
 * Short moves that cannot reach their frequency still run this many steps
 * at constant speed between the ramps (manual, chapter 2): two full steps
 * of a half-stepping drive, enough for the rotor to follow the change from
 * accelerating to braking torque without being torn off.
 */
#define X4_PLATEAU_STEPS 4
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
};

/* Data register: axis i has direction on bit 2i, clock on bit 2i+1. */
#define X4_DIR_BIT(axis) ((u8)(1u << (2 * (axis))))
#define X4_CLK_BIT(axis) ((u8)(2u << (2 * (axis))))
#define X4_CLK_MASK 0xaa
#define X4_DIR_MASK 0x55

/* Control outputs as pin levels. */
#define X4_CTL_SIGNAL1 0x01 /* pin 1 */
#define X4_CTL_SIGNAL2 0x02 /* pin 14 */
#define X4_CTL_BOOST 0x04 /* pin 16: high while ramping */
#define X4_CTL_AKTIV 0x08 /* pin 17: high while a move runs */

/*
 * Step timing of a port (issue: driver boards need their own). pulse_ns 0
 * is the X4Step behaviour: a symmetric clock (high = low time).
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
#define X4_SMC_AXES 3 /* motors X, Y, Z: select bits 0x00, 0x40, 0x80 */

/* One output event, as the tests record them: e->data and e->ctl after
 * x4_engine_fire(), at the time x4_engine_due() said before it.
 */
struct x4_event {
	u64 t_ns; /* when, since the engine epoch */
	u8 data; /* data register after the event */
	u8 ctl; /* control outputs after the event */
};

/* An interpolated X4Load move. */
struct x4_move {
	s32 steps[X4_AXES];
	s32 freq_hz;
	s32 ramp_ms;
};

/*
 * The leader axis' schedule, precomputed at load so that starting a
 * preloaded move needs no work. T(n) is the time of leader step n
 * (n = 0 is the first step, T(0) = 0) relative to the move's origin:
 *   n <  n_cruise: T(n) = sqrt(n * k)                (acceleration)
 *   n <  n_decel:  T(n) = c_base + (2n - c_m0) * c_num / c_den (cruise)
 *   n >= n_decel:  T(n) = t_last - sqrt((last - n) * k)  (deceleration)
 * with k = 2 / a in ns^2 per step, a = freq / ramp (thesis eq. 4.6).
 */
struct x4_plan {
	u64 last; /* index of the last leader step; U64_MAX: endless */
	u64 k_ns2;
	u64 n_cruise;
	u64 n_decel;
	u64 c_base;
	u64 c_m0;
	u64 c_num;
	u64 c_den;
	u64 t_last;
	u32 bres_2l; /* 2 * leader steps, for the interpolation */
	u64 single_half_ns; /* high time of a one-step move */
	u32 brake_steps; /* steps to stop from cruise along the ramp */
	u32 abs_steps[X4_AXES];
	u32 bres_inc[X4_AXES]; /* 2 * steps of a minor axis, else 0 */
	u8 dirs; /* direction bits of the axes that move */
	u8 leader;
	u8 axes; /* axes with a non-zero path */
	s8 sign[X4_AXES];
	bool endless;
};

enum x4_phase {
	X4_IDLE, /* nothing pending */
	X4_SETUP, /* move started: directions out, first step pending */
	X4_RISE, /* clock rising edge of step n pending */
	X4_FALL, /* clock falling edge of step n pending */
	X4_END, /* end of move pending */
	X4_QUEUED, /* phase mode: more writes of the same instant */
};

struct x4_engine {
	struct x4_plan run; /* the move in progress */
	struct x4_plan next; /* the loaded (preloaded) move */
	bool loaded;

	enum x4_phase phase;
	bool no_steps; /* braked before its first step */
	u64 origin; /* engine time of leader step 0 */
	u64 n; /* current leader step index */
	u64 t_cur; /* T(n) */
	u64 t_next; /* T(n + 1), when n < last */
	u64 t_pending; /* engine time of the pending event */
	u64 half_ns; /* high time of the current step */
	u32 bres[X4_AXES]; /* Bresenham accumulators of the minor axes */
	u8 stepping; /* clock bits set by the current step */

	u8 data; /* current pin levels */
	u8 ctl;
	struct x4_timing timing;
	u8 mode; /* enum x4_output_mode */
	u8 smc_phase[X4_SMC_AXES]; /* half-step table index of each motor */
	u8 queue[X4_SMC_AXES]; /* phase mode: more writes due at t_pending */
	u8 queued;
	u8 qhead;
	u8 phase_after; /* the phase when the queue is done, due at t_after */
	u64 t_after;
	s32 steps[X4_AXES]; /* signed steps since the last start */
};

void x4_engine_init(struct x4_engine *e);
int x4_engine_configure(struct x4_engine *e, const struct x4_timing *t,
			u8 mode);
int x4_move_check(const struct x4_move *m);
int x4_ramp_check(s32 freq_hz, s32 ramp_ms);
int x4_engine_load(struct x4_engine *e, const struct x4_move *m);
int x4_engine_start(struct x4_engine *e, u64 now_ns);
int x4_engine_endless(struct x4_engine *e, s32 axis, bool negative,
		      s32 freq_hz, s32 ramp_ms, u64 now_ns);
int x4_engine_brake(struct x4_engine *e);
int x4_engine_stop(struct x4_engine *e);
void x4_engine_set_signal(struct x4_engine *e, u8 signal_bit, bool high);
void x4_engine_fire(struct x4_engine *e, u64 now_ns);

/* Busy: a move runs, or writes of its last instant are still due. */
static inline bool x4_engine_busy(const struct x4_engine *e)
{
	return e->phase != X4_IDLE;
}

/* Engine time at which x4_engine_fire() is due; valid while busy. */
static inline u64 x4_engine_due(const struct x4_engine *e)
{
	return e->t_pending;
}

/* What the port shows at rest: 1 byte, or one per SMC motor (3). */
int x4_engine_rest_writes(const struct x4_engine *e, u8 *bytes);

/* Exposed for the unit tests. */
u64 x4_isqrt(u64 x);
u64 x4_plan_time(const struct x4_plan *p, u64 n);

#endif /* X4_ENGINE_H */
