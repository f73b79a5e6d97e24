/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: the event stream of a port (x4step_events.c), the lowest of the
 * module's parts. The *_locked functions need the port's raw lock.
 */
#ifndef X4STEP_EVENTS_H
#define X4STEP_EVENTS_H

#include <linux/fs.h>
#include <linux/poll.h>

#include "x4step_dev.h"

int x4step_events_alloc(struct x4_port *x4);
void x4step_events_free(struct x4_port *x4);
u8 x4step_events_chans_locked(struct x4_port *x4, u8 axes);
void x4step_events_brake_locked(struct x4_port *x4, u8 chans, u32 source,
				u32 code);
void x4step_events_stop_locked(struct x4_port *x4, u8 chans);
void x4step_events_controller_locked(struct x4_port *x4, u32 how);
void x4step_events_gone_locked(struct x4_port *x4);
void x4step_events_update_locked(struct x4_port *x4, int c, u32 kind);
void x4step_events_fired_locked(struct x4_port *x4, int c);
void x4step_events_open(struct x4_port *x4, struct x4_file *xf);
__poll_t x4step_events_poll(struct x4_port *x4, struct x4_file *xf);
ssize_t x4step_events_read(struct x4_port *x4, struct x4_file *xf,
			   struct file *file, char __user *buf, size_t count);

#endif /* X4STEP_EVENTS_H */
