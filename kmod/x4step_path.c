// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: continuous paths (ABI 5), the glue of kmod/engine/x4_path.c.
 * The controller streams segments with write(); each is checked under the
 * raw lock, queued and planned without it (a bounded part of the
 * planner's backward pass a segment: process context, never the timer),
 * and the path is kicked under the lock after each chunk of records; the
 * mutex is let go between chunks. X4STEP_PATH_CTL holds, resumes, aborts
 * and overrides (a hold and an abort under the raw lock only, as the
 * halts); X4STEP_GET_PATH reports, X4STEP_GET_PROBE reads the probe latch. The queue's storage belongs to the
 * port (kvcalloc: up to 4096 segments) and changes only while no path is
 * active.
 */
#include <linux/fs.h>
#include <linux/mm.h>
#include <linux/poll.h>
#include <linux/sched/signal.h>
#include <linux/slab.h>
#include <linux/uaccess.h>

#include "x4_req.h"
#include "x4step_path.h"
#include "x4step_motion.h"

#define X4_PATH_CHUNK 8 /* records copied at a time: on the stack */

/* A new queue of `depth` slots, the old one freed; lock held. */
static int x4step_path_resize(struct x4_port *x4, u32 depth)
{
	struct x4_path_slot *slots, *old = x4->path_slots;
	unsigned long flags;
	int ret;

	lockdep_assert_held(&x4->lock);
	if (x4->eng.path.depth == depth)
		return 0;
	slots = kvcalloc(depth, sizeof(*slots), GFP_KERNEL);
	if (!slots)
		return -ENOMEM;
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_path_set_queue(&x4->eng, slots, depth);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (ret) {
		kvfree(slots);
		return x4_req_errno(ret);
	}
	x4->path_slots = slots;
	kvfree(old);
	return 0;
}

/*
 * The pass a write() left over, X4_PATH_PLAN_WORK entries a jiffy under
 * the mutex; then the running segment follows the raised plan.
 */
static void x4step_path_plan_work(struct work_struct *work)
{
	struct x4_port *x4 = container_of(to_delayed_work(work),
					  struct x4_port, path_plan_work);
	unsigned long flags;
	bool more;

	mutex_lock(&x4->lock);
	if (x4->gone) {
		mutex_unlock(&x4->lock);
		return;
	}
	more = x4_path_plan(&x4->eng, X4_PATH_PLAN_WORK);
	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->eng.path.state != X4_PATH_IDLE) /* never a start */
		x4_path_kick(&x4->eng, 0);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (more)
		schedule_delayed_work(&x4->path_plan_work, 1);
	mutex_unlock(&x4->lock);
}

void x4step_path_init(struct x4_port *x4)
{
	mutex_init(&x4->path_write_lock);
	INIT_DELAYED_WORK(&x4->path_plan_work, x4step_path_plan_work);
}

/* The port is gone (x4->gone): no planning from now on. */
void x4step_path_stop(struct x4_port *x4)
{
	cancel_delayed_work_sync(&x4->path_plan_work);
}

void x4step_path_free(struct x4_port *x4)
{
	kvfree(x4->path_slots);
}

/*
 * Start an idle path; a running one follows its new plan without a new
 * event. Only a start is a start (x4step_motion_run() arms the timer, clears
 * the last brake code): a kick of a running path leaves the timer as it
 * is, the gap it keeps after a capped callback too.
 */
static int x4step_kick(struct x4_engine *e, const void *arg, u64 now_ns)
{
	return x4_path_kick(e, now_ns) ? X4_OK : X4_ERR_IS_ACTIVE;
}

static int x4step_resume(struct x4_engine *e, const void *arg, u64 now_ns)
{
	return x4_path_resume(e, now_ns);
}

/* Check one record and queue it (room known); lock held. */
static int x4step_path_queue(struct x4_port *x4, const struct x4step_segment *r)
{
	struct x4_segment seg;
	unsigned long flags;
	int ret;

	ret = x4_req_segment(r, &seg);
	if (ret)
		return x4_req_errno(ret);
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_path_check(&x4->eng, &seg);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (ret)
		return x4_req_errno(ret);
	x4_path_push(&x4->eng, &seg); /* the writer's half: no raw lock */
	return 0;
}

/* A flush the controller has not acknowledged (X4STEP_PATH_CLEAR). */
static bool x4step_path_flushed(struct x4_port *x4)
{
	return READ_ONCE(x4->eng.path.flushes) != x4->path_flushes_seen;
}

