// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/* x4step engine: the module's request structs as the engine takes them. */
#include "x4_req.h"

#ifdef __KERNEL__
#include <linux/errno.h>
#include <linux/string.h>
#else
#include <errno.h>
#include <string.h>
#endif

enum x4_req_access x4_req_access(unsigned int cmd)
{
	switch (cmd) {
	case X4STEP_GET_INFO:
	case X4STEP_GET_STATUS:
	case X4STEP_GET_CONFIG:
	case X4STEP_GET_TIMING:
	case X4STEP_GET_TIMING_V2:
	case X4STEP_GET_STEP_TIMING:
	case X4STEP_GET_PROFILE:
	case X4STEP_GET_SWITCHES:
	case X4STEP_GET_AXES:
	case X4STEP_GET_PATH:
	case X4STEP_GET_PATH_CONFIG:
	case X4STEP_GET_PROBE:
	case X4STEP_ESTOP: /* the emergency halt, whoever controls the port */
		return X4_REQ_ANY;
	case X4STEP_LOAD:
	case X4STEP_START:
	case X4STEP_BRAKE:
	case X4STEP_STOP:
	case X4STEP_MOVE_ENDLESS:
	case X4STEP_GOTO:
	case X4STEP_HOME:
	case X4STEP_HALT:
	case X4STEP_SET_POSITION:
	case X4STEP_SET_PROFILE:
	case X4STEP_SET_SWITCHES:
	case X4STEP_SET_OUTPUT:
	case X4STEP_SET_OUTPUTS:
	case X4STEP_SET_BRAKE_CODES:
	case X4STEP_SET_CONFIG:
	case X4STEP_SET_STEP_TIMING:
	case X4STEP_SET_PATH_CONFIG:
	case X4STEP_PATH_CTL:
		return X4_REQ_CONTROLLER;
	default:
		return X4_REQ_UNKNOWN;
	}
}

int x4_req_errno(int result)
{
	switch (result) {
	case X4_OK:
		return 0;
	case X4_ERR_IS_ACTIVE:
		return -EBUSY;
	case X4_ERR_IS_LOADED:
		return -EEXIST;
	case X4_ERR_NOT_LOADED:
		return -ENODATA;
	case X4_ERR_NOT_ACTIVE:
		return -ESRCH;
	case X4_ERR_RATE_BUDGET:
		return -ERANGE;
	default:
		return -EINVAL;
	}
}

s32 x4_req_result(int result)
{
	/* Over the write budget: the API's nearest code, errno ERANGE. */
	return result == X4_ERR_RATE_BUDGET ? X4_ERR_FREQ_TOO_HIGH : result;
}

/* Reserved words: any bit set makes a request invalid. */
static bool x4_req_nonzero(const __u32 *w, u32 n)
{
	u32 i;

	for (i = 0; i < n; i++)
		if (w[i])
			return true;
	return false;
}

#define X4_NONZERO(a) x4_req_nonzero((a), sizeof(a) / sizeof((a)[0]))

bool x4_req_bad_endless(const struct x4step_endless *ue)
{
	return (ue->direction != 1 && ue->direction != -1) || ue->flags ||
	       X4_NONZERO(ue->reserved);
}

bool x4_req_bad_goto(const struct x4step_goto *ug)
{
	return ug->axes > 0x0f || ug->flags & ~X4STEP_GOTO_RELATIVE ||
	       X4_NONZERO(ug->reserved);
}

bool x4_req_bad_home(const struct x4step_home *uh)
{
	return uh->phases > (X4STEP_HOME_AUTO | X4STEP_HOME_BRAKE) ||
	       X4_NONZERO(uh->reserved);
}

bool x4_req_bad_halt(const struct x4step_halt *h)
{
	return !h->axes || h->axes > 0x0f || h->how > X4STEP_HALT_STOP ||
	       X4_NONZERO(h->reserved);
}

bool x4_req_bad_estop(const struct x4step_estop *es)
{
	return es->how > X4STEP_HALT_STOP || es->flags ||
	       X4_NONZERO(es->reserved);
}

bool x4_req_bad_position(const struct x4step_position *up)
{
	return !up->axes || up->axes > 0x0f || up->reserved;
}

