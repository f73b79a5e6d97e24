// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: why moves end (x4_track.h), from what the engine shows
 * after each of its calls: new error bits (a limit hit, a reference run
 * too long), a reference phase ended, a path held or flushed, a probing
 * segment's input tripped.
 */
#include "x4_track.h"

#include "x4_chan.h"

#include <linux/x4step.h>
#ifdef __KERNEL__
#include <linux/string.h>
#else
#include <string.h>
#endif

u8 x4_track_chans(const struct x4_engine *e, u8 axes)
{
	u8 chans = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (e->busy & (1u << i) && x4_engine_chan_axes(e, i) & axes)
			chans |= 1u << i;
	return chans;
}

static u8 x4_track_chan_axes(const struct x4_engine *e, u8 chans)
{
	u8 axes = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (chans & (1u << i))
			axes |= e->ch[i].run.axes;
	return axes;
}

void x4_track_brake(struct x4_track *t, const struct x4_engine *e, u8 chans,
		    u32 source, u32 code)
{
	if (!chans)
		return;
	t->braked |= chans;
	t->push(t, X4STEP_EV_BRAKE, x4_track_chan_axes(e, chans), source, code,
		0);
}

void x4_track_stop(struct x4_track *t, u8 chans)
{
	t->stopped |= chans;
}

/*
 * The axes of channel i's move in the event stream: a path's are every
 * axis of the output mode (it owns them all while it is active), not the
 * segment's that runs when it starts or comes to rest.
 */
static u8 x4_track_move_axes(const struct x4_track *t,
			     const struct x4_engine *e, int i)
{
	return !i && t->path ? x4_chan_mode_axes(e) : e->ch[i].run.axes;
}

int x4_track_path_abort(struct x4_track *t, struct x4_engine *e)
{
	bool held = e->path.state == X4_PATH_HELD;
	int ret = x4_path_hold(e, true);

	if (ret)
		return ret;
	if (held)
		t->push(t, X4STEP_EV_MOVE_ENDED, x4_chan_mode_axes(e),
			X4STEP_END_ABORTED, 0, 0);
	else if (x4_path_active(e))
		t->path_aborting = true; /* its end says so */
	return X4_OK;
}

/* The channel that runs axis i, or -1. */
static int x4_track_chan_of_axis(const struct x4_track *t,
				 const struct x4_engine *e, int i)
{
	int c;

	for (c = 0; c < X4_AXES; c++)
		if (t->busy & (1u << c) && e->ch[c].run.axes & (1u << i))
			return c;
	return -1;
}

/* Limit switches and reference runs: the error bits that became set. */
static void x4_track_errors(struct x4_track *t, const struct x4_engine *e)
{
	u32 amb;
	u8 new;
	int i, c;

	for (i = 0; i < X4_AXES; i++) {
		new = e->err[i] & ~t->err[i];
		t->err[i] = e->err[i];
		if (!new)
			continue;
		c = x4_track_chan_of_axis(t, e, i);
		amb = e->err[i] & X4_AXERR_AMBIGUOUS ? X4STEP_EVF_AMBIGUOUS : 0;
		if (new & X4_AXERR_LIMIT_POS)
			t->push(t, X4STEP_EV_SWITCH, 1u << i,
				X4STEP_SW_LIMIT_POS, e->sw.plus[i], amb);
		if (new & X4_AXERR_LIMIT_NEG)
			t->push(t, X4STEP_EV_SWITCH, 1u << i,
				X4STEP_SW_LIMIT_NEG, e->sw.minus[i], amb);
		if (c < 0)
			continue;
		if (new & (X4_AXERR_LIMIT_POS | X4_AXERR_LIMIT_NEG))
			t->how[c] = X4STEP_END_LIMIT;
		else if (new & X4_AXERR_REF_TRAVEL)
			t->how[c] = X4STEP_END_REF_TRAVEL;
		else if (new & X4_AXERR_REF_PASSED)
			t->how[c] = X4STEP_END_REF_PASSED;
	}
}

/* Channel c's reference switch ended a phase of its reference run. */
static void x4_track_ref(struct x4_track *t, const struct x4_engine *e, int c)
{
	int axis = e->ch[c].run.leader;

	t->push(t, X4STEP_EV_SWITCH, 1u << axis, X4STEP_SW_REF,
		e->sw.ref[axis], 0);
}

