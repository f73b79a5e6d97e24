// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: the char device's ioctls. Who may make a request is decided by
 * engine/x4_req.c, as for libx4step's simulated port: the reading
 * requests and ESTOP on any descriptor, the others on the controller's
 * only. The moves and halts are x4step_move.c's, the path's
 * x4step_path.c's; the settings and the reports are here.
 */
#include <linux/fs.h>
#include <linux/slab.h>
#include <linux/uaccess.h>

#include "x4_req.h"
#include "x4step_ioctl.h"
#include "x4step_move.h"
#include "x4step_path.h"
#include "x4step_port.h"

static int x4step_get_status(struct x4_port *x4, struct x4step_status *st)
{
	unsigned long flags;
	int i;

	memset(st, 0, sizeof(*st));
	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone) {
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		return -ENODEV;
	}
	st->inputs = x4step_port_inputs_locked(x4);
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

static int x4step_ioctl_set_profile(struct x4_port *x4,
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

static int x4step_ioctl_get_profile(struct x4_port *x4,
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

static int x4step_ioctl_set_switches(struct x4_port *x4,
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

static int x4step_ioctl_get_switches(struct x4_port *x4, void __user *uarg)
{
	struct x4step_switches us;
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	x4_req_get_switches(&x4->eng, &us);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(uarg, &us, sizeof(us)) ? -EFAULT : 0;
}

static int x4step_ioctl_get_axes(struct x4_port *x4, void __user *uarg)
{
	struct x4step_axes ua;
	unsigned long flags;

	memset(&ua, 0, sizeof(ua));
	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->gone) {
		raw_spin_unlock_irqrestore(&x4->slock, flags);
		return -ENODEV;
	}
	x4_req_get_axes(&x4->eng, x4step_port_inputs_locked(x4), x4->inputs_ns,
			&ua);
	if (!x4->claimed)
		ua.flags = X4STEP_ST_INPUTS_STALE;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(uarg, &ua, sizeof(ua)) ? -EFAULT : 0;
}

/* Set the signals in `mask` to `levels`, in one control register write. */
static void x4step_set_outputs(struct x4_port *x4, u32 mask, u32 levels)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (mask & X4STEP_OUT_SIGNAL1)
		x4_engine_set_signal(&x4->eng, X4_CTL_SIGNAL1,
				     levels & X4STEP_OUT_SIGNAL1);
	if (mask & X4STEP_OUT_SIGNAL2)
		x4_engine_set_signal(&x4->eng, X4_CTL_SIGNAL2,
				     levels & X4STEP_OUT_SIGNAL2);
	x4step_port_write_locked(x4);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/* X4STEP_SET_OUTPUT, ABI 1..3. */
static int x4step_ioctl_output(struct x4_port *x4,
			       struct x4step_output __user *arg)
{
	struct x4step_output out;

	if (copy_from_user(&out, arg, sizeof(out)))
		return -EFAULT;
	if (x4_req_bad_output(&out))
		return -EINVAL;
	x4step_set_outputs(x4, out.signal, out.level ? out.signal : 0);
	return 0;
}

static int x4step_ioctl_outputs(struct x4_port *x4,
				struct x4step_outputs __user *arg)
{
	struct x4step_outputs out;

	if (copy_from_user(&out, arg, sizeof(out)))
		return -EFAULT;
	if (x4_req_bad_outputs(&out))
		return -EINVAL;
	x4step_set_outputs(x4, out.mask, out.levels);
	return 0;
}

static int x4step_ioctl_brake_codes(struct x4_port *x4,
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

static int x4step_ioctl_set_config(struct x4_port *x4,
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
		x4step_port_set_invert(x4, cfg.clock_invert, cfg.dir_invert);
		WRITE_ONCE(x4->cfg_flags, cfg.flags); /* read by the key handler */
		x4step_port_write_rest_locked(x4);
	}
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return x4_req_errno(ret);
}

static int x4step_ioctl_set_step_timing(struct x4_port *x4,
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

static int x4step_ioctl_get_step_timing(struct x4_port *x4, void __user *uarg)
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
static int x4step_ioctl_timing(struct x4_port *x4, struct file *file,
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

static int x4step_ioctl_info(struct x4_port *x4, void __user *uarg)
{
	struct x4step_info info;

	memset(&info, 0, sizeof(info));
	info.abi_version = X4STEP_ABI_VERSION;
	info.axes = X4STEP_AXES;
	info.port = MINOR(x4->dev.devt);
	info.event_buffer = X4_EVENTS;
	return copy_to_user(uarg, &info, sizeof(info)) ? -EFAULT : 0;
}

static int x4step_ioctl_status(struct x4_port *x4, void __user *uarg)
{
	struct x4step_status st;

	if (x4step_get_status(x4, &st))
		return -ENODEV;
	return copy_to_user(uarg, &st, sizeof(st)) ? -EFAULT : 0;
}

static int x4step_ioctl_get_config(struct x4_port *x4, void __user *uarg)
{
	struct x4step_config cfg;
	unsigned long flags;

	memset(&cfg, 0, sizeof(cfg));
	raw_spin_lock_irqsave(&x4->slock, flags); /* as SET_CONFIG */
	cfg.clock_invert = x4->clock_invert;
	cfg.dir_invert = x4->dir_invert;
	cfg.flags = x4->cfg_flags;
	cfg.output_mode = x4->eng.mode;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return copy_to_user(uarg, &cfg, sizeof(cfg)) ? -EFAULT : 0;
}

/* The reading requests, and the emergency halt: any descriptor. */
static long x4step_ioctl_any(struct x4_port *x4, struct file *file,
			     unsigned int cmd, void __user *uarg)
{
	switch (cmd) {
	case X4STEP_GET_INFO:
		return x4step_ioctl_info(x4, uarg);
	case X4STEP_GET_STATUS:
		return x4step_ioctl_status(x4, uarg);
	case X4STEP_GET_CONFIG:
		return x4step_ioctl_get_config(x4, uarg);
	case X4STEP_GET_TIMING:
		return x4step_ioctl_timing(x4, file, uarg,
					   sizeof(struct x4step_timing));
	case X4STEP_GET_TIMING_V2:
		return x4step_ioctl_timing(x4, file, uarg,
					   X4STEP_TIMING_V2_SIZE);
	case X4STEP_GET_STEP_TIMING:
		return x4step_ioctl_get_step_timing(x4, uarg);
	case X4STEP_GET_PROFILE:
		return x4step_ioctl_get_profile(x4, uarg);
	case X4STEP_GET_SWITCHES:
		return x4step_ioctl_get_switches(x4, uarg);
	case X4STEP_GET_AXES:
		return x4step_ioctl_get_axes(x4, uarg);
	case X4STEP_ESTOP:
		return x4step_move_halt_ioctl(x4, cmd, uarg);
	case X4STEP_GET_PATH:
	case X4STEP_GET_PATH_CONFIG:
	case X4STEP_GET_PROBE:
		return x4step_path_ioctl_read(x4, cmd, uarg);
	default:
		return -ENOTTY;
	}
}

/* The controller's requests. */
static long x4step_ioctl_controller(struct x4_port *x4, unsigned int cmd,
				    void __user *uarg)
{
	long ret;

	/* The halts: the raw lock only (the controller's file is held). */
	switch (cmd) {
	case X4STEP_BRAKE:
	case X4STEP_STOP:
	case X4STEP_HALT:
		return x4step_move_halt_ioctl(x4, cmd, uarg);
	case X4STEP_PATH_CTL:
		return x4step_path_ctl_ioctl(x4, uarg);
	}
	mutex_lock(&x4->lock);
	if (x4->gone) {
		ret = -ENODEV;
		goto out;
	}
	switch (cmd) {
	case X4STEP_LOAD:
	case X4STEP_START:
	case X4STEP_MOVE_ENDLESS:
	case X4STEP_GOTO:
	case X4STEP_HOME:
	case X4STEP_SET_POSITION:
		ret = x4step_move_ioctl(x4, cmd, uarg);
		break;
	case X4STEP_SET_PROFILE:
		ret = x4step_ioctl_set_profile(x4, uarg);
		break;
	case X4STEP_SET_SWITCHES:
		ret = x4step_ioctl_set_switches(x4, uarg);
		break;
	case X4STEP_SET_OUTPUT:
		ret = x4step_ioctl_output(x4, uarg);
		break;
	case X4STEP_SET_OUTPUTS:
		ret = x4step_ioctl_outputs(x4, uarg);
		break;
	case X4STEP_SET_BRAKE_CODES:
		ret = x4step_ioctl_brake_codes(x4, uarg);
		break;
	case X4STEP_SET_CONFIG:
		ret = x4step_ioctl_set_config(x4, uarg);
		break;
	case X4STEP_SET_PATH_CONFIG:
		ret = x4step_path_ioctl(x4, cmd, uarg);
		break;
	case X4STEP_SET_STEP_TIMING:
		ret = x4step_ioctl_set_step_timing(x4, uarg);
		break;
	default:
		ret = -ENOTTY;
		break;
	}
out:
	mutex_unlock(&x4->lock);
	return ret;
}

long x4step_ioctl(struct file *file, unsigned int cmd, unsigned long arg)
{
	struct x4_port *x4 = ((struct x4_file *)file->private_data)->x4;
	void __user *uarg = (void __user *)arg;

	switch (x4_req_access(cmd)) {
	case X4_REQ_ANY:
		return x4step_ioctl_any(x4, file, cmd, uarg);
	case X4_REQ_CONTROLLER:
		if (READ_ONCE(x4->controller) != file)
			return -EBADF;
		return x4step_ioctl_controller(x4, cmd, uarg);
	default:
		return -ENOTTY;
	}
}
