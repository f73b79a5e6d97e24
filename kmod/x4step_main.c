// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: up to four stepper motors on a PC parallel port.
 *
 * A parport client driver: one char device /dev/x4stepN per parportN
 * (the `ports` parameter chooses which), the port claimed while a
 * controller holds the device open, and until the brake of its last
 * moves has ended; the rest of the time lp, ppdev and others may use it.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/cdev.h>
#include <linux/device.h>
#include <linux/fs.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/parport.h>
#include <linux/poll.h>
#include <linux/rcupdate.h>
#include <linux/slab.h>
#include <linux/uaccess.h>
#include <linux/workqueue.h>

#include "x4step_compat.h"
#include "x4step_dev.h"

static dev_t x4_devt;
static struct class *x4_class;
/* Read by the input handler under RCU. */
static struct x4_port __rcu *x4_ports[X4_MAX_PORTS];

/* A key event on any keyboard: true if it braked a move and is swallowed. */
bool x4_brake_key_all(u32 code)
{
	struct x4_port *x4;
	bool swallow = false;
	int i;

	rcu_read_lock();
	for (i = 0; i < X4_MAX_PORTS; i++) {
		x4 = rcu_dereference(x4_ports[i]);
		if (x4 && x4_port_brake_key(x4, code))
			swallow |= READ_ONCE(x4->cfg_flags) &
				   X4STEP_CFG_KEYS_SWALLOW;
	}
	rcu_read_unlock();
	return swallow;
}

static bool x4_busy(struct x4_port *x4)
{
	unsigned long flags;
	bool busy;

	raw_spin_lock_irqsave(&x4->slock, flags);
	busy = x4_engine_busy(&x4->eng);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return busy;
}

static struct x4_port *x4_of(struct file *file)
{
	return ((struct x4_file *)file->private_data)->x4;
}

static int x4_open(struct inode *inode, struct file *file)
{
	struct x4_port *x4 = container_of(inode->i_cdev, struct x4_port, cdev);
	struct x4_file *xf;
	unsigned long flags;
	int ret = 0;

	xf = kzalloc(sizeof(*xf), GFP_KERNEL);
	if (!xf)
		return -ENOMEM;
	get_device(&x4->dev);
	xf->x4 = x4;
	file->private_data = xf;
	stream_open(inode, file);
	x4_events_open(x4, xf);
	if ((file->f_mode & FMODE_WRITE) == 0)
		return 0;

	mutex_lock(&x4->lock);
	if (x4->gone)
		ret = -ENODEV;
	else if (x4->controller || x4->releasing)
		ret = -EBUSY; /* a controller, or the brake of one that closed */
	else if (parport_claim(x4->pardev))
		ret = -EBUSY; /* another driver (lp, ppdev, ...) holds the port */
	if (!ret) {
		WRITE_ONCE(x4->controller, file);
		/*
		 * Flushes of paths before it are none of its business, and its
		 * feed override starts at 100 %.
		 */
		x4->path_flushes_seen = READ_ONCE(x4->eng.path.flushes);
		raw_spin_lock_irqsave(&x4->slock, flags);
		x4_path_set_override(&x4->eng, 100);
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		x4_port_claimed(x4);
		raw_spin_lock_irqsave(&x4->slock, flags);
		x4_events_controller_locked(x4, X4STEP_CTL_OPENED);
		raw_spin_unlock_irqrestore(&x4->slock, flags);
	}
	mutex_unlock(&x4->lock);
	if (ret) {
		put_device(&x4->dev);
		kfree(xf);
	}
	return ret;
}

/* How often the deferred release looks whether the brake has ended. */
#define X4_RELEASE_POLL msecs_to_jiffies(5)

