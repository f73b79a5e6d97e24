/* SPDX-License-Identifier: GPL-2.0 */
/* x4step: the char device's ioctls (x4step_ioctl.c). */
#ifndef X4STEP_IOCTL_H
#define X4STEP_IOCTL_H

#include <linux/fs.h>

long x4step_ioctl(struct file *file, unsigned int cmd, unsigned long arg);

#endif /* X4STEP_IOCTL_H */
