/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: continuous paths (x4step_path.c): write() of segments and the
 * path's ioctls, above the port (x4step_port.h).
 */
#ifndef X4STEP_PATH_H
#define X4STEP_PATH_H

#include <linux/fs.h>
#include <linux/poll.h>

#include "x4step_dev.h"

void x4step_path_init(struct x4_port *x4);
void x4step_path_stop(struct x4_port *x4);
void x4step_path_free(struct x4_port *x4);
ssize_t x4step_path_write(struct x4_port *x4, struct file *file,
			  const char __user *buf, size_t count);
__poll_t x4step_path_poll(struct x4_port *x4, struct file *file);
int x4step_path_ioctl(struct x4_port *x4, unsigned int cmd,
		      void __user *uarg);
int x4step_path_ctl_ioctl(struct x4_port *x4, void __user *uarg);
int x4step_path_ioctl_read(struct x4_port *x4, unsigned int cmd,
			   void __user *uarg);

#endif /* X4STEP_PATH_H */
