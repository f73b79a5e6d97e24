// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: moves on the port. Starting them (the engine call under the raw
 * lock, the timer armed, the event of their start), and braking and
 * stopping them for an ioctl, a brake key or a controller that closes,
 * with the path's part in each halt (the brakes that abort it). Above the
 * timer and the registers (x4step_port.c).
 */
#include <linux/ktime.h>

#include "x4_req.h"
#include "x4step_events.h"
#include "x4step_motion.h"
#include "x4step_port.h"

/*
 * Start moves: `start` is an engine call that starts them at the engine
 * time it is given. The inputs are sampled first, so that a move toward
 * an active limit makes no step. Returns an X4Step result.
 */
int x4step_motion_run(struct x4_port *x4, x4_starter start, const void *arg,
		      u32 kind)
{
	unsigned long flags;
	int ret;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (x4->claimed)
		x4_switch_sense(&x4->eng, x4step_port_inputs_locked(x4));
	ret = start(&x4->eng, arg,
		    ktime_get_ns() - ktime_to_ns(x4->epoch));
	if (ret == X4_OK) {
		x4->last_brake_code = 0;
		x4step_port_arm_locked(x4, 0);
		x4step_events_update_locked(x4, -1, kind);
	}
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return ret;
}

static int x4step_start_planned_goto(struct x4_engine *e, const void *arg,
				     u64 now_ns)
{
	return x4_engine_start_goto(e, arg, now_ns);
}

/*
 * A goto (X4STEP_GOTO): planned, with the divisions and square roots of up
 * to four axes, on a copy of the engine outside the raw lock, so that
 * interrupts stay off only for the start. Caller holds the mutex, which
 * keeps the copy and the plan.
 */
int x4step_motion_goto(struct x4_port *x4, u8 axes, const s32 *target,
		       bool relative)
{
	unsigned long flags;
	int ret;

	lockdep_assert_held(&x4->lock);
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4->plan_eng = x4->eng;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	ret = x4_engine_plan_goto(&x4->plan_eng, axes, target, relative,
				  &x4->plan_goto);
	if (ret)
		return ret;
	return x4step_motion_run(x4, x4step_start_planned_goto, &x4->plan_goto,
				 X4STEP_KIND_GOTO);
}

/*
 * After the engine braked or stopped moves: a stop's writes go out at
 * once, and pollers and readers learn of the moves that ended.
 */
void x4step_motion_halted_locked(struct x4_port *x4)
{
	lockdep_assert_held(&x4->slock);
	x4step_port_write_locked(x4);
	x4step_port_drain_locked(x4, 0); /* a stop's rest patterns, due at 0 */
	x4step_port_note_ends_locked(x4);
	x4step_events_update_locked(x4, -1, 0);
}

/* Whether a brake by `source` aborts the path: there is one. */
bool x4step_motion_path_aborts_locked(struct x4_port *x4, u32 source)
{
	lockdep_assert_held(&x4->slock);
	return x4_req_brake_aborts_path(source, READ_ONCE(x4->path_cfg_flags)) &&
	       x4_path_active(&x4->eng);
}

/*
 * Brake a path: hold it, and flush it too for `source`, held or running.
 * True: it aborted the path.
 */
bool x4step_motion_path_brake_locked(struct x4_port *x4, u32 source)
{
	return x4step_motion_path_aborts_locked(x4, source) &&
	       !x4_track_path_abort(&x4->ev, &x4->eng);
}

/*
 * Brake the moves of the axes in `axes` (and their partners) along their
 * ramps, asked for by `source` (X4STEP_SRC_*; a key: its `code`). An
 * X4Step result: X4_ERR_NOT_ACTIVE if none of them moves and no path was
 * aborted (a held one is, by the sources that abort paths).
 */
int x4step_motion_brake_locked(struct x4_port *x4, u8 axes, u32 source,
			       u32 code)
{
	u8 chans = x4step_events_chans_locked(x4, axes);
	bool aborted;
	int ret;

	lockdep_assert_held(&x4->slock);
	aborted = x4step_motion_path_brake_locked(x4, source);
	ret = x4_engine_halt(&x4->eng, axes, false);
	if (ret == X4_OK) {
		x4->brake_time_ns = ktime_get_ns();
		x4step_events_brake_locked(x4, chans, source, code);
	}
	x4step_motion_halted_locked(x4);
	return aborted ? X4_OK : ret;
}

/* Stop the moves of the axes in `axes` (and their partners) at once. */
int x4step_motion_stop_locked(struct x4_port *x4, u8 axes)
{
	int ret;

	lockdep_assert_held(&x4->slock);
	x4step_events_stop_locked(x4, x4step_events_chans_locked(x4, axes));
	ret = x4_engine_halt(&x4->eng, axes, true);
	x4step_motion_halted_locked(x4);
	irq_work_queue(&x4->wake_work); /* a path writer: its queue is gone */
	return ret;
}

/* A key event: brake if it is ESC or one of the brake codes. */
bool x4step_motion_brake_key(struct x4_port *x4, u32 code)
{
	unsigned long flags;
	bool hit = code == 1;
	u32 i;

	raw_spin_lock_irqsave(&x4->slock, flags);
	for (i = 0; i < x4->n_brake_codes && !hit; i++)
		hit = x4->brake_codes[i] == code;
	/* A key brakes moves, and aborts a held path if keys abort paths. */
	hit = hit && (x4_engine_busy(&x4->eng) ||
		      x4step_motion_path_aborts_locked(x4, X4STEP_SRC_KEY));
	if (hit &&
	    x4step_motion_brake_locked(x4, 0x0f, X4STEP_SRC_KEY, code) == X4_OK)
		x4->last_brake_code = code;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return hit;
}
