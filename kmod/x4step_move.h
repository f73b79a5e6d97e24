/* SPDX-License-Identifier: GPL-2.0 */
/* x4step: the ioctls that start and halt moves (x4step_move.c). */
#ifndef X4STEP_MOVE_H
#define X4STEP_MOVE_H

#include "x4step_dev.h"

int x4step_move_halt_ioctl(struct x4_port *x4, unsigned int cmd,
			   void __user *uarg);
int x4step_move_ioctl(struct x4_port *x4, unsigned int cmd, void __user *uarg);

#endif /* X4STEP_MOVE_H */