/* Stop the port (the engine is idle) and let others have it. */
static void x4_let_go(struct x4_port *x4)
{
	unsigned long flags;

	lockdep_assert_held(&x4->lock);
	/* Before the wake-up in quiesce: pollers see the port free. */
	WRITE_ONCE(x4->releasing, false);
	x4_port_quiesce(x4);
	parport_release(x4->pardev);
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_events_controller_locked(x4, X4STEP_CTL_RELEASED);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/*
 * The deferred release: once the brake started by x4_release() has ended,
 * the port goes back to the parport core and a new controller may open.
 * It looks every few ms: the end of the moves is signalled only to the
 * wait queue, by the hard-irq timer's irq_work. x4_detach() cancels it.
 */
static void x4_release_work(struct work_struct *work)
{
	struct x4_port *x4 = container_of(to_delayed_work(work), struct x4_port,
					  release_work);

	mutex_lock(&x4->lock);
	if (x4->releasing) {
		if (x4_busy(x4))
			schedule_delayed_work(&x4->release_work,
					      X4_RELEASE_POLL);
		else
			x4_let_go(x4);
	}
	mutex_unlock(&x4->lock);
}

/*
 * The controller went away (closed, or killed): brake what runs along its
 * ramp and return at once. A brake may take minutes (profiles allow
 * ramps of an hour), so the port is released by x4_release_work() when
 * the engine is idle; until then the port stays claimed and the
 * controller slot taken. Nothing here waits for the motors.
 */
static int x4_release(struct inode *inode, struct file *file)
{
	struct x4_file *xf = file->private_data;
	struct x4_port *x4 = xf->x4;
	unsigned long flags;
	bool busy;

	mutex_lock(&x4->lock);
	if (x4->controller == file) {
		WRITE_ONCE(x4->controller, NULL);
		if (!x4->gone) { /* else x4_detach() released the port */
			raw_spin_lock_irqsave(&x4->slock, flags);
			x4_events_controller_locked(x4, X4STEP_CTL_CLOSED);
			x4_path_brake_locked(x4, X4STEP_SRC_CLOSE);
			if (x4_engine_busy(&x4->eng))
				x4_port_brake_locked(x4, 0x0f, X4STEP_SRC_CLOSE,
						     0);
			busy = x4_engine_busy(&x4->eng);
			raw_spin_unlock_irqrestore(&x4->slock, flags);
			if (busy) {
				WRITE_ONCE(x4->releasing, true);
				schedule_delayed_work(&x4->release_work,
						      X4_RELEASE_POLL);
			} else {
				x4_let_go(x4);
			}
		}
	}
	mutex_unlock(&x4->lock);
	put_device(&x4->dev);
	kfree(xf);
	return 0;
}

/*
 * POLLIN keeps its meaning of ABI 1 to 3 (the library's wait() relies on
 * it): no move runs. Events to read() are POLLPRI, on any descriptor.
 */
static __poll_t x4_poll(struct file *file, struct poll_table_struct *wait)
{
	struct x4_file *xf = file->private_data;
	struct x4_port *x4 = xf->x4;
	__poll_t events;

	poll_wait(file, &x4->wait, wait);
	events = x4_events_poll(x4, xf);
	if (events & EPOLLHUP) /* PORT_GONE is in the ring */
		return events;
	/*
	 * Idle, and the brake of a controller that closed is over: once
	 * this reports POLLIN, a new controller may open.
	 */
	events |= x4_path_poll(x4, file);
	if (x4_busy(x4) || READ_ONCE(x4->releasing))
		return events;
	return events | EPOLLIN | EPOLLRDNORM;
}

static ssize_t x4_read(struct file *file, char __user *buf, size_t count,
		       loff_t *ppos)
{
	struct x4_file *xf = file->private_data;

	return x4_events_read(xf->x4, xf, file, buf, count);
}

/* Path segments (ABI 5), from the controller: x4step_path.c. */
static ssize_t x4_write(struct file *file, const char __user *buf,
			size_t count, loff_t *ppos)
{
	if (READ_ONCE(x4_of(file)->controller) != file)
		return -EBADF;
	return x4_path_write(x4_of(file), file, buf, count);
}

static int x4_get_status(struct x4_port *x4, struct x4step_status *st)
{
	unsigned long flags;
	int i;

	memset(st, 0, sizeof(*st));
	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone) {
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		return -ENODEV;
	}
	st->inputs = x4_port_inputs_locked(x4);
	st->inputs_time_ns = x4->inputs_ns;
	if (!x4->claimed)
		st->flags |= X4STEP_ST_INPUTS_STALE;
	if (x4_engine_busy(&x4->eng))
		st->flags |= X4STEP_ST_ACTIVE;
	if (x4->eng.loaded)
		st->flags |= X4STEP_ST_LOADED;
	if (x4->claimed)
		st->flags |= X4STEP_ST_CONTROLLED;
	st->last_brake_code = x4->last_brake_code;
	st->outputs = x4->eng.ctl;
	st->data = x4->eng.data;
	for (i = 0; i < X4_AXES; i++)
		st->steps[i] = x4->eng.steps[i];
	st->moves_ended = x4->eng.ends;
	st->brake_time_ns = x4->brake_time_ns;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return 0;
}

