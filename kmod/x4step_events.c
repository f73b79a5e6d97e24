// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: the event stream (ABI 4). What happens on a port (moves started
 * and ended, brake requests, switches hit, controllers, the port going
 * away) is kept in a ring of X4_EVENTS records per port, filled under the
 * raw port lock from any context (the hard-irq step timer, the key
 * handler, the ioctls), without allocation. Each open file reads it with
 * read() from its own position, as evdev's clients and the GPIO v2
 * chardev's line requests do; a reader that fell more than the ring
 * behind resumes at the oldest event kept and sees the gap in the
 * sequence numbers.
 *
 * Moves end where the engine says so; why comes from what the glue did
 * (a brake or stop asked for) and from what the engine shows after each
 * of its calls: new error bits (a limit hit, a reference run too long), a
 * reference phase ended. x4_events_update_locked() compares it with what
 * was seen last, so the engine itself keeps no event state.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/fs.h>
#include <linux/ktime.h>
#include <linux/poll.h>
#include <linux/sched/signal.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/uaccess.h>

#include "x4step_dev.h"

int x4_events_alloc(struct x4_port *x4)
{
	x4->events = kcalloc(X4_EVENTS, sizeof(*x4->events), GFP_KERNEL);
	if (!x4->events)
		return -ENOMEM;
	x4->ev_seq = 1;
	return 0;
}

void x4_events_free(struct x4_port *x4)
{
	kfree(x4->events);
}

/* Append an event; its reader wake-up goes through the irq_work. */
static void x4_ev_push_locked(struct x4_port *x4, u32 type, u32 axes,
			      u32 how, u32 value, u32 flags)
{
	const struct x4_engine *e = &x4->eng;
	struct x4step_event *ev;
	u64 now = ktime_get_ns();
	int i;

	lockdep_assert_held(&x4->slock);
	ev = &x4->events[x4->ev_seq & (X4_EVENTS - 1)];
	memset(ev, 0, sizeof(*ev));
	ev->seq = x4->ev_seq++;
	/* Monotonic, also across CPUs: events are ordered by the lock. */
	if (now < x4->ev_time_ns)
		now = x4->ev_time_ns;
	x4->ev_time_ns = now;
	ev->timestamp_ns = now;
	ev->type = type;
	ev->axes = axes;
	ev->how = how;
	ev->value = value;
	ev->flags = flags;
	for (i = 0; i < X4_AXES; i++)
		ev->position[i] = (s32)(e->pos_base[i] + (u32)e->steps[i]);
	irq_work_queue(&x4->wake_work);
}

/* The channels that run moves of the axes in `axes`. */
u8 x4_events_chans_locked(struct x4_port *x4, u8 axes)
{
	u8 chans = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (x4->eng.busy & (1u << i) &&
		    x4_engine_chan_axes(&x4->eng, i) & axes)
			chans |= 1u << i;
	return chans;
}

static u8 x4_chan_axes(struct x4_port *x4, u8 chans)
{
	u8 axes = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (chans & (1u << i))
			axes |= x4->eng.ch[i].run.axes;
	return axes;
}

/* A brake of the moves of channels `chans` was asked for, by `source`. */
void x4_events_brake_locked(struct x4_port *x4, u8 chans, u32 source,
			    u32 code)
{
	lockdep_assert_held(&x4->slock);
	if (!chans)
		return;
	x4->ev_braked |= chans;
	x4_ev_push_locked(x4, X4STEP_EV_BRAKE, x4_chan_axes(x4, chans), source,
			  code, 0);
}

/* The moves of channels `chans` are being stopped at once. */
void x4_events_stop_locked(struct x4_port *x4, u8 chans)
{
	lockdep_assert_held(&x4->slock);
	x4->ev_stopped |= chans;
}

void x4_events_controller_locked(struct x4_port *x4, u32 how)
{
	x4_ev_push_locked(x4, X4STEP_EV_CONTROLLER, 0, how, 0, 0);
}

void x4_events_gone_locked(struct x4_port *x4)
{
	x4_ev_push_locked(x4, X4STEP_EV_PORT_GONE, 0, 0, 0, 0);
	x4->ev_closed = true;
}

/* The channel that runs axis i, or -1. */
static int x4_chan_of_axis(struct x4_port *x4, int i)
{
	int c;

	for (c = 0; c < X4_AXES; c++)
		if (x4->ev_busy & (1u << c) && x4->eng.ch[c].run.axes & (1u << i))
			return c;
	return -1;
}

