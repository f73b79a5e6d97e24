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
 * The engine's files, each owning one job, by level: a file calls only
 * the levels below its own (kmod/engine/sources.mk lists them,
 * tests/check-layers.sh checks), and tells the one above what happened by
 * what it returns. Each level's header includes only the ones below it.
 *   0 x4_check.c   the commands' arguments and their checks (libx4step too)
 *   1 x4_plan.c    profile mathematics: plans, T(n), brake distances
 *   2 x4_chan.c    channels: begin, brake and cut a move, the write budget
 *                  and frequency checks, the switches that end a move
 *   3 x4_switch.c  reference and limit switches, reference runs
 *     x4_path.c    continuous paths: the segment queue and its planner
 *     x4_phase.c   the SMC800/SMC1500 half-step phase output
 *     x4_status.c  what the axes are doing, for GET_AXES
 *   4 x4_engine.c  the commands (x4_engine_*) and the event state machine:
 *                  Bresenham, the minimum pulse and space (this header)
 *   5 x4_req.c     the module's requests as engine calls (x4_req.h)
 *     x4_track.c   why moves end, for the event stream (x4_track.h)
 * The state they share is x4_state.h.
 */
#ifndef X4_ENGINE_H
#define X4_ENGINE_H

#include "x4_state.h"
#include "x4_path.h"
#include "x4_phase.h"
#include "x4_status.h"
#include "x4_switch.h"

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
int x4_engine_set_position(struct x4_engine *e, u8 axes, const s32 *pos);
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
 * The pending event is a step that a switch may forbid (a probing
 * segment's input too), or one of a reference run (whose phase 2 starts from the REF level the brake of
 * phase 1 ended at): sample first.
 */
static inline bool x4_engine_rise_watched(const struct x4_engine *e)
{
	return e->cur->phase == X4_RISE &&
	       (e->cur->halt_mask | e->cur->deferred | e->cur->home |
		e->cur->probe_mask);
}

#endif /* X4_ENGINE_H */