bool x4_req_bad_output(const struct x4step_output *o)
{
	return (o->signal != X4STEP_OUT_SIGNAL1 &&
		o->signal != X4STEP_OUT_SIGNAL2) || o->level > 1;
}

bool x4_req_bad_outputs(const struct x4step_outputs *o)
{
	const u32 signals = X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2;

	return !o->mask || o->mask & ~signals || o->levels & ~o->mask ||
	       o->flags || X4_NONZERO(o->reserved);
}

bool x4_req_bad_brake_codes(const struct x4step_brake_codes *bc)
{
	u32 i;

	if (bc->reserved || bc->count > X4STEP_MAX_BRAKE_CODES)
		return true;
	for (i = 0; i < bc->count; i++)
		if (!bc->codes[i] || bc->codes[i] > 255)
			return true;
	return false;
}

bool x4_req_bad_config(const struct x4step_config *cfg)
{
	return X4_NONZERO(cfg->reserved) || cfg->clock_invert > 0xf ||
	       cfg->dir_invert > 0xf || cfg->flags & ~X4STEP_CFG_KEYS_SWALLOW ||
	       cfg->output_mode > X4STEP_MODE_SMC_PHASE_HOLD;
}

bool x4_req_bad_step_timing(const struct x4step_step_timing *ut)
{
	return X4_NONZERO(ut->reserved);
}

bool x4_req_bad_switches(const struct x4step_switches *us)
{
	u32 i;

	for (i = 0; i < sizeof(us->reserved); i++)
		if (us->reserved[i])
			return true;
	return false;
}

int x4_req_profile(const struct x4step_profile *up, struct x4_profile *p)
{
	if (X4_NONZERO(up->reserved) || up->axis < 1 || up->axis > X4_AXES)
		return -EINVAL;
	p->v0 = up->v0;
	p->ve = up->ve;
	p->vm = up->vm;
	p->a0 = up->a0;
	p->ae = up->ae;
	return 0;
}

void x4_req_switches(const struct x4step_switches *us, struct x4_switches *sw)
{
	memcpy(sw->ref, us->ref, sizeof(sw->ref));
	memcpy(sw->plus, us->plus, sizeof(sw->plus));
	memcpy(sw->minus, us->minus, sizeof(sw->minus));
	sw->nc = us->nc;
}

void x4_req_step_timing(const struct x4step_step_timing *ut,
			struct x4_timing *t)
{
	t->pulse_ns = ut->pulse_ns;
	t->space_ns = ut->space_ns;
	t->dir_setup_ns = ut->dir_setup_ns;
	t->dir_hold_ns = ut->dir_hold_ns;
}

void x4_req_get_switches(const struct x4_engine *e, struct x4step_switches *us)
{
	memset(us, 0, sizeof(*us));
	memcpy(us->ref, e->sw.ref, sizeof(us->ref));
	memcpy(us->plus, e->sw.plus, sizeof(us->plus));
	memcpy(us->minus, e->sw.minus, sizeof(us->minus));
	us->nc = e->sw.nc;
}

void x4_req_get_profile(const struct x4_engine *e, u32 axis,
			struct x4step_profile *up)
{
	const struct x4_profile *p = &e->prof[axis - 1];

	memset(up, 0, sizeof(*up));
	up->axis = axis;
	up->v0 = p->v0;
	up->ve = p->ve;
	up->vm = p->vm;
	up->a0 = p->a0;
	up->ae = p->ae;
}

void x4_req_get_step_timing(const struct x4_engine *e,
			    struct x4step_step_timing *ut)
{
	memset(ut, 0, sizeof(*ut));
	ut->pulse_ns = e->timing.pulse_ns;
	ut->space_ns = e->timing.space_ns;
	ut->dir_setup_ns = e->timing.dir_setup_ns;
	ut->dir_hold_ns = e->timing.dir_hold_ns;
}

void x4_req_get_axes(const struct x4_engine *e, u32 inputs, u64 when,
		     struct x4step_axes *ua)
{
	struct x4_axis_state st;
	int i;

