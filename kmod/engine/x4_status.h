/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: what an axis is doing (x4_status.c), for GET_AXES and the
 * library's axes status; above the channels (x4_chan.h), reads the state.
 */
#ifndef X4_STATUS_H
#define X4_STATUS_H

#include "x4_state.h"

void x4_status_axis(const struct x4_engine *e, int axis,
		    struct x4_axis_state *st);

#endif /* X4_STATUS_H */