static bool x4step_path_has_room(struct x4_port *x4)
{
	return x4_path_room(&x4->eng) || x4step_path_flushed(x4) ||
	       READ_ONCE(x4->gone);
}

/*
 * After a chunk: start the path, unless it was flushed meanwhile; then
 * what this write() queued after the flush goes too, and it ends.
 */
static int x4step_path_go(struct x4_port *x4)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4step_path_flushed(x4))
		x4_path_hold(&x4->eng, true);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (x4step_path_flushed(x4))
		return -ECANCELED;
	x4step_motion_run(x4, x4step_kick, NULL, X4STEP_KIND_PATH);
	return 0;
}

ssize_t x4step_path_write(struct x4_port *x4, struct file *file,
			  const char __user *buf, size_t count)
{
	struct x4step_segment rec[X4_PATH_CHUNK];
	size_t done = 0, n, i;
	int ret = 0;

	if (count % sizeof(rec[0]))
		return -EINVAL;
	/* One write() at a time: its records go in one piece. */
	if (file->f_flags & O_NONBLOCK) {
		if (!mutex_trylock(&x4->path_write_lock))
			return -EAGAIN;
	} else if (mutex_lock_interruptible(&x4->path_write_lock)) {
		return -ERESTARTSYS;
	}
	if (mutex_lock_interruptible(&x4->lock)) {
		mutex_unlock(&x4->path_write_lock);
		return -ERESTARTSYS;
	}
	if (x4->gone)
		ret = -ENODEV;
	else if (!x4->path_slots)
		ret = x4step_path_resize(x4, X4STEP_PATH_DEPTH_MIN);
	while (!ret && done < count) {
		if (done) { /* between chunks: the controller's ioctls */
			mutex_unlock(&x4->lock);
			cond_resched();
			/* not interruptible: the pass below needs the lock */
			mutex_lock(&x4->lock);
			if (x4->gone || signal_pending(current))
				break;
		}
		if (x4step_path_flushed(x4)) {
			ret = -ECANCELED;
			break;
		}
		n = min_t(size_t, (count - done) / sizeof(rec[0]),
			  min_t(u32, X4_PATH_CHUNK, x4_path_room(&x4->eng)));
		if (!n) { /* full: wait without the lock (hold, abort) */
			if (done)
				break;
			if (file->f_flags & O_NONBLOCK) {
				ret = -EAGAIN;
				break;
			}
			WRITE_ONCE(x4->path_room_wanted, true);
			mutex_unlock(&x4->lock);
			ret = wait_event_interruptible(
				x4->wait, x4step_path_has_room(x4));
			if (!ret && mutex_lock_interruptible(&x4->lock))
				ret = -ERESTARTSYS;
			if (ret)
				goto out_unlocked;
			if (x4->gone)
				ret = -ENODEV;
			continue;
		}
		if (copy_from_user(rec, buf + done, n * sizeof(rec[0]))) {
			ret = -EFAULT;
			break;
		}
		for (i = 0; i < n && !ret; i++) {
			ret = x4step_path_queue(x4, &rec[i]);
			if (!ret)
				done += sizeof(rec[0]);
		}
		if (x4step_path_go(x4)) { /* what it queued is flushed too */
			ret = -ECANCELED;
			done = 0;
		}
	}
	/* What the pushes' budget left of the pass: in time. */
	if (!x4->gone && x4_path_plan(&x4->eng, 0))
		schedule_delayed_work(&x4->path_plan_work, 1);
	mutex_unlock(&x4->lock);
out_unlocked:
	mutex_unlock(&x4->path_write_lock);
	return done ? done : ret;
}

/* POLLOUT for the controller while the queue has room. */
__poll_t x4step_path_poll(struct x4_port *x4, struct file *file)
{
	if (READ_ONCE(x4->controller) != file)
		return 0;
	if (!READ_ONCE(x4->path_slots))
		return EPOLLOUT | EPOLLWRNORM;
	WRITE_ONCE(x4->path_room_wanted, true);
	/* Pairs with x4step_port_room_locked(): one of us sees the other. */
	smp_mb();
	return x4_path_room(&x4->eng) ? EPOLLOUT | EPOLLWRNORM : 0;
}

/*
 * HOLD and ABORT: the raw lock only, as ESTOP and the brake keys, so that
 * a write() or another ioctl holding the mutex does not delay them.
 */
