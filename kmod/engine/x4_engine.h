/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: turns moves into a stream of port events. The public
 * interface of kmod/engine/ for the module's glue and the host tests.
 *
 * Plain C with no kernel dependency, no floating point and no allocation:
 * the module runs it in its hrtimer callback and the host unit tests run
 * the very same code. Times are integer nanoseconds since the engine's
 * epoch (the glue maps them to ktime); every edge time is computed from
 * the step index directly, so error never accumulates.
 *
 * Output levels are logical pin levels (1 = HIGH at the connector); the
 * port glue applies hardware inversions and user polarity in one place.
 *
 * The engine's files, each owning one job:
 *   x4_check.c   the commands' arguments and their checks (libx4step too)
 *   x4_plan.c    profile mathematics: plans, T(n), brake distances
 *   x4_engine.c  channels: commands, the event state machine, Bresenham,
 *                the write budget and the minimum pulse and space
 *   x4_switch.c  reference and limit switches, reference runs
 *   x4_phase.c   the SMC800/SMC1500 half-step phase output
 *   x4_status.c  what the axes are doing, for GET_AXES
 *   x4_path.c    continuous paths: the segment queue and its planner
 */
#ifndef X4_ENGINE_H
#define X4_ENGINE_H

#include "x4_check.h"
#include "x4_path.h"
#include "x4_plan.h"

/*
 * The X4Step clock's shortest half period (20 kHz): without a configured
 * pulse, no clock high or low time is shorter than this, however late the
 * timer; where a move plans shorter ones (a profile move above 20 000
 * steps/s), none is shorter than half of what it plans.
 */
#define X4_CLOCK_MIN_NS 25000u
/*
 * Port writes per second that the moves of one port may need together,
 * by default (x4_engine.budget): a leader step is two writes (clock up and
 * down), a phase-mode step one per motor. See docs/timing.md for where the
 * figure comes from.
 */
#define X4_WRITE_BUDGET 200000u

/* Control outputs as pin levels. */
#define X4_CTL_SIGNAL1 0x01 /* pin 1 */
#define X4_CTL_SIGNAL2 0x02 /* pin 14 */
#define X4_CTL_BOOST 0x04 /* pin 16: high while ramping */
#define X4_CTL_AKTIV 0x08 /* pin 17: high while a move runs */

#define X4_SMC_AXES 3 /* motors X, Y, Z: select bits 0x00, 0x40, 0x80 */

/* Reference and limit switches: inputs 1..5 (X4GetIn bit 0..4), 0 none. */
struct x4_switches {
	u8 ref[X4_AXES];
	u8 plus[X4_AXES];
	u8 minus[X4_AXES];
	u8 nc; /* bit k: input k + 1 is active while LOW */
};
#define X4_INPUTS 5

/* Per-axis state and error bits, as ProStep4's asr and error registers. */
#define X4_AX_RUN 0x001
#define X4_AX_SYNC 0x002
#define X4_AX_ERROR 0x004
#define X4_AX_REF1 0x008
#define X4_AX_REF2 0x010
#define X4_AX_ACCEL 0x100
#define X4_AX_CRUISE 0x200
#define X4_AX_DECEL 0x400
#define X4_AXERR_REF_TRAVEL 0x1
#define X4_AXERR_LIMIT_POS 0x2
#define X4_AXERR_LIMIT_NEG 0x4
#define X4_AXERR_AMBIGUOUS 0x8
#define X4_AXERR_REF_PASSED 0x10
/*
 * A reference run's phase 2 starts this long after phase 1 stood: a stop
 * without a ramp leaves the rotor ringing, and a switch bouncing; phase 2
 * starts from rest and watches a settled switch (GRBL pauses 250 ms).
 */
#define X4_HOME_SETTLE_NS 50000000ull

struct x4_axis_state {
	s32 position;
	u32 state; /* X4_AX_* */
	u32 error; /* X4_AXERR_* */
	u32 velocity; /* steps/s */
};

