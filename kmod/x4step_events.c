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
 * reference phase ended. The engine's tracker (engine/x4_track.c, shared
 * with libx4step's simulated port) compares it with what was seen last,
 * so the engine itself keeps no event state.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/fs.h>
#include <linux/ktime.h>
#include <linux/poll.h>
#include <linux/sched/signal.h>
#include <linux/slab.h>
#include <linux/string.h>
#include <linux/uaccess.h>

#include "x4step_events.h"

static void x4step_ev_track_push(struct x4_track *t, u32 type, u32 axes,
				 u32 how, u32 value, u32 flags);

int x4step_events_alloc(struct x4_port *x4)
{
	x4->events = kcalloc(X4_EVENTS, sizeof(*x4->events), GFP_KERNEL);
	if (!x4->events)
		return -ENOMEM;
	x4->ev_seq = 1;
	x4->ev.push = x4step_ev_track_push;
	return 0;
}

void x4step_events_free(struct x4_port *x4)
{
	kfree(x4->events);
}

/* Append an event; its reader wake-up goes through the irq_work. */
static void x4step_ev_push_locked(struct x4_port *x4, u32 type, u32 axes,
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

/* The events the tracker (engine/x4_track.c) tells of. */
static void x4step_ev_track_push(struct x4_track *t, u32 type, u32 axes,
				 u32 how, u32 value, u32 flags)
{
	x4step_ev_push_locked(container_of(t, struct x4_port, ev), type, axes,
			      how, value, flags);
}

/* The channels that run moves of the axes in `axes`. */
u8 x4step_events_chans_locked(struct x4_port *x4, u8 axes)
{
	lockdep_assert_held(&x4->slock);
	return x4_track_chans(&x4->eng, axes);
}

/* A brake of the moves of channels `chans` was asked for, by `source`. */
void x4step_events_brake_locked(struct x4_port *x4, u8 chans, u32 source,
				u32 code)
{
	lockdep_assert_held(&x4->slock);
	x4_track_brake(&x4->ev, &x4->eng, chans, source, code);
}

/* The moves of channels `chans` are being stopped at once. */
void x4step_events_stop_locked(struct x4_port *x4, u8 chans)
{
	lockdep_assert_held(&x4->slock);
	x4_track_stop(&x4->ev, chans);
}

void x4step_events_controller_locked(struct x4_port *x4, u32 how)
{
	x4step_ev_push_locked(x4, X4STEP_EV_CONTROLLER, 0, how, 0, 0);
}

void x4step_events_gone_locked(struct x4_port *x4)
{
	x4step_ev_push_locked(x4, X4STEP_EV_PORT_GONE, 0, 0, 0, 0);
	x4->ev_closed = true;
}

/*
 * After the engine changed: what the changes mean (x4_track_update()).
 * `c`: the engine fired an event of channel c; `kind`: the moves that
 * start now are of this X4STEP_KIND_*.
 */
void x4step_events_update_locked(struct x4_port *x4, int c, u32 kind)
{
	lockdep_assert_held(&x4->slock);
	x4_track_update(&x4->ev, &x4->eng, c, kind);
}

/* What the engine may have changed by firing an event of channel c. */
void x4step_events_fired_locked(struct x4_port *x4, int c)
{
	x4_track_fired(&x4->ev, &x4->eng, c);
}

void x4step_events_open(struct x4_port *x4, struct x4_file *xf)
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
static int x4step_ev_take(struct x4_port *x4, struct x4_file *xf,
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
static bool x4step_ev_ready(struct x4_port *x4, struct x4_file *xf, bool *gone)
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
__poll_t x4step_events_poll(struct x4_port *x4, struct x4_file *xf)
{
	bool gone;
	__poll_t events = x4step_ev_ready(x4, xf, &gone) ? EPOLLPRI : 0;

	return gone ? events | EPOLLERR | EPOLLHUP : events;
}

static bool x4step_ev_wakeup(struct x4_port *x4, struct x4_file *xf)
{
	bool gone;

	return x4step_ev_ready(x4, xf, &gone) || gone;
}

/* Event `seq` reached xf's reader (under slock: poll reads ev_next). */
static void x4step_ev_consumed(struct x4_port *x4, struct x4_file *xf, u64 seq)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	xf->ev_next = seq + 1;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/* Copy the events there are into buf: bytes copied, or 0, or -errno. */
static ssize_t x4step_ev_copy(struct x4_port *x4, struct x4_file *xf,
			      char __user *buf, size_t count)
{
	struct x4step_event ev;
	size_t done = 0;
	int ret;

	while (count - done >= sizeof(ev)) {
		ret = x4step_ev_take(x4, xf, &ev);
		if (ret <= 0)
			return done ? done : ret;
		if (copy_to_user(buf + done, &ev, sizeof(ev)))
			return done ? done : -EFAULT;
		/* Only what reached the reader counts as read. */
		x4step_ev_consumed(x4, xf, ev.seq);
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
ssize_t x4step_events_read(struct x4_port *x4, struct x4_file *xf,
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
		ret = x4step_ev_copy(x4, xf, buf, count);
		mutex_unlock(&xf->read_lock);
		if (ret)
			return ret;
		if (nonblock)
			return -EAGAIN;
		ret = wait_event_interruptible(x4->wait,
					       x4step_ev_wakeup(x4, xf));
		if (ret)
			return ret;
	}
}