static int x4step_path_hold_ctl(struct x4_port *x4, u32 cmd)
{
	unsigned long flags;
	int ret;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone)
		ret = -ENODEV;
	else if (cmd == X4STEP_PATH_ABORT)
		ret = x4_req_errno(x4_track_path_abort(&x4->ev, &x4->eng));
	else
		ret = x4_req_errno(x4_path_hold(&x4->eng, false));
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	wake_up_all(&x4->wait); /* a writer waiting for room: flushed */
	return ret;
}

/* The other commands; lock held. */
static int x4step_path_ctl_cmd(struct x4_port *x4,
			       const struct x4step_path_ctl *c)
{
	struct x4_engine *e = &x4->eng;
	unsigned long flags;
	int ret;

	lockdep_assert_held(&x4->lock);
	switch (c->cmd) {
	case X4STEP_PATH_CLEAR:
		x4->path_flushes_seen = READ_ONCE(e->path.flushes);
		return 0;
	case X4STEP_PATH_RESUME:
		return x4_req_errno(x4step_motion_run(x4, x4step_resume, NULL,
						  X4STEP_KIND_PATH));
	case X4STEP_PATH_OVERRIDE:
		raw_spin_lock_irqsave(&x4->slock, flags);
		ret = x4_path_set_override(e, c->value);
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		if (ret)
			return x4_req_errno(ret);
		x4_path_replan(e); /* the writer's half: no raw lock */
		x4step_motion_run(x4, x4step_kick, NULL, X4STEP_KIND_PATH);
		return 0;
	default:
		return -EINVAL;
	}
}

/* X4STEP_PATH_CTL of the controller; takes the locks it needs. */
int x4step_path_ctl_ioctl(struct x4_port *x4, void __user *uarg)
{
	struct x4step_path_ctl c;
	int ret;

	if (copy_from_user(&c, uarg, sizeof(c)))
		return -EFAULT;
	if (x4_req_bad_path_ctl(&c))
		return -EINVAL;
	if (c.cmd == X4STEP_PATH_HOLD || c.cmd == X4STEP_PATH_ABORT)
		return x4step_path_hold_ctl(x4, c.cmd);
	mutex_lock(&x4->lock);
	ret = x4->gone ? -ENODEV : x4step_path_ctl_cmd(x4, &c);
	mutex_unlock(&x4->lock);
	return ret;
}

static int x4step_path_set_config(struct x4_port *x4,
				  const struct x4step_path_config *c)
{
	unsigned long flags;
	int ret;

	if (x4_req_bad_path_config(c))
		return -EINVAL;
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_req_errno(x4_req_set_probe(&x4->eng, c));
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (!ret && c->depth)
		ret = x4step_path_resize(x4, c->depth);
	if (!ret)
		WRITE_ONCE(x4->path_cfg_flags, c->flags);
	return ret;
}

/* X4STEP_SET_PATH_CONFIG of the controller; lock held. */
int x4step_path_ioctl(struct x4_port *x4, unsigned int cmd, void __user *uarg)
{
	struct x4step_path_config cfg;

	lockdep_assert_held(&x4->lock);
	if (copy_from_user(&cfg, uarg, sizeof(cfg)))
		return -EFAULT;
	return x4step_path_set_config(x4, &cfg);
}

/* The path's reading ioctls, on any descriptor. */
int x4step_path_ioctl_read(struct x4_port *x4, unsigned int cmd,
			   void __user *uarg)
{
	struct x4step_path_config cfg;
	struct x4step_path_status st;
	struct x4step_probe pr;
	struct x4_path_status s;
	unsigned long flags;

	if (cmd == X4STEP_GET_PROBE) {
		raw_spin_lock_irqsave(&x4->slock, flags);
		x4_req_probe(&x4->eng, &pr);
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		return copy_to_user(uarg, &pr, sizeof(pr)) ? -EFAULT : 0;
	}
	if (cmd == X4STEP_GET_PATH_CONFIG) {
		x4_req_path_config(&x4->eng, READ_ONCE(x4->path_cfg_flags),
				   &cfg);
		return copy_to_user(uarg, &cfg, sizeof(cfg)) ? -EFAULT : 0;
	}
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_path_get_status(&x4->eng, &s);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	x4_req_path_status(&s, READ_ONCE(x4->path_cfg_flags), &st);
	return copy_to_user(uarg, &st, sizeof(st)) ? -EFAULT : 0;
}
