/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: the channels (x4_chan.c), the level above the plan maths
 * that every part of the engine calls (x4_switch.c, x4_path.c, x4_phase.c,
 * x4_status.c, x4_engine.c); and the helpers they share. The engine's own:
 * the glue and the tests use x4_engine.h.
 */
#ifndef X4_CHAN_H
#define X4_CHAN_H

#include "x4_state.h"

static inline bool x4_chan_phase_mode(const struct x4_engine *e)
{
	return e->mode != X4_MODE_CLOCK_DIR;
}

/* The direction bits of the axes in `axes`. */
static inline u8 x4_chan_dir_bits(u8 axes)
{
	u8 bits = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (axes & (1u << i))
			bits |= X4_DIR_BIT(i);
	return bits;
}

/* The clock bits of the axes in `axes`. */
static inline u8 x4_chan_clk_bits(u8 axes)
{
	return (u8)(x4_chan_dir_bits(axes) << 1);
}

/* The clock bits of plan p's axes whose direction pin must change. */
static inline u8 x4_chan_dir_changes(const struct x4_engine *e,
				const struct x4_plan *p)
{
	return (u8)((x4_chan_dir_bits(p->axes) & (e->data ^ p->dirs)) << 1);
}

/* Axis i's coordinate. */
static inline s32 x4_chan_position(const struct x4_engine *e, int i)
{
	return (s32)(e->pos_base[i] + (u32)e->steps[i]);
}

/* Rounded Bresenham: the minor axes start half a step along. */
static inline void x4_chan_bres_start(struct x4_chan *c)
{
	int i;

	for (i = 0; i < X4_AXES; i++)
		c->bres[i] = c->run.bres_2l / 2;
}

/* The input bit of an input number 1..5, 0 for none. */
static inline u8 x4_chan_input_bit(u8 input)
{
	return input ? (u8)(1u << (input - 1)) : 0;
}

/* The limit switch input that axis i of plan p moves toward. */
static inline u8 x4_chan_limit_bit(const struct x4_engine *e,
				   const struct x4_plan *p, int i)
{
	return x4_chan_input_bit(p->sign[i] > 0 ? e->sw.plus[i] : e->sw.minus[i]);
}

/*
 * A path is active (x4_path_active()): it runs, holds or stands held, or
 * has segments queued. It owns every axis of the output mode then.
 */
static inline bool x4_chan_path_active(const struct x4_engine *e)
{
	const struct x4_path *pa = &e->path;

	return pa->state != X4_PATH_IDLE || pa->head != x4_read_once(pa->tail);
}

void x4_chan_begin(struct x4_engine *e, struct x4_chan *c, u64 now_ns);
void x4_chan_cut(struct x4_chan *c);
void x4_chan_halt(struct x4_chan *c, bool ramp);
u8 x4_chan_mode_axes(const struct x4_engine *e);
u8 x4_chan_busy_axes(const struct x4_engine *e);
u32 x4_chan_writes_per_step(const struct x4_engine *e, u8 axes);
u32 x4_chan_plan_rate(const struct x4_engine *e, const struct x4_plan *p);
int x4_chan_budget_check(const struct x4_engine *e, u64 add);
int x4_chan_freq_check(const struct x4_engine *e, s32 freq_hz);
void x4_chan_fold_steps(struct x4_engine *e, u8 axes);
void x4_chan_schedule_all(struct x4_engine *e);
void x4_chan_arm_switches(struct x4_engine *e, struct x4_chan *c);

#endif /* X4_CHAN_H */