static int x4_ioctl_load(struct x4_port *x4, struct x4step_move __user *arg)
{
	struct x4_move m;
	struct x4step_move um;
	unsigned long flags;
	int i, ret;

	if (copy_from_user(&um, arg, sizeof(um)))
		return -EFAULT;
	/* The result must be writable before anything happens. */
	if (put_user(X4_ERR_PARAM_FAIL, &arg->result))
		return -EFAULT;
	if (um.flags)
		return -EINVAL;
	for (i = 0; i < X4_AXES; i++)
		m.steps[i] = um.steps[i];
	m.freq_hz = um.freq_hz;
	m.ramp_ms = um.ramp_ms;
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_engine_load(&x4->eng, &m);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (put_user(ret, &arg->result))
		return -EFAULT;
	return x4_req_errno(ret);
}

static int x4_start_loaded(struct x4_engine *e, const void *arg, u64 now)
{
	return x4_engine_start(e, now);
}

static int x4_start_endless(struct x4_engine *e, const void *arg, u64 now)
{
	const struct x4step_endless *ue = arg;

	return x4_engine_endless(e, ue->axis, ue->direction < 0, ue->freq_hz,
				 ue->ramp_ms, now);
}

static int x4_start_home(struct x4_engine *e, const void *arg, u64 now)
{
	const struct x4step_home *uh = arg;

	return x4_switch_home(e, uh->axis, (u8)uh->phases, uh->vref1,
			      uh->vref2, uh->sref, now);
}

/* How the ioctls that start moves start them: an X4Step result. */
typedef int (*x4_runner)(struct x4_port *x4, const void *karg);

static int x4_run_endless(struct x4_port *x4, const void *karg)
{
	return x4_port_run(x4, x4_start_endless, karg, X4STEP_KIND_ENDLESS);
}

static int x4_run_home(struct x4_port *x4, const void *karg)
{
	return x4_port_run(x4, x4_start_home, karg, X4STEP_KIND_HOME);
}

/* A goto is planned outside the raw lock (x4_port_goto()). */
static int x4_run_goto(struct x4_port *x4, const void *karg)
{
	const struct x4step_goto *ug = karg;

	return x4_port_goto(x4, (u8)ug->axes, ug->target,
			    ug->flags & X4STEP_GOTO_RELATIVE);
}

/*
 * The ioctls that start moves and report an X4Step result: copy in the
 * argument (`size` bytes, its s32 result at `result_off`), make sure the
 * result is writable before anything moves, refuse what is wrong in
 * the argument itself (`bad`: reserved words, values the engine's types
 * would truncate), start, write the result.
 */
static int x4_ioctl_run(struct x4_port *x4, void __user *uarg, void *karg,
			size_t size, size_t result_off,
			bool (*bad)(const void *karg), x4_runner run)
{
	s32 __user *uresult = (s32 __user *)((char __user *)uarg + result_off);
	s32 result = X4_ERR_PARAM_FAIL;

	if (copy_from_user(karg, uarg, size))
		return -EFAULT;
	if (put_user(result, uresult))
		return -EFAULT;
	if (bad(karg))
		return -EINVAL;
	result = run(x4, karg);
	if (put_user(x4_req_result(result), uresult))
		return -EFAULT;
	return x4_req_errno(result);
}

static bool x4_bad_endless(const void *karg)
{
	return x4_req_bad_endless(karg);
}

static bool x4_bad_goto(const void *karg)
{
	return x4_req_bad_goto(karg);
}

static bool x4_bad_home(const void *karg)
{
	return x4_req_bad_home(karg);
}

/*
 * Brake or stop (X4Brake, X4Stop, X4STEP_HALT); ESRCH if nothing runs.
 * Only the raw lock, as ESTOP: a write() or an ioctl holding the mutex
 * does not delay it.
 */
static int x4_ioctl_halt(struct x4_port *x4, u32 axes, u32 how)
{
	unsigned long flags;
	int ret;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone)
		ret = -ENODEV;
	else if (how == X4STEP_HALT_STOP)
		ret = x4_req_errno(x4_port_stop_locked(x4, (u8)axes));
	else
		ret = x4_req_errno(x4_port_brake_locked(x4, (u8)axes,
						    X4STEP_SRC_IOCTL, 0));
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ret;
}

static int x4_ioctl_halt_axes(struct x4_port *x4,
			      struct x4step_halt __user *arg)
{
	struct x4step_halt h;

	if (copy_from_user(&h, arg, sizeof(h)))
		return -EFAULT;
	if (x4_req_bad_halt(&h))
		return -EINVAL;
	return x4_ioctl_halt(x4, h.axes, h.how);
}

