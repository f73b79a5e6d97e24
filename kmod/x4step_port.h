/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: the engine on the port registers, paced by the step timer
 * (x4step_port.c). Below the files, the ioctls, paths and keys; above the
 * event stream. The *_locked functions need the port's raw lock (slock).
 */
#ifndef X4STEP_PORT_H
#define X4STEP_PORT_H

#include "x4step_dev.h"

void x4step_port_init(struct x4_port *x4);
void x4step_port_claimed(struct x4_port *x4);
void x4step_port_quiesce(struct x4_port *x4);
void x4step_port_gone(struct x4_port *x4);

/* Engine calls that start moves, with the ioctl's arguments. */
typedef int (*x4_starter)(struct x4_engine *e, const void *arg, u64 now_ns);
int x4step_port_run(struct x4_port *x4, x4_starter start, const void *arg,
		    u32 kind);
int x4step_port_goto(struct x4_port *x4, u8 axes, const s32 *target,
		     bool relative);

void x4step_port_halted_locked(struct x4_port *x4);
int x4step_port_brake_locked(struct x4_port *x4, u8 axes, u32 source,
			     u32 code);
int x4step_port_stop_locked(struct x4_port *x4, u8 axes);
bool x4step_port_brake_key(struct x4_port *x4, u32 code);

/* A path's part in the halts and the timer's work (paths: x4step_path.c). */
bool x4step_port_path_aborts_locked(struct x4_port *x4, u32 source);
bool x4step_port_path_brake_locked(struct x4_port *x4, u32 source);
void x4step_port_room_locked(struct x4_port *x4);

void x4step_port_write_locked(struct x4_port *x4);
void x4step_port_set_invert(struct x4_port *x4, u8 clock_invert,
			    u8 dir_invert);
void x4step_port_write_rest_locked(struct x4_port *x4);
u32 x4step_port_inputs_locked(struct x4_port *x4);

#endif /* X4STEP_PORT_H */
