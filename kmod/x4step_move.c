// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: the ioctls that start and halt moves. Those that start them
 * copy the request in, refuse what is invalid in itself
 * (engine/x4_req.c), start the engine through the port
 * (x4step_motion_run()) and write the X4Step result back; the controller's
 * mutex is held. The halts take only the raw lock, so that nothing
 * holding the mutex delays them.
 */
#include <linux/uaccess.h>

#include "x4_req.h"
#include "x4step_events.h"
#include "x4step_move.h"
#include "x4step_motion.h"

static int x4step_ioctl_load(struct x4_port *x4, struct x4step_move __user *arg)
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

static int x4step_start_loaded(struct x4_engine *e, const void *arg, u64 now)
{
	return x4_engine_start(e, now);
}

static int x4step_start_endless(struct x4_engine *e, const void *arg, u64 now)
{
	const struct x4step_endless *ue = arg;

	return x4_engine_endless(e, ue->axis, ue->direction < 0, ue->freq_hz,
				 ue->ramp_ms, now);
}

static int x4step_start_home(struct x4_engine *e, const void *arg, u64 now)
{
	const struct x4step_home *uh = arg;

	return x4_switch_home(e, uh->axis, (u8)uh->phases, uh->vref1,
			      uh->vref2, uh->sref, now);
}

/* How the ioctls that start moves start them: an X4Step result. */
typedef int (*x4_runner)(struct x4_port *x4, const void *karg);

static int x4step_run_endless(struct x4_port *x4, const void *karg)
{
	return x4step_motion_run(x4, x4step_start_endless, karg,
				 X4STEP_KIND_ENDLESS);
}

static int x4step_run_home(struct x4_port *x4, const void *karg)
{
	return x4step_motion_run(x4, x4step_start_home, karg, X4STEP_KIND_HOME);
}

/* A goto is planned outside the raw lock (x4step_motion_goto()). */
static int x4step_run_goto(struct x4_port *x4, const void *karg)
{
	const struct x4step_goto *ug = karg;

	return x4step_motion_goto(x4, (u8)ug->axes, ug->target,
				  ug->flags & X4STEP_GOTO_RELATIVE);
}

/*
 * The ioctls that start moves and report an X4Step result: copy in the
 * argument (`size` bytes, its s32 result at `result_off`), make sure the
 * result is writable before anything moves, refuse what is wrong in
 * the argument itself (`bad`: reserved words, values the engine's types
 * would truncate), start, write the result.
 */
static int x4step_ioctl_run(struct x4_port *x4, void __user *uarg, void *karg,
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

static bool x4step_bad_endless(const void *karg)
{
	return x4_req_bad_endless(karg);
}

static bool x4step_bad_goto(const void *karg)
{
	return x4_req_bad_goto(karg);
}

static bool x4step_bad_home(const void *karg)
{
	return x4_req_bad_home(karg);
}

/*
 * Brake or stop (X4Brake, X4Stop, X4STEP_HALT); ESRCH if nothing runs.
 * Only the raw lock, as ESTOP: a write() or an ioctl holding the mutex
 * does not delay it.
 */
static int x4step_ioctl_halt(struct x4_port *x4, u32 axes, u32 how)
{
	unsigned long flags;
	int ret;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone)
		ret = -ENODEV;
	else if (how == X4STEP_HALT_STOP)
		ret = x4_req_errno(x4step_motion_stop_locked(x4, (u8)axes));
	else
		ret = x4_req_errno(x4step_motion_brake_locked(x4, (u8)axes,
							  X4STEP_SRC_IOCTL, 0));
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ret;
}

static int x4step_ioctl_halt_axes(struct x4_port *x4,
				  struct x4step_halt __user *arg)
{
	struct x4step_halt h;

	if (copy_from_user(&h, arg, sizeof(h)))
		return -EFAULT;
	if (x4_req_bad_halt(&h))
		return -EINVAL;
	return x4step_ioctl_halt(x4, h.axes, h.how);
}

/*
 * X4STEP_ESTOP, from any descriptor: halt every move whoever controls
 * the port. Only the raw lock, as the brake keys: a controller's ioctl
 * holding the mutex does not delay it. The EV_BRAKE event comes before
 * the stop's MOVE_ENDED; a stop's end reason wins over the brake's.
 */
static int x4step_ioctl_estop(struct x4_port *x4,
			      struct x4step_estop __user *arg)
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
		x4step_events_brake_locked(x4,
					   x4step_events_chans_locked(x4, 0x0f),
					   X4STEP_SRC_ESTOP, X4STEP_HALT_STOP);
		ret = x4_req_errno(x4step_motion_stop_locked(x4, 0x0f));
	} else {
		ret = x4_req_errno(x4step_motion_brake_locked(x4, 0x0f,
							  X4STEP_SRC_ESTOP,
							  X4STEP_HALT_BRAKE));
	}
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ret;
}

static int x4step_ioctl_set_position(struct x4_port *x4,
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
	x4step_events_stop_locked(x4,
				  x4step_events_chans_locked(x4, (u8)up.axes));
	ret = x4_engine_set_position(&x4->eng, (u8)up.axes, up.position);
	x4step_motion_halted_locked(x4);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	wake_up_all(&x4->wait); /* a path writer or poller: its queue is gone */
	return x4_req_errno(ret);
}

/* BRAKE, STOP, HALT (the controller's) and ESTOP (any descriptor). */
int x4step_move_halt_ioctl(struct x4_port *x4, unsigned int cmd,
			   void __user *uarg)
{
	switch (cmd) {
	case X4STEP_BRAKE:
		return x4step_ioctl_halt(x4, 0x0f, X4STEP_HALT_BRAKE);
	case X4STEP_STOP:
		return x4step_ioctl_halt(x4, 0x0f, X4STEP_HALT_STOP);
	case X4STEP_HALT:
		return x4step_ioctl_halt_axes(x4, uarg);
	default: /* X4STEP_ESTOP */
		return x4step_ioctl_estop(x4, uarg);
	}
}

/*
 * LOAD, START, MOVE_ENDLESS, GOTO, HOME and SET_POSITION of the
 * controller; lock held.
 */
int x4step_move_ioctl(struct x4_port *x4, unsigned int cmd, void __user *uarg)
{
	union {
		struct x4step_endless endless;
		struct x4step_goto go;
		struct x4step_home home;
	} karg;

	lockdep_assert_held(&x4->lock);
	switch (cmd) {
	case X4STEP_LOAD:
		return x4step_ioctl_load(x4, uarg);
	case X4STEP_START:
		return x4_req_errno(x4step_motion_run(x4, x4step_start_loaded, NULL,
						  X4STEP_KIND_LOADED));
	case X4STEP_MOVE_ENDLESS:
		return x4step_ioctl_run(x4, uarg, &karg.endless,
					sizeof(karg.endless),
					offsetof(struct x4step_endless, result),
					x4step_bad_endless, x4step_run_endless);
	case X4STEP_GOTO:
		return x4step_ioctl_run(x4, uarg, &karg.go, sizeof(karg.go),
					offsetof(struct x4step_goto, result),
					x4step_bad_goto, x4step_run_goto);
	case X4STEP_HOME:
		return x4step_ioctl_run(x4, uarg, &karg.home, sizeof(karg.home),
					offsetof(struct x4step_home, result),
					x4step_bad_home, x4step_run_home);
	default: /* X4STEP_SET_POSITION */
		return x4step_ioctl_set_position(x4, uarg);
	}
}
