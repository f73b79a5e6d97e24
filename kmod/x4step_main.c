// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: up to four stepper motors on a PC parallel port.
 *
 * A parport client driver: one char device /dev/x4stepN per parportN,
 * the port claimed exclusively while a controller holds the device open.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/cdev.h>
#include <linux/device.h>
#include <linux/fs.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/parport.h>
#include <linux/slab.h>
#include <linux/version.h>

#include "x4step_dev.h"

static dev_t x4_devt;
static struct class *x4_class;
static struct x4_port *x4_ports[X4_MAX_PORTS];

static int x4_open(struct inode *inode, struct file *file)
{
	struct x4_port *x4 = container_of(inode->i_cdev, struct x4_port, cdev);
	int ret = 0;

	get_device(&x4->dev);
	file->private_data = x4;
	if ((file->f_mode & FMODE_WRITE) == 0)
		return 0;

	mutex_lock(&x4->lock);
	if (x4->gone)
		ret = -ENODEV;
	else if (x4->controller)
		ret = -EBUSY;
	else if (parport_claim(x4->pardev))
		ret = -EBUSY; /* another driver holds the port */
	else
		x4->controller = file;
	mutex_unlock(&x4->lock);
	if (ret)
		put_device(&x4->dev);
	return ret;
}

static int x4_release(struct inode *inode, struct file *file)
{
	struct x4_port *x4 = file->private_data;

	mutex_lock(&x4->lock);
	if (x4->controller == file) {
		x4->controller = NULL;
		if (!x4->gone)
			parport_release(x4->pardev);
	}
	mutex_unlock(&x4->lock);
	put_device(&x4->dev);
	return 0;
}

static const struct file_operations x4_fops = {
	.owner = THIS_MODULE,
	.open = x4_open,
	.release = x4_release,
	.llseek = noop_llseek,
};

static void x4_dev_release(struct device *dev)
{
	kfree(container_of(dev, struct x4_port, dev));
}

static void x4_attach(struct parport *port)
{
	struct pardev_cb cb = { .flags = PARPORT_DEV_EXCL };
	struct x4_port *x4;
	int ret;

	if (port->number >= X4_MAX_PORTS)
		return;
	x4 = kzalloc(sizeof(*x4), GFP_KERNEL);
	if (!x4)
		return;
	mutex_init(&x4->lock);
	x4->port = port;
	cb.private = x4;
	x4->pardev = parport_register_dev_model(port, KBUILD_MODNAME, &cb,
						port->number);
	if (!x4->pardev) {
		pr_err("%s: cannot register device\n", port->name);
		kfree(x4);
		return;
	}

	device_initialize(&x4->dev);
	x4->dev.class = x4_class;
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

	x4_ports[port->number] = x4;
	dev_info(&x4->dev, "on %s\n", port->name);
	return;

err_put:
	pr_err("%s: cannot create device: %d\n", port->name, ret);
	parport_unregister_device(x4->pardev);
	put_device(&x4->dev);
}

static void x4_detach(struct parport *port)
{
	struct x4_port *x4;

	if (port->number >= X4_MAX_PORTS || !x4_ports[port->number])
		return;
	x4 = x4_ports[port->number];
	x4_ports[port->number] = NULL;

	cdev_device_del(&x4->cdev, &x4->dev);
	mutex_lock(&x4->lock);
	x4->gone = true;
	if (x4->controller)
		parport_release(x4->pardev);
	parport_unregister_device(x4->pardev);
	mutex_unlock(&x4->lock);
	put_device(&x4->dev);
}

static struct parport_driver x4_driver = {
	.name = KBUILD_MODNAME,
	.match_port = x4_attach,
	.detach = x4_detach,
#if LINUX_VERSION_CODE < KERNEL_VERSION(6, 7, 0)
	.devmodel = true,
#endif
};

#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 2, 0)
static char *x4_devnode(const struct device *dev, umode_t *mode)
#else
static char *x4_devnode(struct device *dev, umode_t *mode)
#endif
{
	if (mode)
		*mode = 0660; /* group lp, as /dev/parport* (udev rule) */
	return NULL;
}

static int __init x4_init(void)
{
	int ret;

	ret = alloc_chrdev_region(&x4_devt, 0, X4_MAX_PORTS, KBUILD_MODNAME);
	if (ret)
		return ret;
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 4, 0)
	x4_class = class_create(KBUILD_MODNAME);
#else
	x4_class = class_create(THIS_MODULE, KBUILD_MODNAME);
#endif
	if (IS_ERR(x4_class)) {
		ret = PTR_ERR(x4_class);
		goto err_region;
	}
	x4_class->devnode = x4_devnode;
	ret = parport_register_driver(&x4_driver);
	if (ret)
		goto err_class;
	return 0;

err_class:
	class_destroy(x4_class);
err_region:
	unregister_chrdev_region(x4_devt, X4_MAX_PORTS);
	return ret;
}

static void __exit x4_exit(void)
{
	parport_unregister_driver(&x4_driver);
	class_destroy(x4_class);
	unregister_chrdev_region(x4_devt, X4_MAX_PORTS);
}

module_init(x4_init);
module_exit(x4_exit);

MODULE_DESCRIPTION("Stepper motors on the PC parallel port (X4Step)");
MODULE_LICENSE("GPL");