/*
 * X4STEP_ESTOP, from any descriptor: halt every move whoever controls
 * the port. Only the raw lock, as the brake keys: a controller's ioctl
 * holding the mutex does not delay it. The EV_BRAKE event comes before
 * the stop's MOVE_ENDED; a stop's end reason wins over the brake's.
 */
static int x4_ioctl_estop(struct x4_port *x4, struct x4step_estop __user *arg)
{
	struct x4step_estop es;
	unsigned long flags;
	int ret;

	if (copy_from_user(&es, arg, sizeof(es)))
		return -EFAULT;
	if (x4_req_bad_estop(&es))
		return -EINVAL;
	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone) {
		ret = -ENODEV;
	} else if (es.how == X4STEP_HALT_STOP) {
		x4_events_brake_locked(x4, x4_events_chans_locked(x4, 0x0f),
				       X4STEP_SRC_ESTOP, X4STEP_HALT_STOP);
		ret = x4_req_errno(x4_port_stop_locked(x4, 0x0f));
	} else {
		ret = x4_req_errno(x4_port_brake_locked(x4, 0x0f, X4STEP_SRC_ESTOP,
						    X4STEP_HALT_BRAKE));
	}
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ret;
}

static int x4_ioctl_set_position(struct x4_port *x4,
				 struct x4step_position __user *arg)
{
	struct x4step_position up;
	unsigned long flags;
	int ret;

	if (copy_from_user(&up, arg, sizeof(up)))
		return -EFAULT;
	if (x4_req_bad_position(&up))
		return -EINVAL;
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_events_stop_locked(x4, x4_events_chans_locked(x4, (u8)up.axes));
	ret = x4_engine_set_position(&x4->eng, (u8)up.axes, up.position);
	x4_port_halted_locked(x4);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	wake_up_all(&x4->wait); /* a path writer or poller: its queue is gone */
	return x4_req_errno(ret);
}

static int x4_ioctl_set_profile(struct x4_port *x4,
				struct x4step_profile __user *arg)
{
	struct x4step_profile up;
	struct x4_profile p;
	unsigned long flags;
	int ret;

	if (copy_from_user(&up, arg, sizeof(up)))
		return -EFAULT;
	ret = x4_req_profile(&up, &p);
	if (ret)
		return ret;
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_engine_set_profile(&x4->eng, up.axis, &p);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return x4_req_errno(ret);
}

static int x4_ioctl_get_profile(struct x4_port *x4,
				struct x4step_profile __user *arg)
{
	struct x4step_profile up;
	unsigned long flags;
	u32 axis;

	if (get_user(axis, &arg->axis))
		return -EFAULT;
	if (axis < 1 || axis > X4_AXES)
		return -EINVAL;
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_req_get_profile(&x4->eng, axis, &up);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(arg, &up, sizeof(up)) ? -EFAULT : 0;
}

static int x4_ioctl_set_switches(struct x4_port *x4,
				 struct x4step_switches __user *arg)
{
	struct x4step_switches us;
	struct x4_switches sw;
	unsigned long flags;
	int ret;

	if (copy_from_user(&us, arg, sizeof(us)))
		return -EFAULT;
	if (x4_req_bad_switches(&us))
		return -EINVAL;
	x4_req_switches(&us, &sw);
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_switch_set(&x4->eng, &sw);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return x4_req_errno(ret);
}

static int x4_ioctl_get_switches(struct x4_port *x4, void __user *uarg)
{
	struct x4step_switches us;
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_req_get_switches(&x4->eng, &us);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(uarg, &us, sizeof(us)) ? -EFAULT : 0;
}

static int x4_ioctl_get_axes(struct x4_port *x4, void __user *uarg)
{
	struct x4step_axes ua;
	unsigned long flags;

	memset(&ua, 0, sizeof(ua));
	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone) {
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		return -ENODEV;
	}
	x4_req_get_axes(&x4->eng, x4_port_inputs_locked(x4), x4->inputs_ns,
			&ua);
	if (!x4->claimed)
		ua.flags = X4STEP_ST_INPUTS_STALE;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(uarg, &ua, sizeof(ua)) ? -EFAULT : 0;
}

/* Set the signals in `mask` to `levels`, in one control register write. */
static void x4_set_outputs(struct x4_port *x4, u32 mask, u32 levels)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (mask & X4STEP_OUT_SIGNAL1)
		x4_engine_set_signal(&x4->eng, X4_CTL_SIGNAL1,
				     levels & X4STEP_OUT_SIGNAL1);
	if (mask & X4STEP_OUT_SIGNAL2)
		x4_engine_set_signal(&x4->eng, X4_CTL_SIGNAL2,
				     levels & X4STEP_OUT_SIGNAL2);
	x4_port_write_locked(x4);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/* X4STEP_SET_OUTPUT, ABI 1..3. */
