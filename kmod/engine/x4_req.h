/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: the module's request structs (linux/x4step.h) as the engine
 * takes them. What the char device's glue decides beyond copying them in and
 * out: who may make a request, which fields make it invalid, the engine's
 * arguments made from a request, the X4Step results as errnos, the path's
 * reports. The module (kmod/x4step_*.c) and libx4step's simulated port
 * (lib/sim) both call these, so they answer alike.
 */
#ifndef X4_REQ_H
#define X4_REQ_H

#include <linux/x4step.h>

#include "x4_engine.h"

/* Who may make a request (x4_req_access()). */
enum x4_req_access {
	X4_REQ_UNKNOWN, /* no such request: ENOTTY */
	X4_REQ_ANY, /* any descriptor: the reading requests and ESTOP */
	X4_REQ_CONTROLLER, /* the controller's descriptor only, else EBADF */
};
/* Who may make request `cmd`. */
enum x4_req_access x4_req_access(unsigned int cmd);

/* An X4Step result as the module's errno: 0 or negative. */
int x4_req_errno(int result);
/* The result a request writes back: over the write budget, the API's code. */
s32 x4_req_result(int result);

/* Requests whose fields are invalid in themselves (EINVAL). */
bool x4_req_bad_endless(const struct x4step_endless *ue);
bool x4_req_bad_goto(const struct x4step_goto *ug);
bool x4_req_bad_home(const struct x4step_home *uh);
bool x4_req_bad_halt(const struct x4step_halt *h);
bool x4_req_bad_estop(const struct x4step_estop *es);
bool x4_req_bad_position(const struct x4step_position *up);
bool x4_req_bad_output(const struct x4step_output *o);
bool x4_req_bad_outputs(const struct x4step_outputs *o);
bool x4_req_bad_brake_codes(const struct x4step_brake_codes *bc);
bool x4_req_bad_config(const struct x4step_config *cfg);
bool x4_req_bad_step_timing(const struct x4step_step_timing *ut);
bool x4_req_bad_switches(const struct x4step_switches *us);

/* X4STEP_SET_PROFILE: -EINVAL, or 0 and the engine's profile. */
int x4_req_profile(const struct x4step_profile *up, struct x4_profile *p);
/* X4STEP_SET_SWITCHES' engine switches (after x4_req_bad_switches()). */
void x4_req_switches(const struct x4step_switches *us, struct x4_switches *sw);
/* X4STEP_SET_STEP_TIMING's engine timing. */
void x4_req_step_timing(const struct x4step_step_timing *ut,
			struct x4_timing *t);

/* The answers of X4STEP_GET_SWITCHES, GET_PROFILE, GET_STEP_TIMING. */
void x4_req_get_switches(const struct x4_engine *e, struct x4step_switches *us);
void x4_req_get_profile(const struct x4_engine *e, u32 axis,
			struct x4step_profile *up);
void x4_req_get_step_timing(const struct x4_engine *e,
			    struct x4step_step_timing *ut);
/* X4STEP_GET_AXES' axes and active switches (`inputs` read at `when`). */
void x4_req_get_axes(const struct x4_engine *e, u32 inputs, u64 when,
		     struct x4step_axes *ua);

/* A written segment record as the engine's: an X4Step result. */
int x4_req_segment(const struct x4step_segment *r, struct x4_segment *seg);
/* X4STEP_PATH_CTL's fields are invalid in themselves. */
bool x4_req_bad_path_ctl(const struct x4step_path_ctl *c);
/* X4STEP_SET_PATH_CONFIG's fields are invalid in themselves. */
bool x4_req_bad_path_config(const struct x4step_path_config *c);
/* X4STEP_GET_PATH_CONFIG's answer; `flags` the path flags configured. */
void x4_req_path_config(const struct x4_engine *e, u32 flags,
			struct x4step_path_config *c);
/*
 * X4STEP_SET_PATH_CONFIG's probe input and polarity into the engine (after
 * x4_req_bad_path_config()): an X4Step result.
 */
int x4_req_set_probe(struct x4_engine *e, const struct x4step_path_config *c);
/* X4STEP_GET_PROBE's answer: the engine's probe latch. */
void x4_req_probe(const struct x4_engine *e, struct x4step_probe *up);
/* X4STEP_GET_PATH's answer from the engine's status. */
void x4_req_path_status(const struct x4_path_status *s, u32 flags,
			struct x4step_path_status *st);
/* A brake by `source` (X4STEP_SRC_*) aborts the path, not just holds it. */
bool x4_req_brake_aborts_path(u32 source, u32 path_flags);

#endif /* X4_REQ_H */