/*
 * Channel c's reference phase changed from `was` in the timer: phase 1,
 * having seen REF (x4_track_ref() then) and stopped or braked past it,
 * ended (phase 2 follows, or the run ends there), or REF ended phase 2
 * (the axis is at 0 and synchronized).
 */
static void x4_track_home(struct x4_track *t, const struct x4_engine *e,
			  int c, u8 was)
{
	const struct x4_chan *ch = &e->ch[c];

	if (t->how[c])
		return; /* a limit or the travel ended it */
	if (was == X4_HOME_PHASE1 && !ch->ref_found)
		return; /* braked or stopped before REF */
	if (was == X4_HOME_PHASE2)
		x4_track_ref(t, e, c);
	if (!ch->home)
		t->how[c] = was == X4_HOME_PHASE2 ? X4STEP_END_HOMED :
						    X4STEP_END_REF_FOUND;
}

/* Why a path's channel came to rest: held, aborted, stopped, or done. */
static u8 x4_track_path_end(struct x4_track *t, const struct x4_engine *e)
{
	bool aborting = t->path_aborting;

	if (e->path.state == X4_PATH_HELD)
		return X4STEP_END_HELD;
	t->path_aborting = false;
	if (t->stopped & 1)
		return X4STEP_END_STOPPED;
	return aborting ? X4STEP_END_ABORTED : X4STEP_END_COMPLETED;
}

/*
 * A probing segment's input tripped: a switch event, and the path, whose
 * queue the trip flushes, ends ABORTED (x4_track_path_end()).
 */
static void x4_track_probe(struct x4_track *t, const struct x4_engine *e)
{
	t->probe_trips = e->path.latch.trips;
	t->push(t, X4STEP_EV_SWITCH, x4_chan_mode_axes(e), X4STEP_SW_PROBE,
		e->path.probe_input, 0);
	t->path_aborting = true; /* the trip flushes the path */
}

void x4_track_update(struct x4_track *t, const struct x4_engine *e, int c,
		     u32 kind)
{
	u8 ended, started, how, bit, was;
	int i;

	if (e->path.latch.trips != t->probe_trips)
		x4_track_probe(t, e);
	if (memcmp(e->err, t->err, sizeof(t->err)))
		x4_track_errors(t, e);
	for (i = 0; i < X4_AXES; i++) {
		was = t->home[i];
		if (e->ch[i].ref_found && !t->ref_found[i] && e->ch[i].home)
			x4_track_ref(t, e, i);
		t->ref_found[i] = e->ch[i].ref_found;
		t->home[i] = e->ch[i].home;
		if (i == c && was && was != e->ch[i].home)
			x4_track_home(t, e, i, was);
	}
	ended = t->busy & ~e->busy;
	started = e->busy & ~t->busy;
	for (i = 0; i < X4_AXES; i++) {
		bit = 1u << i;
		if (!(ended & bit))
			continue;
		how = t->how[i];
		if (!how && !i && t->path)
			how = x4_track_path_end(t, e);
		else if (!how)
			how = t->stopped & bit ? X4STEP_END_STOPPED :
			      t->braked & bit ? X4STEP_END_BRAKED :
			      X4STEP_END_COMPLETED;
		t->push(t, X4STEP_EV_MOVE_ENDED, x4_track_move_axes(t, e, i),
			how, 0, 0);
		t->how[i] = 0;
	}
	t->braked &= ~ended;
	t->stopped &= ~ended;
	t->busy = e->busy;
	if (started & 1)
		t->path = kind == X4STEP_KIND_PATH;
	for (i = 0; i < X4_AXES; i++)
		if (started & (1u << i))
			t->push(t, X4STEP_EV_MOVE_STARTED,
				x4_track_move_axes(t, e, i), kind, 0, 0);
}

void x4_track_fired(struct x4_track *t, const struct x4_engine *e, int c)
{
	if (e->busy != t->busy || e->ch[c].home != t->home[c] ||
	    e->ch[c].ref_found != t->ref_found[c] ||
	    e->path.latch.trips != t->probe_trips ||
	    memcmp(e->err, t->err, sizeof(t->err)))
		x4_track_update(t, e, c, 0);
}