static int x4_ioctl_output(struct x4_port *x4, struct x4step_output __user *arg)
{
	struct x4step_output out;

	if (copy_from_user(&out, arg, sizeof(out)))
		return -EFAULT;
	if (x4_req_bad_output(&out))
		return -EINVAL;
	x4_set_outputs(x4, out.signal, out.level ? out.signal : 0);
	return 0;
}

static int x4_ioctl_outputs(struct x4_port *x4,
			    struct x4step_outputs __user *arg)
{
	struct x4step_outputs out;

	if (copy_from_user(&out, arg, sizeof(out)))
		return -EFAULT;
	if (x4_req_bad_outputs(&out))
		return -EINVAL;
	x4_set_outputs(x4, out.mask, out.levels);
	return 0;
}

static int x4_ioctl_brake_codes(struct x4_port *x4,
				struct x4step_brake_codes __user *arg)
{
	struct x4step_brake_codes bc;
	unsigned long flags;

	if (copy_from_user(&bc, arg, sizeof(bc)))
		return -EFAULT;
	if (x4_req_bad_brake_codes(&bc))
		return -EINVAL;
	raw_spin_lock_irqsave(&x4->slock, flags);
	memcpy(x4->brake_codes, bc.codes, sizeof(x4->brake_codes));
	x4->n_brake_codes = bc.count;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return 0;
}

static int x4_ioctl_set_config(struct x4_port *x4,
			       struct x4step_config __user *arg)
{
	struct x4step_config cfg;
	unsigned long flags;
	int ret;

	if (copy_from_user(&cfg, arg, sizeof(cfg)))
		return -EFAULT;
	if (x4_req_bad_config(&cfg))
		return -EINVAL;
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_engine_configure(&x4->eng, &x4->eng.timing, cfg.output_mode);
	if (!ret) {
		x4_port_set_invert(x4, cfg.clock_invert, cfg.dir_invert);
		WRITE_ONCE(x4->cfg_flags, cfg.flags); /* read by the key handler */
		x4_port_write_rest_locked(x4);
	}
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return x4_req_errno(ret);
}

static int x4_ioctl_set_step_timing(struct x4_port *x4,
				    struct x4step_step_timing __user *arg)
{
	struct x4step_step_timing ut;
	struct x4_timing t;
	unsigned long flags;
	int ret;

	if (copy_from_user(&ut, arg, sizeof(ut)))
		return -EFAULT;
	if (x4_req_bad_step_timing(&ut))
		return -EINVAL;
	x4_req_step_timing(&ut, &t);
	raw_spin_lock_irqsave(&x4->slock, flags);
	ret = x4_engine_configure(&x4->eng, &t, x4->eng.mode);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return x4_req_errno(ret);
}

static int x4_ioctl_get_step_timing(struct x4_port *x4, void __user *uarg)
{
	struct x4step_step_timing ut;
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_req_get_step_timing(&x4->eng, &ut);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(uarg, &ut, sizeof(ut)) ? -EFAULT : 0;
}

/*
 * GET_TIMING, in this ABI's size or version 2's (`size`). Only the
 * controller's read resets the figures.
 */
static int x4_ioctl_timing(struct x4_port *x4, struct file *file,
			   void __user *uarg, size_t size)
{
	struct x4step_timing *t;
	unsigned long flags;
	int ret = 0;

	/* Version 2's struct is this one's head. */
	BUILD_BUG_ON(offsetof(struct x4step_timing, callbacks) !=
		     X4STEP_TIMING_V2_SIZE);
	t = kmalloc(sizeof(*t), GFP_KERNEL);
	if (!t)
		return -ENOMEM;
	raw_spin_lock_irqsave(&x4->slock, flags);
	*t = x4->timing;
	if (READ_ONCE(x4->controller) == file)
		memset(&x4->timing, 0, sizeof(x4->timing));
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	if (copy_to_user(uarg, t, size))
		ret = -EFAULT;
	kfree(t);
	return ret;
}

