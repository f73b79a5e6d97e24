// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: the argument checks (x4_check.h). Calls nothing.
 */
#include "x4_check.h"

int x4_ramp_check(s32 freq_hz, s32 ramp_ms)
{
	if (freq_hz > X4_FREQ_MAX_HZ)
		return X4_ERR_FREQ_TOO_HIGH;
	if (freq_hz < X4_FREQ_MIN_HZ)
		return X4_ERR_FREQ_TOO_LOW;
	if (ramp_ms > X4_RAMP_MAX_MS)
		return X4_ERR_RAMP_TOO_HIGH;
	if (ramp_ms < 0)
		return X4_ERR_PARAM_FAIL;
	if (ramp_ms > freq_hz)
		return X4_ERR_RAMP_FREQ;
	return X4_OK;
}

/*
 * Arguments are checked before state, in this order (documented in
 * x4step.h): frequency, ramp, paths; then loaded, then active.
 */
int x4_move_check(const struct x4_move *m)
{
	int ret = x4_ramp_check(m->freq_hz, m->ramp_ms);
	bool any = false;
	int i;

	if (ret)
		return ret;
	for (i = 0; i < X4_AXES; i++) {
		if (m->steps[i] > X4_STEPS_MAX || m->steps[i] < -X4_STEPS_MAX)
			return X4_ERR_STEPS_TOO_HIGH;
		any |= m->steps[i] != 0;
	}
	return any ? X4_OK : X4_ERR_NO_STEPS;
}

int x4_profile_check(const struct x4_profile *p)
{
	if (!p->vm || p->vm > X4_VEL_MAX || p->v0 > p->vm || p->ve > p->vm ||
	    p->a0 > X4_ACC_MAX || p->ae > X4_ACC_MAX ||
	    x4_ramp_too_long(p->vm, p->a0) || x4_ramp_too_long(p->vm, p->ae))
		return X4_ERR_PARAM_FAIL;
	return X4_OK;
}

int x4_timing_check(const struct x4_timing *t, u8 mode)
{
	if (t->pulse_ns > X4_TIMING_MAX_NS ||
	    (t->pulse_ns && t->pulse_ns < X4_PULSE_MIN_NS) ||
	    t->space_ns > X4_TIMING_MAX_NS ||
	    t->dir_setup_ns > X4_TIMING_MAX_NS ||
	    t->dir_hold_ns > X4_TIMING_MAX_NS || mode > X4_MODE_SMC_PHASE_HOLD)
		return X4_ERR_PARAM_FAIL;
	return X4_OK;
}

static bool vref_ok(s32 v)
{
	return v && v <= X4_VEL_MAX && v >= -X4_VEL_MAX;
}

int x4_home_check(u8 phases, s32 vref1, s32 vref2, u32 sref)
{
	if (!(phases & (X4_HOME_PHASE1 | X4_HOME_PHASE2)) ||
	    phases & ~(X4_HOME_PHASE1 | X4_HOME_PHASE2 | X4_HOME_BRAKE) ||
	    (phases & X4_HOME_BRAKE && !(phases & X4_HOME_PHASE1)) ||
	    (phases & X4_HOME_PHASE1 && !vref_ok(vref1)) ||
	    (phases & X4_HOME_PHASE2 && !vref_ok(vref2)) || !sref ||
	    sref > 0x7fffffff)
		return X4_ERR_PARAM_FAIL;
	return X4_OK;
}

int x4_segment_check(const struct x4_segment *s, u32 reserved)
{
	u32 leader = x4_segment_leader(s);
	u64 length = s->length;

	if (leader > X4_STEPS_MAX)
		return X4_ERR_STEPS_TOO_HIGH;
	if (!leader)
		return X4_ERR_NO_STEPS;
	if (reserved || !length || !s->v_max || !s->accel ||
	    s->probe > X4_PROBE_AWAY ||
	    length > X4_PATH_VALUE_MAX || s->v_max > X4_PATH_VALUE_MAX ||
	    s->v_entry > X4_PATH_VALUE_MAX || s->accel > X4_PATH_VALUE_MAX ||
	    (u64)s->v_max > (u64)X4_PATH_RAMP_MAX_S * s->accel)
		return X4_ERR_PARAM_FAIL;
	/* The leader's acceleration: at least 1, at most the ramp maths'. */
	if ((u64)s->accel * leader < length ||
	    (u64)s->accel * leader > (u64)X4_ACC_MAX * length)
		return X4_ERR_PARAM_FAIL;
	/* Its rate at v_max: no port steps faster (x4_path_check(): the port's). */
	if ((u64)s->v_max * leader > (u64)X4_VEL_MAX * length)
		return X4_ERR_RATE_BUDGET;
	return X4_OK;
}
