/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: continuous paths (x4_path.c). A path is a queue of
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
 */
#ifndef X4_PATH_H
#define X4_PATH_H

#include "x4_check.h"

/* A queued segment and its planned entry speed (path units/s). */
struct x4_path_slot {
	struct x4_segment seg;
	u32 leader; /* the leader axis' steps: max |steps[i]| */
	u32 v_rate; /* the path speed of the port's fastest leader rate */
	u32 limit; /* its entry's limit: corner, reversal, top speed */
	u32 accel; /* its leader's acceleration, steps/s^2 */
	u64 two_as; /* 2 a length, path units: v^2 gained or lost along it */
	u32 entry; /* the writer stores it, the timer reads it (once) */
	u32 v_rev; /* the fastest entry an axis reversing into it allows */
	u8 dirs; /* the direction pins after it (X4_DIR_BIT) */
};

enum x4_path_state {
	X4_PATH_IDLE, /* nothing runs; segments queued start at the next kick */
	X4_PATH_RUN,
	X4_PATH_HOLDING, /* braking along the path to rest */
	X4_PATH_HELD, /* at rest on the path: resume, or abort */
};

/* Why the path's channel came to rest (x4_path.c, when it ends). */
enum x4_path_rest {
	X4_REST_CUT, /* stopped at once, or at a limit: the queue is flushed */
	X4_REST_DRY, /* the queue ran empty */
	X4_REST_HELD, /* a hold reached rest */
};

struct x4_path {
	struct x4_path_slot *slot; /* `depth` slots, from the glue */
	u32 depth; /* a power of 2; 0: no queue */
	u32 head; /* the running (or next) segment; the timer's */
	u32 tail; /* the next free slot; the writer's */
	u8 state; /* enum x4_path_state, under the engine's lock */
	u8 rest; /* enum x4_path_rest */
	bool abort; /* flush the queue once held */
	bool started; /* the segment at head has started */
	bool lonely; /* it started with nothing queued after it */
	u16 override; /* percent of v_max, 1..200 */
	/* The running segment, in its leader's steps and steps/s. */
	u32 leader;
	u32 accel;
	u32 exit; /* its planned end speed, fixed at its start */
	u32 pos; /* steps done before the running piece */
	u32 piece; /* steps of the running piece */
	u32 v_end; /* speed at the end of the running piece */
	u32 flushes; /* queues flushed: the glue's writers learn of them */
	/* The writer's backward pass (x4_path_plan()). */
	u32 plan; /* the slot whose entry it plans next */
	u32 plan_tail; /* the tail it started from */
	u64 planned; /* entries it planned: its cost, for the tests */
	u64 done; /* segments completed */
	u64 starved; /* refills that came after the path began to stop */
	u64 frac; /* the ns fraction the pieces' ends left out, 32.32 */
};

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

struct x4_engine;
struct x4_chan;

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

#endif /* X4_PATH_H */
