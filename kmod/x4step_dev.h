/* SPDX-License-Identifier: GPL-2.0 */
/* x4step: per-port state shared by the module's parts. */
#ifndef X4STEP_DEV_H
#define X4STEP_DEV_H

#include <linux/cdev.h>
#include <linux/device.h>
#include <linux/mutex.h>

#include "x4_engine.h"

#define X4_MAX_PORTS 16 /* minors: parport numbers 0..15 */

struct x4_port {
	struct device dev; /* lifetime: last of the files and the port */
	struct cdev cdev;
	struct parport *port;
	struct pardevice *pardev;
	struct mutex lock; /* controller, gone, claim */
	struct file *controller; /* the one read-write opener */
	bool gone; /* the parport went away */
};

#endif /* X4STEP_DEV_H */