enum x4_phase {
	X4_IDLE, /* nothing pending */
	X4_SETUP, /* move started: directions out, first step pending */
	X4_RISE, /* clock rising edge of step n pending */
	X4_FALL, /* clock falling edge of step n pending */
	X4_END, /* end of move pending */
	X4_QUEUED, /* phase mode: more writes of the same instant */
};

/*
 * A channel runs one move: an interpolated one over several axes, or an
 * axis' own move. Channel i runs the moves whose lowest axis is i, so
 * moves on disjoint axes never share one.
 */
struct x4_chan {
	struct x4_plan run;
	enum x4_phase phase;
	bool no_steps; /* braked before its first step */
	u8 stepping; /* clock bits set by the current step */
	u8 ctl; /* AKTIV while it runs, BOOST while it ramps */
	u8 halt_mask; /* inputs that end the move ... */
	u8 halt_flip; /* ... when (inputs ^ halt_flip) & halt_mask */
	u8 deferred; /* limits left behind: armed once they are released */
	u8 home; /* X4_HOME_PHASE1/2 running, 0: no reference run */
	u8 home_next; /* phase 2 follows phase 1 */
	bool home_brake; /* phase 1 brakes past REF along the axis' ae */
	bool ref_found; /* phase 1 found REF: it stops, or brakes past it */
	u8 ref_bit;
	u64 origin; /* engine time of leader step 0 */
	u64 n; /* current leader step index */
	u64 t_cur; /* T(n) */
	u64 t_next; /* T(n + 1), when n < last */
	u64 t_pending; /* engine time of the pending event */
	u64 half_ns; /* high time of the current step */
	u64 high_min; /* shortest high time of the current step */
	u64 space_min; /* shortest low time (phase mode: step) after it */
	u32 rate; /* port writes per second at the move's top speed */
	u32 home_rate; /* a reference run's, at its faster phase */
	u64 bres[X4_AXES]; /* Bresenham accumulators of the minor axes */
	u8 queue[X4_SMC_AXES]; /* phase mode: more writes due at t_pending */
	u8 queued;
	u8 qhead;
	u8 phase_after; /* the phase when the queue is done, due at t_after */
	u64 t_after;
	s32 vref2; /* reference run: phase 2 speed */
	u32 sref;
	bool path; /* runs the path (x4_path.c): channel 0 only */
	bool path_cut; /* ... and was stopped: the path ends here */
	u8 dir_fresh; /* clocks whose direction changed at dir_ready - setup */
	u64 dir_ready; /* ... and may step from then on */
};

struct x4_engine {
	struct x4_chan ch[X4_AXES];
	struct x4_plan next; /* the loaded (preloaded) move */
	bool loaded;
	u8 busy; /* bit i: channel i runs */
	bool solo; /* only one channel runs */
	/* The channel whose event is due first (copies must not run). */
	struct x4_chan *cur;
	u64 due; /* its time */
	u64 ends; /* counts moves that came to an end */

	u8 data; /* current pin levels */
	u8 ctl;
	struct x4_timing timing;
	u8 mode; /* enum x4_output_mode */
	u8 smc_phase[X4_SMC_AXES]; /* half-step table index of each motor */

	s64 steps[X4_AXES]; /* signed steps since the axis' last start */
	u32 pos_base[X4_AXES]; /* coordinate = pos_base + steps, mod 2^32 */
	u8 sync; /* bit i: axis i's coordinate is referenced */
	u8 err[X4_AXES]; /* X4_AXERR_* */
	struct x4_profile prof[X4_AXES];
	struct x4_switches sw;
	u8 inputs; /* active switches (after NO/NC), last sampled */

	/*
	 * A late event never makes a pulse, space or phase step shorter than
	 * its minimum: the channel's remaining schedule moves instead. These
	 * count how often and by how much (the glue reads and clears them).
	 */
	u64 shifts;
	u64 shifted_ns;
	struct x4_chan *fired; /* the channel of the last step edge fired */
	bool edge_shifted; /* ... and that edge moved its schedule already */
	u32 budget; /* port writes per second, all moves together; 0: none */
	struct x4_path path;
};

void x4_engine_init(struct x4_engine *e);
int x4_engine_configure(struct x4_engine *e, const struct x4_timing *t,
			u8 mode);