static long x4_ioctl(struct file *file, unsigned int cmd, unsigned long arg)
{
	struct x4_port *x4 = x4_of(file);
	void __user *uarg = (void __user *)arg;
	struct x4step_status st;
	struct x4step_info info;
	struct x4step_config cfg;
	union {
		struct x4step_endless endless;
		struct x4step_goto go;
		struct x4step_home home;
	} karg;
	unsigned long flags;
	long ret;

	/* Reading commands, and the emergency halt, work on any descriptor. */
	switch (cmd) {
	case X4STEP_GET_INFO:
		memset(&info, 0, sizeof(info));
		info.abi_version = X4STEP_ABI_VERSION;
		info.axes = X4STEP_AXES;
		info.port = MINOR(x4->dev.devt);
		info.event_buffer = X4_EVENTS;
		return copy_to_user(uarg, &info, sizeof(info)) ? -EFAULT : 0;
	case X4STEP_GET_STATUS:
		if (x4_get_status(x4, &st))
			return -ENODEV;
		return copy_to_user(uarg, &st, sizeof(st)) ? -EFAULT : 0;
	case X4STEP_GET_CONFIG:
		memset(&cfg, 0, sizeof(cfg));
		raw_spin_lock_irqsave(&x4->slock, flags); /* as SET_CONFIG */
		cfg.clock_invert = x4->clock_invert;
		cfg.dir_invert = x4->dir_invert;
		cfg.flags = x4->cfg_flags;
		cfg.output_mode = x4->eng.mode;
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		return copy_to_user(uarg, &cfg, sizeof(cfg)) ? -EFAULT : 0;
	case X4STEP_GET_TIMING:
		return x4_ioctl_timing(x4, file, uarg, sizeof(struct x4step_timing));
	case X4STEP_GET_TIMING_V2:
		return x4_ioctl_timing(x4, file, uarg, X4STEP_TIMING_V2_SIZE);
	case X4STEP_GET_STEP_TIMING:
		return x4_ioctl_get_step_timing(x4, uarg);
	case X4STEP_GET_PROFILE:
		return x4_ioctl_get_profile(x4, uarg);
	case X4STEP_GET_SWITCHES:
		return x4_ioctl_get_switches(x4, uarg);
	case X4STEP_GET_AXES:
		return x4_ioctl_get_axes(x4, uarg);
	case X4STEP_ESTOP: /* any descriptor: the emergency halt */
		return x4_ioctl_estop(x4, uarg);
	case X4STEP_GET_PATH:
	case X4STEP_GET_PATH_CONFIG:
		return x4_path_ioctl_read(x4, cmd, uarg);
	case X4STEP_SET_PATH_CONFIG:
	case X4STEP_PATH_CTL:
	case X4STEP_SET_PROFILE:
	case X4STEP_GOTO:
	case X4STEP_HOME:
	case X4STEP_HALT:
	case X4STEP_SET_POSITION:
	case X4STEP_SET_SWITCHES:
	case X4STEP_LOAD:
	case X4STEP_START:
	case X4STEP_BRAKE:
	case X4STEP_STOP:
	case X4STEP_MOVE_ENDLESS:
	case X4STEP_SET_OUTPUT:
	case X4STEP_SET_OUTPUTS:
	case X4STEP_SET_BRAKE_CODES:
	case X4STEP_SET_CONFIG:
	case X4STEP_SET_STEP_TIMING:
		break;
	default:
		return -ENOTTY;
	}

	if (READ_ONCE(x4->controller) != file)
		return -EBADF;
	/* The halts: the raw lock only (the controller's file is held). */
	switch (cmd) {
	case X4STEP_BRAKE:
		return x4_ioctl_halt(x4, 0x0f, X4STEP_HALT_BRAKE);
	case X4STEP_STOP:
		return x4_ioctl_halt(x4, 0x0f, X4STEP_HALT_STOP);
	case X4STEP_HALT:
		return x4_ioctl_halt_axes(x4, uarg);
	case X4STEP_PATH_CTL:
		return x4_path_ctl_ioctl(x4, uarg);
	}
	mutex_lock(&x4->lock);
	if (x4->gone) {
		ret = -ENODEV;
		goto out;
	}
	switch (cmd) {
	case X4STEP_LOAD:
		ret = x4_ioctl_load(x4, uarg);
		break;
	case X4STEP_START:
		ret = x4_req_errno(x4_port_run(x4, x4_start_loaded, NULL,
					   X4STEP_KIND_LOADED));
		break;
	case X4STEP_MOVE_ENDLESS:
		ret = x4_ioctl_run(x4, uarg, &karg.endless, sizeof(karg.endless),
				   offsetof(struct x4step_endless, result),
				   x4_bad_endless, x4_run_endless);
		break;
	case X4STEP_GOTO:
		ret = x4_ioctl_run(x4, uarg, &karg.go, sizeof(karg.go),
				   offsetof(struct x4step_goto, result),
				   x4_bad_goto, x4_run_goto);
		break;
	case X4STEP_HOME:
		ret = x4_ioctl_run(x4, uarg, &karg.home, sizeof(karg.home),
				   offsetof(struct x4step_home, result),
				   x4_bad_home, x4_run_home);
		break;
	case X4STEP_SET_POSITION:
		ret = x4_ioctl_set_position(x4, uarg);
		break;
	case X4STEP_SET_PROFILE:
		ret = x4_ioctl_set_profile(x4, uarg);
		break;
	case X4STEP_SET_SWITCHES:
		ret = x4_ioctl_set_switches(x4, uarg);
		break;
	case X4STEP_SET_OUTPUT:
		ret = x4_ioctl_output(x4, uarg);
		break;
	case X4STEP_SET_OUTPUTS:
		ret = x4_ioctl_outputs(x4, uarg);
		break;
	case X4STEP_SET_BRAKE_CODES:
		ret = x4_ioctl_brake_codes(x4, uarg);
		break;
	case X4STEP_SET_CONFIG:
		ret = x4_ioctl_set_config(x4, uarg);
		break;
	case X4STEP_SET_PATH_CONFIG:
		ret = x4_path_ioctl(x4, cmd, uarg);
		break;
	default: /* X4STEP_SET_STEP_TIMING */
		ret = x4_ioctl_set_step_timing(x4, uarg);
		break;
	}
out:
	mutex_unlock(&x4->lock);
	return ret;
}

