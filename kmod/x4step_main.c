// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: up to four stepper motors on a PC parallel port.
 *
 * A parport client driver: one char device /dev/x4stepN per parportN
 * (the `ports` parameter chooses which), the port claimed while a
 * controller holds the device open, and until the brake of its last
 * moves has ended; the rest of the time lp, ppdev and others may use it.
 * Here: the parport client, the file operations and the module's start
 * and end; the ioctls are x4step_ioctl.c's.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/cdev.h>
#include <linux/device.h>
#include <linux/fs.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/parport.h>
#include <linux/poll.h>
#include <linux/slab.h>
#include <linux/workqueue.h>

#include "x4step_compat.h"
#include "x4step_events.h"
#include "x4step_ioctl.h"
#include "x4step_keys.h"
#include "x4step_path.h"
#include "x4step_motion.h"
#include "x4step_port.h"
#include "x4step_registry.h"

static dev_t x4_devt;
static struct class *x4_class;

static bool x4step_busy(struct x4_port *x4)
{
	unsigned long flags;
	bool busy;

	raw_spin_lock_irqsave(&x4->slock, flags);
	busy = x4_engine_busy(&x4->eng);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return busy;
}

static struct x4_port *x4step_of(struct file *file)
{
	return ((struct x4_file *)file->private_data)->x4;
}

