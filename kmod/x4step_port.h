/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: the engine on the port registers, paced by the step timer
 * (x4step_port.c); above the event stream, below the moves
 * (x4step_motion.h). The *_locked functions need the port's raw lock
 * (slock).
 */
#ifndef X4STEP_PORT_H
#define X4STEP_PORT_H

#include "x4step_dev.h"

void x4step_port_init(struct x4_port *x4);
void x4step_port_claimed(struct x4_port *x4);
void x4step_port_quiesce(struct x4_port *x4);
void x4step_port_gone(struct x4_port *x4);

void x4step_port_arm_locked(struct x4_port *x4, ktime_t earliest);
void x4step_port_drain_locked(struct x4_port *x4, u64 until);
void x4step_port_note_ends_locked(struct x4_port *x4);
void x4step_port_room_locked(struct x4_port *x4);

void x4step_port_write_locked(struct x4_port *x4);
void x4step_port_set_invert(struct x4_port *x4, u8 clock_invert,
			    u8 dir_invert);
void x4step_port_write_rest_locked(struct x4_port *x4);
u32 x4step_port_inputs_locked(struct x4_port *x4);

#endif /* X4STEP_PORT_H */
