/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: why moves end, for the event stream (linux/x4step.h,
 * ABI 4). The engine keeps no event state: after each of its calls the
 * glue lets x4_track_update() compare it with what was seen last, and
 * from that and from what the glue asked for (a brake, a stop, a path's
 * abort) the tracker tells which events happened. It pushes them through
 * the glue's callback, under the glue's engine lock: the module's ring
 * (kmod/x4step_events.c) and libx4step's simulated port share this code.
 */
#ifndef X4_TRACK_H
#define X4_TRACK_H

#include "x4_engine.h"

struct x4_track {
	/* Append an event (X4STEP_EV_*) with the engine's positions. */
	void (*push)(struct x4_track *t, u32 type, u32 axes, u32 how,
		     u32 value, u32 flags);
	u8 busy; /* channels that ran */
	u8 err[X4_AXES]; /* the axes' error bits */
	u8 home[X4_AXES]; /* each channel's reference phase */
	bool ref_found[X4_AXES]; /* ... and whether its phase 1 saw REF */
	u8 how[X4_AXES]; /* X4STEP_END_* a channel's move ends with, or 0 */
	bool path; /* channel 0 runs a path */
	bool path_aborting; /* the path's end is an abort */
	u8 braked; /* channels whose brake was asked for */
	u8 stopped; /* channels stopped at once */
	u64 probe_trips; /* the path's probe trips told (x4_probe_latch) */
};

/* The channels that run moves of the axes in `axes`. */
u8 x4_track_chans(const struct x4_engine *e, u8 axes);
/* A brake of the moves of channels `chans` was asked for, by `source`. */
void x4_track_brake(struct x4_track *t, const struct x4_engine *e, u8 chans,
		    u32 source, u32 code);
/* The moves of channels `chans` are being stopped at once. */
void x4_track_stop(struct x4_track *t, u8 chans);
/*
 * Abort the path (hold, then flush: x4_path_hold()) and tell it: a held
 * path (no channel runs it) ends now, a running one when its channel
 * ends. The result of x4_path_hold().
 */
int x4_track_path_abort(struct x4_track *t, struct x4_engine *e);
/*
 * After the engine changed: what the changes mean. `c`: the engine fired
 * an event of channel c (its reference phase is worth a look), else -1;
 * `kind`: the moves that start now are of this X4STEP_KIND_*.
 */
void x4_track_update(struct x4_track *t, const struct x4_engine *e, int c,
		     u32 kind);
/* After the engine fired an event of channel c: update if it may matter. */
void x4_track_fired(struct x4_track *t, const struct x4_engine *e, int c);

#endif /* X4_TRACK_H */