int x4_engine_load(struct x4_engine *e, const struct x4_move *m);
int x4_engine_start(struct x4_engine *e, u64 now_ns);
int x4_engine_endless(struct x4_engine *e, s32 axis, bool negative,
		      s32 freq_hz, s32 ramp_ms, u64 now_ns);
int x4_engine_brake(struct x4_engine *e);
int x4_engine_stop(struct x4_engine *e);
int x4_engine_halt(struct x4_engine *e, u8 axes, bool stop);
void x4_engine_set_signal(struct x4_engine *e, u8 signal_bit, bool high);
void x4_engine_fire(struct x4_engine *e, u64 now_ns);
void x4_engine_written(struct x4_engine *e, u64 t_ns);
u64 x4_engine_slack(const struct x4_engine *e);

int x4_engine_set_profile(struct x4_engine *e, s32 axis,
			  const struct x4_profile *p);
/* Host only: the module plans outside its lock (below). */
int x4_engine_goto(struct x4_engine *e, u8 axes, const s32 *target,
		   bool relative, u64 now_ns);
/*
 * x4_engine_goto() in two steps, so that the module can plan (64-bit
 * divisions and square roots for up to four axes) outside its raw lock, on
 * a copy of the engine, and start under the lock: start_goto re-checks what
 * may have changed meanwhile (the axes idle, the budget, the coordinates).
 */
struct x4_goto {
	u8 axes; /* the axes commanded */
	u8 moving; /* those not at their target already */
	u64 rate; /* port writes per second at the top speeds */
	s32 from[X4_AXES]; /* the coordinates planned from */
	struct x4_plan plan[X4_AXES];
};

int x4_engine_plan_goto(const struct x4_engine *e, u8 axes,
			const s32 *target, bool relative, struct x4_goto *g);
int x4_engine_start_goto(struct x4_engine *e, const struct x4_goto *g,
			 u64 now_ns);
int x4_engine_home(struct x4_engine *e, s32 axis, u8 phases, s32 vref1,
		   s32 vref2, u32 sref, u64 now_ns);
int x4_engine_set_position(struct x4_engine *e, u8 axes, const s32 *pos);
int x4_engine_set_switches(struct x4_engine *e, const struct x4_switches *sw);
void x4_engine_sense(struct x4_engine *e, u8 levels);
void x4_engine_axis(const struct x4_engine *e, int axis,
		    struct x4_axis_state *st);
/* The axes channel i owns: all of them for a path, else its move's. */
u8 x4_engine_chan_axes(const struct x4_engine *e, int i);

/* Busy: a move runs, or writes of its last instant are still due. */
static inline bool x4_engine_busy(const struct x4_engine *e)
{
	return e->busy;
}

/* Engine time at which x4_engine_fire() is due; valid while busy. */
static inline u64 x4_engine_due(const struct x4_engine *e)
{
	return e->due;
}

/*
 * The pending event ends the clock pulse that the event of channel `fired`
 * began: the only event worth waiting for in the timer callback.
 */
static inline bool x4_engine_pulse_pending(const struct x4_engine *e,
					   const struct x4_chan *fired)
{
	return e->cur == fired && fired->phase == X4_FALL;
}

/*
 * The pending event is a step that a switch may forbid, or one of a
 * reference run (whose phase 2 starts from the REF level the brake of
 * phase 1 ended at): sample first.
 */
static inline bool x4_engine_rise_watched(const struct x4_engine *e)
{
	return e->cur->phase == X4_RISE &&
	       (e->cur->halt_mask | e->cur->deferred | e->cur->home);
}

/* The active switches at input levels (X4GetIn bits): after NO/NC. */
static inline u8 x4_engine_active(const struct x4_engine *e, u8 levels)
{
	return (levels ^ e->sw.nc) & ((1u << X4_INPUTS) - 1);
}

/* What the port shows at rest: 1 byte, or one per SMC motor (3). */
int x4_engine_rest_writes(const struct x4_engine *e, u8 *bytes);

#endif /* X4_ENGINE_H */