	ua->inputs = inputs;
	/* Inputs never read (no controller yet) show no active switch. */
	if (when)
		ua->switches = x4_switch_active(e, inputs);
	for (i = 0; i < X4_AXES; i++) {
		x4_status_axis(e, i, &st);
		ua->axis[i].position = st.position;
		ua->axis[i].state = st.state;
		ua->axis[i].error = st.error;
		ua->axis[i].velocity = st.velocity;
	}
}

/* A segment record's flags that must be 0 (ABI 6: the probe flags aside). */
#define X4_SEG_OTHER_FLAGS \
	(~(u32)(X4STEP_SEG_PROBE_TOWARD | X4STEP_SEG_PROBE_AWAY))

int x4_req_segment(const struct x4step_segment *r, struct x4_segment *seg)
{
	u32 other = r->flags & X4_SEG_OTHER_FLAGS;
	int i;

	for (i = 0; i < X4_AXES; i++)
		seg->steps[i] = r->steps[i];
	seg->length = r->length;
	seg->v_max = r->v_max;
	seg->v_entry = r->v_entry;
	seg->accel = r->accel;
	seg->tag = r->tag;
	/* Both probe flags: 3, which x4_segment_check() refuses. */
	seg->probe = (r->flags & X4STEP_SEG_PROBE_TOWARD ? X4_PROBE_TOWARD : 0) |
		     (r->flags & X4STEP_SEG_PROBE_AWAY ? X4_PROBE_AWAY : 0);
	/* libx4step runs the same check before it writes. */
	return x4_segment_check(seg, other | r->reserved);
}

bool x4_req_bad_path_ctl(const struct x4step_path_ctl *c)
{
	return X4_NONZERO(c->reserved) ||
	       (c->value && c->cmd != X4STEP_PATH_OVERRIDE);
}

bool x4_req_bad_path_config(const struct x4step_path_config *c)
{
	if (c->reserved || c->probe > X4_INPUTS ||
	    c->flags & ~(X4STEP_PATH_KEYS_ABORT | X4STEP_PATH_PROBE_NC))
		return true;
	return c->depth && (c->depth < X4STEP_PATH_DEPTH_MIN ||
			    c->depth > X4STEP_PATH_DEPTH_MAX ||
			    c->depth & (c->depth - 1));
}

void x4_req_path_config(const struct x4_engine *e, u32 flags,
			struct x4step_path_config *c)
{
	memset(c, 0, sizeof(*c));
	c->depth = e->path.depth ? e->path.depth : X4STEP_PATH_DEPTH_MIN;
	c->flags = flags & ~X4STEP_PATH_PROBE_NC;
	if (e->path.probe_nc)
		c->flags |= X4STEP_PATH_PROBE_NC;
	c->probe = e->path.probe_input;
}

int x4_req_set_probe(struct x4_engine *e, const struct x4step_path_config *c)
{
	return x4_path_set_probe(e, (u8)c->probe,
				 c->flags & X4STEP_PATH_PROBE_NC);
}

void x4_req_probe(const struct x4_engine *e, struct x4step_probe *up)
{
	const struct x4_probe_latch *l = &e->path.latch;
	int i;

	memset(up, 0, sizeof(*up));
	up->flags = l->tripped ? X4STEP_PROBE_TRIPPED : 0;
	up->input = e->path.probe_input;
	up->tag = l->tag;
	for (i = 0; i < X4_AXES; i++)
		up->position[i] = l->position[i];
	up->runs = l->runs;
	up->trips = l->trips;
}

void x4_req_path_status(const struct x4_path_status *s, u32 flags,
			struct x4step_path_status *st)
{
	memset(st, 0, sizeof(*st));
	st->state = s->state;
	st->queued = s->queued;
	st->depth = s->depth ? s->depth : X4STEP_PATH_DEPTH_MIN;
	st->override = s->override ? s->override : 100;
	st->speed = s->speed;
	st->flags = flags;
	st->tag = s->tag;
	st->done = s->done;
	st->starved = s->starved;
}

bool x4_req_brake_aborts_path(u32 source, u32 path_flags)
{
	return source == X4STEP_SRC_CLOSE || source == X4STEP_SRC_ESTOP ||
	       (source == X4STEP_SRC_KEY && path_flags & X4STEP_PATH_KEYS_ABORT);
}
