/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: moves on the port (x4step_motion.c): started, braked, stopped;
 * above the timer and the registers (x4step_port.h). The *_locked
 * functions need the port's raw lock (slock).
 */
#ifndef X4STEP_MOTION_H
#define X4STEP_MOTION_H

#include "x4step_dev.h"

/* Engine calls that start moves, with the ioctl's arguments. */
typedef int (*x4_starter)(struct x4_engine *e, const void *arg, u64 now_ns);
int x4step_motion_run(struct x4_port *x4, x4_starter start, const void *arg,
		      u32 kind);
int x4step_motion_goto(struct x4_port *x4, u8 axes, const s32 *target,
		       bool relative);

void x4step_motion_halted_locked(struct x4_port *x4);
int x4step_motion_brake_locked(struct x4_port *x4, u8 axes, u32 source,
			       u32 code);
int x4step_motion_stop_locked(struct x4_port *x4, u8 axes);
bool x4step_motion_brake_key(struct x4_port *x4, u32 code);

/* A path's part in the halts (paths: x4step_path.c). */
bool x4step_motion_path_aborts_locked(struct x4_port *x4, u32 source);
bool x4step_motion_path_brake_locked(struct x4_port *x4, u32 source);

#endif /* X4STEP_MOTION_H */