static int x4step_open(struct inode *inode, struct file *file)
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
	x4step_events_open(x4, xf);
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
		x4step_port_claimed(x4);
		raw_spin_lock_irqsave(&x4->slock, flags);
		x4step_events_controller_locked(x4, X4STEP_CTL_OPENED);
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
static void x4step_let_go(struct x4_port *x4)
{
	unsigned long flags;

	lockdep_assert_held(&x4->lock);
	/* Before the wake-up in quiesce: pollers see the port free. */
	WRITE_ONCE(x4->releasing, false);
	x4step_port_quiesce(x4);
	parport_release(x4->pardev);
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4step_events_controller_locked(x4, X4STEP_CTL_RELEASED);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/*
 * The deferred release: once the brake started by x4step_release() has ended,
 * the port goes back to the parport core and a new controller may open.
 * It looks every few ms: the end of the moves is signalled only to the
 * wait queue, by the hard-irq timer's irq_work. x4step_detach() cancels it.
 */
static void x4step_release_work(struct work_struct *work)
{
	struct x4_port *x4 = container_of(to_delayed_work(work), struct x4_port,
					  release_work);

	mutex_lock(&x4->lock);
	if (x4->releasing) {
		if (x4step_busy(x4))
			schedule_delayed_work(&x4->release_work,
					      X4_RELEASE_POLL);
		else
			x4step_let_go(x4);
	}
	mutex_unlock(&x4->lock);
}

/*
 * The controller went away (closed, or killed): brake what runs along its
 * ramp and return at once. A brake may take minutes (profiles allow
 * ramps of an hour), so the port is released by x4step_release_work() when
 * the engine is idle; until then the port stays claimed and the
 * controller slot taken. Nothing here waits for the motors.
 */
static int x4step_release(struct inode *inode, struct file *file)
{
	struct x4_file *xf = file->private_data;
	struct x4_port *x4 = xf->x4;
	unsigned long flags;
	bool busy;

	mutex_lock(&x4->lock);
	if (x4->controller == file) {
		WRITE_ONCE(x4->controller, NULL);
		if (!x4->gone) { /* else x4step_detach() released the port */
			raw_spin_lock_irqsave(&x4->slock, flags);
			x4step_events_controller_locked(x4, X4STEP_CTL_CLOSED);
			x4step_motion_path_brake_locked(x4, X4STEP_SRC_CLOSE);
			if (x4_engine_busy(&x4->eng))
				x4step_motion_brake_locked(x4, 0x0f,
							   X4STEP_SRC_CLOSE, 0);
			busy = x4_engine_busy(&x4->eng);
			raw_spin_unlock_irqrestore(&x4->slock, flags);
			if (busy) {
				WRITE_ONCE(x4->releasing, true);
				schedule_delayed_work(&x4->release_work,
						      X4_RELEASE_POLL);
			} else {
				x4step_let_go(x4);
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
static __poll_t x4step_poll(struct file *file, struct poll_table_struct *wait)
{
	struct x4_file *xf = file->private_data;
	struct x4_port *x4 = xf->x4;
	__poll_t events;

	poll_wait(file, &x4->wait, wait);
	events = x4step_events_poll(x4, xf);
	if (events & EPOLLHUP) /* PORT_GONE is in the ring */
		return events;
	/*
	 * Idle, and the brake of a controller that closed is over: once
	 * this reports POLLIN, a new controller may open.
	 */
	events |= x4step_path_poll(x4, file);
	if (x4step_busy(x4) || READ_ONCE(x4->releasing))
		return events;
	return events | EPOLLIN | EPOLLRDNORM;
}

static ssize_t x4step_read(struct file *file, char __user *buf, size_t count,
			   loff_t *ppos)
{
	struct x4_file *xf = file->private_data;

	return x4step_events_read(xf->x4, xf, file, buf, count);
}

/* Path segments (ABI 5), from the controller: x4step_path.c. */
static ssize_t x4step_write(struct file *file, const char __user *buf,
			    size_t count, loff_t *ppos)
{
	if (READ_ONCE(x4step_of(file)->controller) != file)
		return -EBADF;
	return x4step_path_write(x4step_of(file), file, buf, count);
}

static const struct file_operations x4_fops = {
	.owner = THIS_MODULE,
	.open = x4step_open,
	.release = x4step_release,
	.poll = x4step_poll,
	.read = x4step_read,
	.write = x4step_write,
	.unlocked_ioctl = x4step_ioctl,
	.compat_ioctl = compat_ptr_ioctl,
	.llseek = noop_llseek,
};

static void x4step_dev_release(struct device *dev)
{
	struct x4_port *x4 = container_of(dev, struct x4_port, dev);

	parport_put_port(x4->port);
	x4step_events_free(x4);
	x4step_path_free(x4);
	kfree(x4);
}

/* The parport numbers x4step serves (none given: all of them). */
static int ports[X4_MAX_PORTS];
static int n_ports;
module_param_array(ports, int, &n_ports, 0444);
MODULE_PARM_DESC(ports, "parport numbers to serve, e.g. ports=0,2 (default: every port)");

static bool x4step_serves(struct parport *port)
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
 * only while a controller has /dev/x4stepN open (x4step_open()).
 */
static void x4step_attach(struct parport *port)
{
	struct pardev_cb cb = { };
	struct x4_port *x4;
	int ret;

	if (!x4step_serves(port))
		return;
	x4 = kzalloc(sizeof(*x4), GFP_KERNEL);
	if (!x4)
		return;
	if (x4step_events_alloc(x4)) {
		kfree(x4);
		return;
	}
	mutex_init(&x4->lock);
	x4step_path_init(x4);
	INIT_DELAYED_WORK(&x4->release_work, x4step_release_work);
	x4step_port_init(x4);
	/* Held until the last file closes: the port may go away first. */
	x4->port = parport_get_port(port);
	cb.private = x4;
	x4->pardev = parport_register_dev_model(port, KBUILD_MODNAME, &cb,
						port->number);
	if (!x4->pardev) {
		/* e.g. plip has the port exclusively: see `ports` */
		pr_err("%s: cannot register device\n", port->name);
		parport_put_port(port);
		x4step_events_free(x4);
		kfree(x4);
		return;
	}

	device_initialize(&x4->dev);
	x4->dev.class = x4_class;
	x4->dev.parent = port->dev; /* in sysfs under the port, as ppdev */
	x4->dev.devt = MKDEV(MAJOR(x4_devt), port->number);
	x4->dev.release = x4step_dev_release;
	cdev_init(&x4->cdev, &x4_fops);
	x4->cdev.owner = THIS_MODULE;
	ret = dev_set_name(&x4->dev, "x4step%d", port->number);
	if (ret)
		goto err_put;
	ret = cdev_device_add(&x4->cdev, &x4->dev);
	if (ret)
		goto err_put;

	x4step_registry_add(x4, port->number);
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
static void x4step_detach(struct parport *port)
{
	unsigned long flags;
	struct x4_port *x4;

	x4 = x4step_registry_remove(port->number); /* keys see it no more */
	if (!x4)
		return;

	cdev_device_del(&x4->cdev, &x4->dev);
	mutex_lock(&x4->lock);
	x4step_port_gone(x4);
	if (x4->releasing)
		dev_warn(&x4->dev, "port removed while braking: stopped\n");
	if (x4->controller || x4->releasing) {
		WRITE_ONCE(x4->releasing, false);
		x4step_port_quiesce(x4);
		parport_release(x4->pardev);
	}
	parport_unregister_device(x4->pardev);
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4step_events_gone_locked(x4);
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	mutex_unlock(&x4->lock);
	/*
	 * With `gone` set, nothing queues the release work again: after
	 * this it neither runs nor is pending (module unload, kfree).
	 */
	cancel_delayed_work_sync(&x4->release_work);
	x4step_path_stop(x4);
	hrtimer_cancel(&x4->timer);
	irq_work_sync(&x4->wake_work);
	wake_up_all(&x4->wait);
	put_device(&x4->dev);
}

static struct parport_driver x4_driver = {
	.name = KBUILD_MODNAME,
	.match_port = x4step_attach,
	.detach = x4step_detach,
	X4_PARPORT_DEVMODEL
};

static char *x4step_devnode(X4_DEVNODE_CONST struct device *dev, umode_t *mode)
{
	if (mode)
		*mode = 0660; /* group lp, as /dev/parport* (udev rule) */
	return NULL;
}

static int __init x4step_init(void)
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
	x4_class->devnode = x4step_devnode;
	/*
	 * The brake keys first: once the parport driver is registered, the
	 * devices can be opened, and nothing may fail after that.
	 */
	ret = x4step_keys_init();
	if (ret)
		goto err_class;
	ret = parport_register_driver(&x4_driver);
	if (ret)
		goto err_keys;
	return 0;

err_keys:
	x4step_keys_exit();
err_class:
	class_destroy(x4_class);
err_region:
	unregister_chrdev_region(x4_devt, X4_MAX_PORTS);
	return ret;
}

static void __exit x4step_exit(void)
{
	parport_unregister_driver(&x4_driver); /* detaches every port */
	x4step_keys_exit();
	class_destroy(x4_class);
	unregister_chrdev_region(x4_devt, X4_MAX_PORTS);
}

module_init(x4step_init);
module_exit(x4step_exit);

MODULE_DESCRIPTION("Stepper motors on the PC parallel port (X4Step)");
MODULE_LICENSE("GPL");
