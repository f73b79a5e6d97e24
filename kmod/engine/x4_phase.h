/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: the SMC800/SMC1500 phase output (x4_phase.c), above the
 * channels (x4_chan.h) and below the event machine (x4_engine.h).
 */
#ifndef X4_PHASE_H
#define X4_PHASE_H

#include "x4_state.h"

/* What the port shows at rest: 1 byte, or one per SMC motor (3). */
int x4_phase_rest_writes(const struct x4_engine *e, u8 *bytes);

/* For the event machine (x4_engine.c), in phase mode. */
void x4_phase_move(struct x4_engine *e, struct x4_chan *c, u64 t);
void x4_phase_rest(struct x4_engine *e, struct x4_chan *c);
void x4_phase_walk(struct x4_engine *e, struct x4_chan *c);
void x4_phase_step(struct x4_engine *e, struct x4_chan *c, u64 t);
void x4_phase_queued(struct x4_engine *e, struct x4_chan *c);

#endif /* X4_PHASE_H */