/* Limit switches and reference runs: the error bits that became set. */
static void x4_ev_errors_locked(struct x4_port *x4)
{
	const struct x4_engine *e = &x4->eng;
	u8 new;
	int i, c;

	for (i = 0; i < X4_AXES; i++) {
		new = e->err[i] & ~x4->ev_err[i];
		x4->ev_err[i] = e->err[i];
		if (!new)
			continue;
		c = x4_chan_of_axis(x4, i);
		if (new & X4_AXERR_LIMIT_POS)
			x4_ev_push_locked(x4, X4STEP_EV_SWITCH, 1u << i,
					  X4STEP_SW_LIMIT_POS, e->sw.plus[i],
					  e->err[i] & X4_AXERR_AMBIGUOUS ?
					  X4STEP_EVF_AMBIGUOUS : 0);
		if (new & X4_AXERR_LIMIT_NEG)
			x4_ev_push_locked(x4, X4STEP_EV_SWITCH, 1u << i,
					  X4STEP_SW_LIMIT_NEG, e->sw.minus[i],
					  e->err[i] & X4_AXERR_AMBIGUOUS ?
					  X4STEP_EVF_AMBIGUOUS : 0);
		if (c < 0)
			continue;
		if (new & (X4_AXERR_LIMIT_POS | X4_AXERR_LIMIT_NEG))
			x4->ev_how[c] = X4STEP_END_LIMIT;
		else if (new & X4_AXERR_REF_TRAVEL)
			x4->ev_how[c] = X4STEP_END_REF_TRAVEL;
		else if (new & X4_AXERR_REF_PASSED)
			x4->ev_how[c] = X4STEP_END_REF_PASSED;
	}
}

/* Channel c's reference switch ended a phase of its reference run. */
static void x4_ev_ref_locked(struct x4_port *x4, int c)
{
	int axis = x4->eng.ch[c].run.leader;

	x4_ev_push_locked(x4, X4STEP_EV_SWITCH, 1u << axis, X4STEP_SW_REF,
			  x4->eng.sw.ref[axis], 0);
}

/*
 * Channel c's reference phase changed from `was` in the timer: phase 1,
 * having seen REF (x4_ev_ref_locked() then) and stopped or braked past
 * it, ended (phase 2 follows, or the run ends there), or REF ended phase
 * 2 (the axis is at 0 and synchronized).
 */
static void x4_ev_home_locked(struct x4_port *x4, int c, u8 was)
{
	const struct x4_chan *ch = &x4->eng.ch[c];

	if (x4->ev_how[c])
		return; /* a limit or the travel ended it */
	if (was == X4_HOME_PHASE1 && !ch->ref_found)
		return; /* braked or stopped before REF */
	if (was == X4_HOME_PHASE2)
		x4_ev_ref_locked(x4, c);
	if (!ch->home)
		x4->ev_how[c] = was == X4_HOME_PHASE2 ? X4STEP_END_HOMED :
							X4STEP_END_REF_FOUND;
}

/*
 * After the engine changed: what the changes mean. `fired`: the engine
 * fired an event of channel `c` (its reference phase is worth a look);
 * `kind`: the moves that start now are of this X4STEP_KIND_*.
 */
/* Why a path's channel came to rest: held, aborted, stopped, or done. */
static u8 x4_ev_path_end_locked(struct x4_port *x4)
{
	bool aborting = x4->path_aborting;

	if (x4->eng.path.state == X4_PATH_HELD)
		return X4STEP_END_HELD;
	x4->path_aborting = false;
	if (x4->ev_stopped & 1)
		return X4STEP_END_STOPPED;
	return aborting ? X4STEP_END_ABORTED : X4STEP_END_COMPLETED;
}

void x4_events_update_locked(struct x4_port *x4, int c, u32 kind)
{
	const struct x4_engine *e = &x4->eng;
	u8 ended, started, how, bit;
	int i;

	lockdep_assert_held(&x4->slock);
	if (memcmp(e->err, x4->ev_err, sizeof(x4->ev_err)))
		x4_ev_errors_locked(x4);
	for (i = 0; i < X4_AXES; i++) {
		u8 was = x4->ev_home[i];

		if (e->ch[i].ref_found && !x4->ev_ref_found[i] && e->ch[i].home)
			x4_ev_ref_locked(x4, i);
		x4->ev_ref_found[i] = e->ch[i].ref_found;
		x4->ev_home[i] = e->ch[i].home;
		if (i == c && was && was != e->ch[i].home)
			x4_ev_home_locked(x4, i, was);
	}
	ended = x4->ev_busy & ~e->busy;
	started = e->busy & ~x4->ev_busy;
	for (i = 0; i < X4_AXES; i++) {
		bit = 1u << i;
		if (!(ended & bit))
			continue;
		how = x4->ev_how[i];
		if (!how && !i && x4->ev_path)
			how = x4_ev_path_end_locked(x4);
		else if (!how)
			how = x4->ev_stopped & bit ? X4STEP_END_STOPPED :
			      x4->ev_braked & bit ? X4STEP_END_BRAKED :
			      X4STEP_END_COMPLETED;
		x4_ev_push_locked(x4, X4STEP_EV_MOVE_ENDED, e->ch[i].run.axes,
				  how, 0, 0);
		x4->ev_how[i] = 0;
	}
	x4->ev_braked &= ~ended;
	x4->ev_stopped &= ~ended;
	x4->ev_busy = e->busy;
	if (started & 1)
		x4->ev_path = kind == X4STEP_KIND_PATH;
	for (i = 0; i < X4_AXES; i++)
		if (started & (1u << i))
			x4_ev_push_locked(x4, X4STEP_EV_MOVE_STARTED,
					  e->ch[i].run.axes, kind, 0, 0);
}

