/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: continuous paths (x4_path.c), above the channels
 * (x4_chan.h) and below the event machine (x4_engine.c). A path is a queue of
 * straight segments that run back to back, at path speeds planned ahead
 * over the whole queue so that the queue as planned always ends at rest.
 *
 * Two contexts share the queue without a lock, as a single-producer
 * single-consumer ring:
 *  - the writer (a process writing segments) fills slots, publishes `tail`
 *    and plans: backward over the queue, the highest entry speed of each
 *    segment from which the rest of the queue can still stop (a bounded
 *    number of entries a push: where a pass has not come through yet, an
 *    entry is lower than it could be);
 *  - the timer (x4_engine_fire(), under the engine's lock) runs the segment
 *    at `head` and frees it by advancing `head`.
 * The timer reads a planned entry speed when the segment before it starts
 * (and again at a kick), and clamps it to what that segment's ramps can
 * reach, up and down: so every single value the writer stores keeps the
 * plan safe, whatever the timer reads while a pass runs (a lower override
 * the path is too fast to obey at once is braked toward at the limit),
 * and no loop over the queue runs under the lock.
 *
 * Probing (G38.2..G38.5): a probing segment (x4_segment.probe) watches the
 * path's probe input on every step tick, as a limit switch is watched. At
 * the first tick the input is in the awaited state (active: TOWARD;
 * inactive: AWAY) the latch takes every axis' coordinate (that of the step
 * at which the input changed: the tick's own step is not made yet), and
 * the path holds along the path and flushes its queue, as an abort does.
 * A segment that starts from rest with the input in that state already
 * trips at its first tick and makes no step; one that ends without a trip
 * lets the path go on, its latch not tripped.
 */
#ifndef X4_PATH_H
#define X4_PATH_H

#include "x4_state.h"

#define X4_PATH_OVERRIDE_MAX 200
/*
 * Entries a push plans at most: a queue shorter than the stop distance
 * raises all of them at every push, and the pass spreads that over the
 * pushes that follow.
 */
#define X4_PATH_PLAN_BUDGET 64
/*
 * What the pushes left of a pass goes on in time, in the writer's context
 * (the module: a work item, x4step_path.c): this many entries a jiffy, so
 * that it comes through long before the path gets there, also once the
 * writer stopped writing.
 */
#define X4_PATH_PLAN_WORK (8 * X4_PATH_PLAN_BUDGET)

/* The glue gives the queue's storage; only while no path is active. */
int x4_path_set_queue(struct x4_engine *e, struct x4_path_slot *slot,
		      u32 depth);
/* Whether a segment may join the path now: X4_OK or why not. */
int x4_path_check(const struct x4_engine *e, const struct x4_segment *s);
/* Free slots for the writer. */
u32 x4_path_room(const struct x4_engine *e);
/*
 * Writer context, no lock: queue a checked segment (room must be > 0),
 * publish it and plan backward, X4_PATH_PLAN_BUDGET entries at most. The
 * path starts at the next kick.
 */
void x4_path_push(struct x4_engine *e, const struct x4_segment *s);
/*
 * Writer context: go on with the backward pass, `budget` entries at most;
 * true while it has more to do.
 */
bool x4_path_plan(struct x4_engine *e, u32 budget);
/* Writer context: plan the whole queue again (after an override change). */
void x4_path_replan(struct x4_engine *e);
/*
 * Under the lock, after a push: start an idle path whose queue holds
 * segments (true: the channel begins, arm the timer), or let the running
 * segment end faster if the plan allows now (no event moves).
 */
bool x4_path_kick(struct x4_engine *e, u64 now_ns);
/* Under the lock: brake along the path to rest; abort: then flush it. */
int x4_path_hold(struct x4_engine *e, bool abort);
/* Under the lock: go on from a hold. */
int x4_path_resume(struct x4_engine *e, u64 now_ns);
/* Under the lock: the feed override, percent (writer: x4_path_replan()). */
int x4_path_set_override(struct x4_engine *e, u32 percent);
/*
 * The probe input, 1..5 (X4GetIn bit 0..4) or 0, active while LOW (nc):
 * only while no path is active, unless it stays as it is.
 */
int x4_path_set_probe(struct x4_engine *e, u8 input, bool nc);
/*
 * For the event machine (x4_engine.c): the running probing segment's input
 * is in the awaited state at channel c's pending step. True: that step is
 * not made (the path stood at rest: it ends there).
 */
bool x4_path_probe_hit(struct x4_engine *e, struct x4_chan *c);

/* An active path owns every axis of the output mode. */
bool x4_path_active(const struct x4_engine *e);

struct x4_path_status {
	u8 state; /* enum x4_path_state */
	u32 queued; /* segments in the queue, the running one included */
	u32 depth;
	u32 override;
	u32 speed; /* path units/s now */
	u64 tag; /* of the running (or next) segment; 0: none */
	u64 done;
	u64 starved;
};

void x4_path_get_status(const struct x4_engine *e, struct x4_path_status *st);

/* The timer's half, for the event machine (x4_engine.c), on channel 0. */
bool x4_path_next(struct x4_engine *e, struct x4_chan *c);
u64 x4_path_end_half(const struct x4_engine *e, u64 half_ns);
bool x4_path_ended(struct x4_engine *e, struct x4_chan *c);

#endif /* X4_PATH_H */
