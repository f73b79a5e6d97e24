// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: the SMC800/SMC1500 phase drive (SMCMOT.PAS). Instead of
 * clock and direction, the data byte addresses one motor and sets the
 * current and direction of both its phases; a step walks the motor's
 * half-step table. Several motors at one instant are several writes: the
 * first goes out now, the rest are queued on the channel (X4_QUEUED).
 * Calls nothing; the event machine (x4_engine.c) calls it in phase mode.
 */
#include "x4_chan.h"
#include "x4_phase.h"

/*
 * The half-step table MOTRUN and MOTZERO (0 % on both phases). Per phase,
 * bits 0-1 (A) and 3-4 (B) set the current (11 0 %, 01 20 %, 10 60 %,
 * 00 100 %), bits 2 and 5 its direction; bits 6-7 select the motor.
 */
static const u8 smc_run[8] = { 0x03, 0x09, 0x38, 0x29, 0x27, 0x2d, 0x1c, 0x0d };
#define SMC_OFF 0x1b
#define SMC_SELECT(motor) ((u8)((motor) << 6))

/* Reduced holding current: phases at 100 % drop to 20 %. */
static u8 smc_hold(u8 pattern)
{
	if (!(pattern & 0x03))
		pattern |= 0x01;
	if (!(pattern & 0x18))
		pattern |= 0x08;
	return pattern;
}

/*
 * Writes due at time t: the first now, the rest queued at the same t,
 * before whatever c->phase and c->t_pending were going to be next.
 */
static void emit(struct x4_engine *e, struct x4_chan *c, const u8 *bytes,
		 int n, u64 t)
{
	int i;

	if (!n)
		return;
	e->data = bytes[0];
	if (n < 2)
		return;
	c->queued = 0;
	c->qhead = 0;
	for (i = 1; i < n; i++)
		c->queue[c->queued++] = bytes[i];
	c->phase_after = c->phase;
	c->t_after = c->t_pending;
	c->phase = X4_QUEUED;
	c->t_pending = t;
}

/* Phase-mode writes of the motors in `axes`: moving or resting. */
static int smc_patterns(const struct x4_engine *e, u8 axes, bool rest,
			u8 *bytes)
{
	int m, n = 0;

	for (m = 0; m < X4_SMC_AXES; m++) {
		u8 run = smc_run[e->smc_phase[m]];

		if (!(axes & (1u << m)))
			continue;
		if (rest)
			run = e->mode == X4_MODE_SMC_PHASE_HOLD ? smc_hold(run) :
								  SMC_OFF;
		bytes[n++] = run | SMC_SELECT(m);
	}
	return n;
}

int x4_phase_rest_writes(const struct x4_engine *e, u8 *bytes)
{
	if (!x4_chan_phase_mode(e)) {
		bytes[0] = e->data & X4_DIR_MASK;
		return 1;
	}
	return smc_patterns(e, 0x07, true, bytes);
}

/* The writes of a move's start: the patterns of its motors. */
void x4_phase_move(struct x4_engine *e, struct x4_chan *c, u64 t)
{
	u8 bytes[X4_SMC_AXES];

	emit(e, c, bytes, smc_patterns(e, c->run.axes, false, bytes), t);
}

/* Channel c ended: every motor not driven by another move goes to rest. */
void x4_phase_rest(struct x4_engine *e, struct x4_chan *c)
{
	u8 bytes[X4_SMC_AXES], others = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (e->ch[i].phase != X4_IDLE)
			others |= e->ch[i].run.axes;
	emit(e, c, bytes, smc_patterns(e, 0x07 & ~others, true, bytes),
	     c->t_pending);
}

/* The axes whose clock bits are set in clk. */
static u8 clk_axes(u8 clk)
{
	u8 axes = 0;
	int i;

	for (i = 0; i < X4_AXES; i++)
		if (clk & X4_CLK_BIT(i))
			axes |= 1u << i;
	return axes;
}

/*
 * Phase mode: walk the table of each motor that steps, in the directions
 * of the plan that made the step (before a path's next segment replaces it).
 */
void x4_phase_walk(struct x4_engine *e, struct x4_chan *c)
{
	int m;

	for (m = 0; m < X4_SMC_AXES; m++)
		if (c->stepping & X4_CLK_BIT(m))
			e->smc_phase[m] = (e->smc_phase[m] + c->run.sign[m]) & 7;
}

/* Phase mode: write the patterns of the motors that stepped. */
void x4_phase_step(struct x4_engine *e, struct x4_chan *c, u64 t)
{
	u8 bytes[X4_SMC_AXES];

	emit(e, c, bytes, smc_patterns(e, clk_axes(c->stepping), false, bytes),
	     t);
}

/* The next of the writes queued at one instant. */
void x4_phase_queued(struct x4_engine *e, struct x4_chan *c)
{
	e->data = c->queue[c->qhead++];
	if (c->qhead == c->queued) {
		c->phase = c->phase_after;
		c->t_pending = c->t_after;
	}
}