static const struct file_operations x4_fops = {
	.owner = THIS_MODULE,
	.open = x4_open,
	.release = x4_release,
	.poll = x4_poll,
	.read = x4_read,
	.write = x4_write,
	.unlocked_ioctl = x4_ioctl,
	.compat_ioctl = compat_ptr_ioctl,
	.llseek = noop_llseek,
};

static void x4_dev_release(struct device *dev)
{
	struct x4_port *x4 = container_of(dev, struct x4_port, dev);

	parport_put_port(x4->port);
	x4_events_free(x4);
	x4_path_free(x4);
	kfree(x4);
}

/* The parport numbers x4step serves (none given: all of them). */
static int ports[X4_MAX_PORTS];
static int n_ports;
module_param_array(ports, int, &n_ports, 0444);
MODULE_PARM_DESC(ports, "parport numbers to serve, e.g. ports=0,2 (default: every port)");

static bool x4_serves(struct parport *port)
{
	int i;

	if (port->number >= X4_MAX_PORTS) {
		pr_info("%s: not served: x4step serves parport0..%d\n",
			port->name, X4_MAX_PORTS - 1);
		return false;
	}
	/*
	 * The step timer writes the registers in hard-irq context: a port
	 * whose operations may sleep (a USB adapter such as uss720) cannot
	 * be driven.
	 */
	if (!(port->modes & PARPORT_MODE_SAFEININT)) {
		pr_info("%s: not served: its operations may sleep (USB adapter?), x4step drives the port from a hard-irq timer\n",
			port->name);
		return false;
	}
	if (!n_ports)
		return true;
	for (i = 0; i < n_ports; i++)
		if (ports[i] == port->number)
			return true;
	pr_info("%s: not served (not in the ports parameter)\n", port->name);
	return false;
}

/*
 * A new port. The device is registered without exclusive access, as
 * ppdev's: lp, ppdev and others share the port, and x4step claims it
 * only while a controller has /dev/x4stepN open (x4_open()).
 */
static void x4_attach(struct parport *port)
{
	struct pardev_cb cb = { };
	struct x4_port *x4;
	int ret;

	if (!x4_serves(port))
		return;
	x4 = kzalloc(sizeof(*x4), GFP_KERNEL);
	if (!x4)
		return;
	if (x4_events_alloc(x4)) {
		kfree(x4);
		return;
	}
	mutex_init(&x4->lock);
	x4_path_init(x4);
	INIT_DELAYED_WORK(&x4->release_work, x4_release_work);
	x4_port_init(x4);
	/* Held until the last file closes: the port may go away first. */
	x4->port = parport_get_port(port);
	cb.private = x4;
	x4->pardev = parport_register_dev_model(port, KBUILD_MODNAME, &cb,
						port->number);
	if (!x4->pardev) {
		/* e.g. plip has the port exclusively: see `ports` */
		pr_err("%s: cannot register device\n", port->name);
		parport_put_port(port);
		x4_events_free(x4);
		kfree(x4);
		return;
	}

	device_initialize(&x4->dev);
	x4->dev.class = x4_class;
	x4->dev.parent = port->dev; /* in sysfs under the port, as ppdev */
	x4->dev.devt = MKDEV(MAJOR(x4_devt), port->number);
	x4->dev.release = x4_dev_release;
	cdev_init(&x4->cdev, &x4_fops);
	x4->cdev.owner = THIS_MODULE;
	ret = dev_set_name(&x4->dev, "x4step%d", port->number);
	if (ret)
		goto err_put;
	ret = cdev_device_add(&x4->cdev, &x4->dev);
	if (ret)
		goto err_put;

	rcu_assign_pointer(x4_ports[port->number], x4);
	dev_info(&x4->dev, "on %s\n", port->name);
	return;

err_put:
	pr_err("%s: cannot create device: %d\n", port->name, ret);
	parport_unregister_device(x4->pardev);
	put_device(&x4->dev);
}

