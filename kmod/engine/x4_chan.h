/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: what its files share with each other and with nobody
 * else (the glue and the tests use x4_engine.h).
 */
#ifndef X4_CHAN_H
#define X4_CHAN_H

#include "x4_engine.h"

static inline bool x4_phase_mode(const struct x4_engine *e)
{
	return e->mode != X4_MODE_CLOCK_DIR;
}

/* The direction bits of the axes in `axes`. */
static inline u8 x4_dir_bits(u8 axes)
{
	u8 bits = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (axes & (1u << i))
			bits |= X4_DIR_BIT(i);
	return bits;
}

/* The clock bits of the axes in `axes`. */
static inline u8 x4_clk_bits(u8 axes)
{
	return (u8)(x4_dir_bits(axes) << 1);
}

/* The clock bits of plan p's axes whose direction pin must change. */
static inline u8 x4_dir_changes(const struct x4_engine *e,
				const struct x4_plan *p)
{
	return (u8)((x4_dir_bits(p->axes) & (e->data ^ p->dirs)) << 1);
}

/* Axis i's coordinate. */
static inline s32 x4_position(const struct x4_engine *e, int i)
{
	return (s32)(e->pos_base[i] + (u32)e->steps[i]);
}

/* Rounded Bresenham: the minor axes start half a step along. */
static inline void x4_bres_start(struct x4_chan *c)
{
	int i;

	for (i = 0; i < X4_AXES; i++)
		c->bres[i] = c->run.bres_2l / 2;
}

/* x4_engine.c: channels */
void x4_begin(struct x4_engine *e, struct x4_chan *c, u64 now_ns);
void x4_cut(struct x4_chan *c);
void x4_halt_chan(struct x4_chan *c, bool ramp);
void x4_end(struct x4_engine *e, struct x4_chan *c);
u8 x4_mode_axes(const struct x4_engine *e);
u8 x4_busy_axes(const struct x4_engine *e);
u32 x4_writes_per_step(const struct x4_engine *e, u8 axes);
int x4_budget_check(const struct x4_engine *e, u64 add);
int x4_freq_check(const struct x4_engine *e, s32 freq_hz);

/* x4_switch.c: switches and reference runs */
void x4_arm_switches(struct x4_engine *e, struct x4_chan *c);
void x4_halted(struct x4_engine *e, struct x4_chan *c, u8 hit);
bool x4_home_next(struct x4_engine *e, struct x4_chan *c);

/* x4_path.c: the path's pieces, on channel 0 */
bool x4_path_next(struct x4_engine *e, struct x4_chan *c);
u64 x4_path_end_half(const struct x4_engine *e, u64 half_ns);
bool x4_path_ended(struct x4_engine *e, struct x4_chan *c);

/* x4_phase.c: the SMC phase output */
void x4_phase_move(struct x4_engine *e, struct x4_chan *c, u64 t);
void x4_phase_rest(struct x4_engine *e, struct x4_chan *c);
void x4_phase_walk(struct x4_engine *e, struct x4_chan *c);
void x4_phase_step(struct x4_engine *e, struct x4_chan *c, u64 t);
void x4_phase_queued(struct x4_engine *e, struct x4_chan *c);

#endif /* X4_CHAN_H */