/* What the engine may have changed by firing an event of channel c. */
void x4_events_fired_locked(struct x4_port *x4, int c)
{
	const struct x4_engine *e = &x4->eng;

	if (e->busy != x4->ev_busy || e->ch[c].home != x4->ev_home[c] ||
	    e->ch[c].ref_found != x4->ev_ref_found[c] ||
	    memcmp(e->err, x4->ev_err, sizeof(x4->ev_err)))
		x4_events_update_locked(x4, c, 0);
}

void x4_events_open(struct x4_port *x4, struct x4_file *xf)
{
	unsigned long flags;

	mutex_init(&xf->read_lock);
	raw_spin_lock_irqsave(&x4->slock, flags);
	xf->ev_next = x4->ev_seq; /* what happens from now on */
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/*
 * The next event for xf into *ev: 1, or 0 if there is none yet, -ENODEV
 * if there is none and the port is gone. A reader that fell behind
 * resumes at the oldest event kept.
 */
static int x4_ev_take(struct x4_port *x4, struct x4_file *xf,
		      struct x4step_event *ev)
{
	unsigned long flags;
	u64 oldest;
	int ret = 1;

	raw_spin_lock_irqsave(&x4->slock, flags);
	oldest = x4->ev_seq > X4_EVENTS ? x4->ev_seq - X4_EVENTS : 1;
	if (xf->ev_next < oldest)
		xf->ev_next = oldest;
	if (xf->ev_next < x4->ev_seq)
		*ev = x4->events[xf->ev_next & (X4_EVENTS - 1)];
	else
		ret = x4->ev_closed ? -ENODEV : 0;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ret;
}

/* Whether xf has an event to read, or the port is gone. */
static bool x4_ev_ready(struct x4_port *x4, struct x4_file *xf, bool *gone)
{
	unsigned long flags;
	bool ready;

	raw_spin_lock_irqsave(&x4->slock, flags);
	ready = xf->ev_next < x4->ev_seq;
	*gone = x4->ev_closed;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ready;
}

/*
 * POLLPRI while xf has an event to read; POLLERR | POLLHUP once the port
 * is gone and PORT_GONE is in the ring (one snapshot: a poller sees
 * POLLPRI for PORT_GONE whenever it sees the hang-up).
 */
__poll_t x4_events_poll(struct x4_port *x4, struct x4_file *xf)
{
	bool gone;
	__poll_t events = x4_ev_ready(x4, xf, &gone) ? EPOLLPRI : 0;

	return gone ? events | EPOLLERR | EPOLLHUP : events;
}

static bool x4_ev_wakeup(struct x4_port *x4, struct x4_file *xf)
{
	bool gone;

	return x4_ev_ready(x4, xf, &gone) || gone;
}

/* Event `seq` reached xf's reader (under slock: poll reads ev_next). */
static void x4_ev_consumed(struct x4_port *x4, struct x4_file *xf, u64 seq)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	xf->ev_next = seq + 1;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/* Copy the events there are into buf: bytes copied, or 0, or -errno. */
static ssize_t x4_ev_copy(struct x4_port *x4, struct x4_file *xf,
			  char __user *buf, size_t count)
{
	struct x4step_event ev;
	size_t done = 0;
	int ret;

	while (count - done >= sizeof(ev)) {
		ret = x4_ev_take(x4, xf, &ev);
		if (ret <= 0)
			return done ? done : ret;
		if (copy_to_user(buf + done, &ev, sizeof(ev)))
			return done ? done : -EFAULT;
		/* Only what reached the reader counts as read. */
		x4_ev_consumed(x4, xf, ev.seq);
		done += sizeof(ev);
	}
	return done;
}

/*
 * read(): whole events, as many as fit and are there; blocks for the
 * first unless O_NONBLOCK (EAGAIN, also while another thread reads the
 * same file). EINVAL for a buffer smaller than one event; ENODEV once
 * the port is gone and every event, PORT_GONE the last, has been read.
 * The file's read lock is not held while waiting.
 */
ssize_t x4_events_read(struct x4_port *x4, struct x4_file *xf,
		       struct file *file, char __user *buf, size_t count)
{
	bool nonblock = file->f_flags & O_NONBLOCK;
	ssize_t ret;

	if (count < sizeof(struct x4step_event))
		return -EINVAL;
	for (;;) {
		if (nonblock) {
			if (!mutex_trylock(&xf->read_lock))
				return -EAGAIN;
		} else if (mutex_lock_interruptible(&xf->read_lock)) {
			return -ERESTARTSYS;
		}
		ret = x4_ev_copy(x4, xf, buf, count);
		mutex_unlock(&xf->read_lock);
		if (ret)
			return ret;
		if (nonblock)
			return -EAGAIN;
		ret = wait_event_interruptible(x4->wait,
					       x4_ev_wakeup(x4, xf));
		if (ret)
			return ret;
	}
}