/*
 * The port goes away (its driver's removal, or x4step's unload): stop
 * the motors at once, a brake of a closed controller too, and never touch
 * the port again. Waits for nobody's brake.
 */
static void x4_detach(struct parport *port)
{
	unsigned long flags;
	struct x4_port *x4;

	if (port->number >= X4_MAX_PORTS)
		return;
	x4 = rcu_dereference_protected(x4_ports[port->number], true);
	if (!x4)
		return;
	RCU_INIT_POINTER(x4_ports[port->number], NULL);
	synchronize_rcu(); /* the input handler no longer sees it */

	cdev_device_del(&x4->cdev, &x4->dev);
	mutex_lock(&x4->lock);
	x4_port_gone(x4);
	if (x4->releasing)
		dev_warn(&x4->dev, "port removed while braking: stopped\n");
	if (x4->controller || x4->releasing) {
		WRITE_ONCE(x4->releasing, false);
		x4_port_quiesce(x4);
		parport_release(x4->pardev);
	}
	parport_unregister_device(x4->pardev);
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_events_gone_locked(x4);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	mutex_unlock(&x4->lock);
	/*
	 * With `gone` set, nothing queues the release work again: after
	 * this it neither runs nor is pending (module unload, kfree).
	 */
	cancel_delayed_work_sync(&x4->release_work);
	x4_path_stop(x4);
	hrtimer_cancel(&x4->timer);
	irq_work_sync(&x4->wake_work);
	wake_up_all(&x4->wait);
	put_device(&x4->dev);
}

static struct parport_driver x4_driver = {
	.name = KBUILD_MODNAME,
	.match_port = x4_attach,
	.detach = x4_detach,
	X4_PARPORT_DEVMODEL
};

static char *x4_devnode(X4_DEVNODE_CONST struct device *dev, umode_t *mode)
{
	if (mode)
		*mode = 0660; /* group lp, as /dev/parport* (udev rule) */
	return NULL;
}

static int __init x4_init(void)
{
	int i, ret;

	for (i = 0; i < n_ports; i++) {
		if (ports[i] < 0 || ports[i] >= X4_MAX_PORTS) {
			pr_err("ports: %d is not a parport number 0..%d\n",
			       ports[i], X4_MAX_PORTS - 1);
			return -EINVAL;
		}
	}
	ret = alloc_chrdev_region(&x4_devt, 0, X4_MAX_PORTS, KBUILD_MODNAME);
	if (ret)
		return ret;
	x4_class = x4_class_create(KBUILD_MODNAME);
	if (IS_ERR(x4_class)) {
		ret = PTR_ERR(x4_class);
		goto err_region;
	}
	x4_class->devnode = x4_devnode;
	/*
	 * The brake keys first: once the parport driver is registered, the
	 * devices can be opened, and nothing may fail after that.
	 */
	ret = x4_keys_init();
	if (ret)
		goto err_class;
	ret = parport_register_driver(&x4_driver);
	if (ret)
		goto err_keys;
	return 0;

err_keys:
	x4_keys_exit();
err_class:
	class_destroy(x4_class);
err_region:
	unregister_chrdev_region(x4_devt, X4_MAX_PORTS);
	return ret;
}

static void __exit x4_exit(void)
{
	parport_unregister_driver(&x4_driver); /* detaches every port */
	x4_keys_exit();
	class_destroy(x4_class);
	unregister_chrdev_region(x4_devt, X4_MAX_PORTS);
}

module_init(x4_init);
module_exit(x4_exit);

MODULE_DESCRIPTION("Stepper motors on the PC parallel port (X4Step)");
MODULE_LICENSE("GPL");
