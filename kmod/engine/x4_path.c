// SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later
/*
 * x4step engine: continuous paths (x4_path.h). The writer's half queues
 * segments and plans their entry speeds backward (as GRBL's planner does);
 * the timer's half runs them on channel 0, piece by piece.
 *
 * A segment runs in pieces, each a ProStep4 profile plan (x4_plan.c) in
 * the segment's leader steps: from the current speed up to the cruise
 * speed and down to the segment's exit speed, or, when the cruise speed
 * fell below the current one (a hold, a lower override), braking to it
 * first. Leader step j of a segment lies at path position j * length /
 * leader; a piece starts at a step (or at rest) and its steps' times come
 * from their index in closed form. Hold and override cut the running piece
 * after its pending step and plan the next from there, so nothing already
 * scheduled moves, and the path goes on from exactly where it is: a hold
 * and a resume change no step, only when it comes.
 *
 * Calls the plan maths and the channels (x4_chan.c) to begin. The event
 * machine (x4_engine.c) calls the timer's half; what it must act on (the
 * path goes on, or comes to rest) these functions return.
 */
#include "x4_chan.h"
#include "x4_path.h"

#ifdef __KERNEL__
#include <linux/string.h>
#else
#include <string.h>
#endif

static struct x4_path_slot *slot_of(const struct x4_path *pa, u32 k)
{
	return &pa->slot[k & (pa->depth - 1)];
}

static u64 min_u64(u64 a, u64 b)
{
	return a < b ? a : b;
}

static u64 max_u64(u64 a, u64 b)
{
	return a > b ? a : b;
}

/* Leader steps/s of slot s at path speed v (units/s), rounded down. */
static u64 to_steps(const struct x4_path_slot *s, u64 v)
{
	return x4_div(v * s->leader, s->seg.length);
}

/* Path units/s of slot s at leader speed v (steps/s), rounded down. */
static u64 to_path(const struct x4_path_slot *s, u64 v)
{
	return x4_div(v * s->seg.length, s->leader);
}

/*
 * The fastest leader rate the port's timing and write budget allow a path
 * (which owns the port: no other move runs beside it).
 */
static u64 rate_max(const struct x4_engine *e)
{
	const struct x4_timing *t = &e->timing;
	u64 rate = X4_VEL_MAX, period;

	if (e->budget)
		rate = min_u64(rate, e->budget / x4_chan_writes_per_step(
						  e, x4_chan_mode_axes(e)));
	period = t->pulse_ns ? t->pulse_ns + t->space_ns : 2 * t->space_ns;
	if (!x4_chan_phase_mode(e) && period)
		rate = min_u64(rate, x4_div(X4_NSEC_PER_SEC, period));
	return rate;
}

/* Slot s's top path speed at the current override and the rate limit. */
static u64 top_speed(const struct x4_engine *e, const struct x4_path_slot *s)
{
	u64 v = x4_div((u64)s->seg.v_max * e->path.override, 100);

	return min_u64(v, s->v_rate);
}

bool x4_path_active(const struct x4_engine *e)
{
	return x4_chan_path_active(e);
}

int x4_path_set_queue(struct x4_engine *e, struct x4_path_slot *slot,
		      u32 depth)
{
	struct x4_path *pa = &e->path;

	if (depth & (depth - 1))
		return X4_ERR_PARAM_FAIL;
	if (x4_path_active(e))
		return X4_ERR_IS_ACTIVE;
	pa->slot = slot;
	x4_write_once(pa->depth, depth); /* x4_path_room() reads it unlocked */
	pa->head = 0;
	x4_write_once(pa->tail, 0);
	pa->plan = 0;
	pa->plan_tail = 0;
	return X4_OK;
}

int x4_path_check(const struct x4_engine *e, const struct x4_segment *s)
{
	u32 leader = x4_segment_leader(s);
	int ret = x4_segment_check(s, 0);
	u8 axes = 0;
	int i;

	if (ret)
		return ret;
	for (i = 0; i < X4_AXES; i++)
		if (s->steps[i])
			axes |= 1u << i;
	if (axes & ~x4_chan_mode_axes(e))
		return X4_ERR_PARAM_FAIL;
	/* Its rate at v_max: within what the port can do. */
	if ((u64)s->v_max * leader > rate_max(e) * s->length)
		return X4_ERR_RATE_BUDGET;
	if (s->probe && !e->path.probe_input)
		return X4_ERR_PARAM_FAIL; /* no input to probe with */
	if (e->busy & ~(e->ch[0].path ? 1u : 0u))
		return X4_ERR_IS_ACTIVE; /* other moves run */
	if (!e->path.depth)
		return X4_ERR_PARAM_FAIL;
	return X4_OK;
}

u32 x4_path_room(const struct x4_engine *e)
{
	const struct x4_path *pa = &e->path;

	return x4_read_once(pa->depth) -
	       (x4_read_once(pa->tail) - x4_load_acquire(&pa->head));
}

/*
 * Slot s's entry limit: its corner, its axes' reversals, its top speed
 * (at the override).
 */
static void set_limit(const struct x4_engine *e, struct x4_path_slot *s)
{
	s->limit = (u32)min_u64(min_u64(s->seg.v_entry, s->v_rev),
				top_speed(e, s));
}

/*
 * What the rates' rounding to whole steps/s and the times' to whole ns may
 * take from the time before a reversing axis' step.
 */
#define X4_REVERSAL_MARGIN_NS 1000

/*
 * The fastest rate v (steps/s) with x >= 2^16 (2 v h + a d^2): x is 2^16
 * times twice the leader steps up to the reversing axis' step (less those
 * the high time takes, where it is not the pulse), h the time v runs on
 * before the step, d the time the ramp adds to (ns; a in steps/s^2).
 */
static u64 reversal_ramp(u64 x, u64 d, u64 h, u64 a)
{
	u64 acc;

	if (d > 1u << 22)
		d = 1u << 22;
	/* a d^2 * 2^16 (s, steps): what the ramp adds over d */
	acc = x4_div((x4_div(a * d, 1000000) * d) << 16, 1000000000000ull);
	if (acc >= x)
		return 0;
	return x4_div((x - acc) * 1953125, h << 8);
}

/*
 * The fastest leader rate of slot s (steps/s) at its junction with slot
 * b, before it, where an axis changes direction whose first step in s is
 * its leader step j: the step must come no sooner than the setup time
 * after the direction changed, which it does the hold time after the
 * clock of b's last step fell. So from that step on, the high time (the
 * pulse, or half the interval: rho / 2 of s's leader steps, rho the leader
 * steps of s in one of b) and the hold and setup times H pass before step
 * j: j >= v (high + H) + a (high + H)^2 / 2 at entry v and acceleration a.
 */
static u64 reversal_rate(const struct x4_engine *e,
			 const struct x4_path_slot *b,
			 const struct x4_path_slot *s, u64 j)
{
	const struct x4_timing *t = &e->timing;
	u64 h = (u64)t->dir_setup_ns + t->dir_hold_ns, x = j << 17;
	u64 d, rho, v, n;
	int i;

	if (!h)
		return X4_VEL_MAX;
	h += X4_REVERSAL_MARGIN_NS;
	d = h + t->pulse_ns;
	if (t->pulse_ns) {
		h = d;
		return reversal_ramp(x, d, h, s->accel);
	}
	/* rho * 2^16: s->leader * b_length / (b->leader * length) */
	rho = x4_div((u64)s->leader * b->seg.length, b->leader);
	if (rho >= (j << 1) * s->seg.length)
		return 0;
	n = x4_div(rho, s->seg.length);
	rho = (n << 16) + x4_div((rho - n * s->seg.length) << 16,
				 s->seg.length);
	if (rho >= x)
		return 0;
	x -= rho;
	/*
	 * The high time depends on v: from the rate without the ramp down to
	 * where the ramp's part fits (a few rounds: each one's change is a
	 * tenth of the one before, or less).
	 */
	v = x4_div(x * 1953125, h << 8); /* 10^9 / 2^17 */
	for (i = 0; i < 4 && v; i++)
		v = reversal_ramp(x, h + x4_div(x4_div(rho * 15625, v) * 125,
						 256), h, s->accel);
	return v;
}

/*
 * Slot s's direction pins (after it: its axes', the others' as before
 * it) and, when it joins a segment b before it, the fastest entry that
 * lets an axis reversing at the junction wait for its setup time
 * (reversal_rate()), in path units/s. Phase modes have no directions.
 */
static void set_reversal(const struct x4_engine *e, struct x4_path_slot *s,
			 const struct x4_path_slot *b)
{
	u8 moving = 0, dirs = 0, rev;
	u64 j = 0, n, v;
	int i;

	s->v_rev = X4_PATH_VALUE_MAX;
	s->dirs = 0;
	if (x4_chan_phase_mode(e))
		return;
	for (i = 0; i < X4_AXES; i++) {
		if (!s->seg.steps[i])
			continue;
		moving |= X4_DIR_BIT(i);
		if (s->seg.steps[i] > 0)
			dirs |= X4_DIR_BIT(i);
	}
	/* From rest (the queue is empty): the pins, as the path left them. */
	rev = b ? b->dirs : x4_load_acquire(&e->data) & X4_DIR_MASK;
	s->dirs = (u8)((rev & ~moving) | dirs);
	if (!b)
		return;
	rev = (u8)(moving & (rev ^ dirs));
	for (i = 0; i < X4_AXES; i++) {
		if (!(rev & X4_DIR_BIT(i)))
			continue;
		/* Its first step (x4_chan_bres_start()): ceil(leader / 2n). */
		n = s->seg.steps[i] < 0 ? -(s64)s->seg.steps[i] :
					  s->seg.steps[i];
		n = x4_div(s->leader + 2 * n - 1, 2 * n);
		if (!j || n < j)
			j = n;
	}
	if (!j)
		return;
	v = min_u64(reversal_rate(e, b, s, j), rate_max(e));
	s->v_rev = (u32)min_u64(to_path(s, v), X4_PATH_VALUE_MAX);
}

/*
 * The highest entry speed of slot s from which exit v_exit is reachable;
 * the root from its last entry speed or the exit, the nearer one (entries
 * change little; a short segment's is little above its exit).
 */
static u32 entry_for(const struct x4_path_slot *s, u64 v_exit)
{
	u64 v2 = v_exit * v_exit + s->two_as, x0 = max_u64(s->entry, v_exit);

	if ((u64)s->limit * s->limit <= v2)
		return s->limit;
	return (u32)(x0 ? x4_isqrt_from(v2, x0) : x4_isqrt(v2));
}

/*
 * Whether the backward pass plans slot k's entry: from head + 1's (the
 * timer reads it when head starts) to the one before the last (the last
 * stops).
 */
static bool in_pass(u32 k, u32 head, u32 tail)
{
	return tail - head > 2 && k - head - 1 < tail - head - 2;
}

/*
 * The backward pass from the last segment (which ends at rest) toward the
 * running one: each entry speed as high as its corner, its speed limit
 * and the stop of everything after it allow. Appends only raise entries,
 * so the pass ends where an entry does not change (those before it were
 * planned from it). At most `budget` entries a call: the pass goes on
 * from where it stopped at the next call, and starts again from the tail
 * once it is through if segments came meanwhile. Every entry it stores is
 * planned from the one after it, which only rises: a pass that has not
 * come through yet leaves entries lower than they could be, never unsafe.
 */
bool x4_path_plan(struct x4_engine *e, u32 budget)
{
	struct x4_path *pa = &e->path;
	u32 head = x4_load_acquire(&pa->head), tail = pa->tail, k = pa->plan;

	for (;;) {
		struct x4_path_slot *s;
		u32 v;

		if (!in_pass(k, head, tail)) {
			if (pa->plan_tail == tail)
				break; /* through, and nothing came since */
			pa->plan_tail = tail;
			k = tail - 2;
			continue;
		}
		if (!budget)
			break;
		budget--;
		pa->planned++;
		s = slot_of(pa, k);
		v = entry_for(s, slot_of(pa, k + 1)->entry);
		if (v == s->entry) {
			k = head; /* through: the rest was planned from it */
			continue;
		}
		x4_store_release(&s->entry, v);
		k--;
	}
	pa->plan = k;
	return in_pass(k, head, tail);
}

void x4_path_push(struct x4_engine *e, const struct x4_segment *seg)
{
	struct x4_path *pa = &e->path;
	struct x4_path_slot *s = slot_of(pa, pa->tail);
	u32 leader = x4_segment_leader(seg);
	bool empty = pa->tail == x4_load_acquire(&pa->head);

	s->seg = *seg;
	s->leader = leader;
	s->v_rate = (u32)min_u64(to_path(s, rate_max(e)), X4_PATH_VALUE_MAX);
	/*
	 * The timer runs the segment at whole leader steps/s^2: plan with
	 * that acceleration, not the one asked for, so that the plan's stops
	 * are the ones the timer makes.
	 */
	s->accel = (u32)to_steps(s, seg->accel);
	s->two_as = x4_div(2ull * s->accel * seg->length, leader) * seg->length;
	s->entry = 0;
	set_reversal(e, s, empty ? NULL : slot_of(pa, pa->tail - 1));
	set_limit(e, s);
	s->entry = entry_for(s, 0); /* the last segment stops */
	x4_store_release(&pa->tail, pa->tail + 1);
	x4_path_plan(e, X4_PATH_PLAN_BUDGET);
}

/*
 * The whole queue at once, its limits too (the override changed): no pass
 * is left over after it.
 */
void x4_path_replan(struct x4_engine *e)
{
	struct x4_path *pa = &e->path;
	u32 head = x4_load_acquire(&pa->head), k = pa->tail - 1;
	struct x4_path_slot *s;
	u64 v_exit;

	pa->plan_tail = pa->tail;
	pa->plan = head;
	if (pa->tail == head)
		return;
	s = slot_of(pa, k);
	set_limit(e, s);
	v_exit = entry_for(s, 0);
	x4_store_release(&s->entry, (u32)v_exit);
	while (in_pass(k - 1, head, pa->tail)) {
		s = slot_of(pa, --k);
		set_limit(e, s);
		v_exit = entry_for(s, v_exit);
		x4_store_release(&s->entry, (u32)v_exit);
	}
}

/* ---- the timer's half: under the engine's lock ---- */

/* v^2 at step n of a profile plan, (steps/s)^2. */
static u64 plan_speed2(const struct x4_plan *p, u64 n)
{
	const struct x4_profile *f = &p->prof;

	if (n < p->n_cruise)
		return (u64)f->v0 * f->v0 + 2ull * f->a0 * n;
	if (n >= p->n_decel)
		return (u64)f->ve * f->ve + 2ull * f->ae * (p->last - n);
	return (u64)f->vm * f->vm;
}

/* The running segment's cruise speed now (steps/s); 0 while holding. */
static u64 cruise(const struct x4_engine *e)
{
	const struct x4_path *pa = &e->path;

	const struct x4_path_slot *s = slot_of(pa, pa->head);
	u64 v;

	if (pa->state != X4_PATH_RUN)
		return 0;
	v = to_steps(s, top_speed(e, s));
	return v ? v : 1;
}

/*
 * Plan the running segment's next piece into c->run, from step pa->pos at
 * speed pa->v_end: brake to the cruise speed first where it is lower,
 * else up to it and down to the exit speed. Every end speed is one the
 * ramp reaches in the piece; rounding never makes a speed jump of more
 * than a step/s. An exit lower than the ramp can reach (the override
 * dropped after the plan fixed this segment's entry) is not: the piece
 * brakes all the way, and the next segment goes on braking from there.
 */
static void plan_piece(struct x4_engine *e, struct x4_chan *c)
{
	struct x4_path *pa = &e->path;
	u64 v0 = pa->v_end, a = pa->accel, rest = pa->leader - pa->pos;
	u64 vc = cruise(e), ve = min_u64(pa->exit, vc), d = rest;
	struct x4_profile f = { 0 };

	if (v0 > vc || v0 * v0 > ve * ve + 2 * a * rest) {
		/*
		 * Brake to vc, or as far as the segment lets; all the way
		 * where vc leaves too little room to brake to the exit after
		 * (d is rounded up: the last part of a step).
		 */
		d = v0 > vc ? x4_div(v0 * v0 - vc * vc + 2 * a - 1, 2 * a) :
			      rest;
		if (d < rest && vc * vc <= ve * ve + 2 * a * (rest - d)) {
			ve = vc;
		} else {
			/*
			 * The brake reaches the segment's end: to the exit
			 * there (or vc), if the ramp gets that slow.
			 */
			u64 reach = v0 * v0 > 2 * a * rest ?
				x4_isqrt(v0 * v0 - 2 * a * rest) : 0;

			d = rest;
			ve = reach > ve ? reach : ve;
		}
		f.vm = (u32)v0;
		f.ae = (u32)a;
	} else if (v0 + 1 >= vc && ve + 1 >= vc) {
		/* Cruising through (within the step/s of rounding): no ramps. */
		f.vm = (u32)vc;
		ve = vc;
	} else {
		/* Within the segment's reach: up from v0, down from v0. */
		ve = min_u64(ve, x4_isqrt(v0 * v0 + 2 * a * rest));
		f.v0 = (u32)v0;
		f.vm = (u32)vc;
		f.a0 = (u32)a;
		f.ae = (u32)a;
	}
	f.ve = (u32)ve;
	x4_plan_profile(&c->run, d + 1, &f);
	pa->piece = (u32)d;
	pa->v_end = (u32)ve;
	/* Step 0 of the plan is where the piece starts; its steps are 1..d. */
	c->n = 0;
	c->t_cur = 0;
	c->t_next = x4_plan_time(&c->run, 1);
	c->half_ns = c->t_next / 2;
}

/*
 * Watch the probe input while the segment at head is a probing one (from
 * its start, fresh: its latch is cleared; or again after a hold).
 * TOWARD trips at the input's active level, AWAY at its inactive one.
 */
static void arm_probe(struct x4_engine *e, struct x4_chan *c, bool fresh)
{
	struct x4_path *pa = &e->path;
	const struct x4_segment *s = &slot_of(pa, pa->head)->seg;
	u8 bit = x4_chan_input_bit(pa->probe_input);

	c->probe_mask = 0;
	if (!s->probe)
		return;
	if (fresh) {
		memset(pa->latch.position, 0, sizeof(pa->latch.position));
		pa->latch.tripped = false;
		pa->latch.tag = s->tag;
		pa->latch.runs++;
	}
	c->probe_mask = bit;
	c->probe_flip = pa->probe_nc != (s->probe == X4_PROBE_AWAY) ? bit : 0;
}

bool x4_path_probe_hit(struct x4_engine *e, struct x4_chan *c)
{
	struct x4_path *pa = &e->path;
	int i;

	c->probe_mask = 0; /* it trips once */
	pa->latch.tripped = true;
	for (i = 0; i < X4_AXES; i++) /* before this tick's step */
		pa->latch.position[i] = x4_chan_position(e, i);
	pa->latch.trips++;
	if (c->n == 1 && !plan_speed2(&c->run, 0)) {
		/* At rest before the piece's first step: none is made. */
		x4_chan_cut(c);
		return true;
	}
	x4_path_hold(e, true); /* along the path, then flushed */
	return false;
}

/*
 * Start the segment at head, entering at path speed v_in / pa->leader
 * (v_in: the segment before's end speed in its leader steps/s times its
 * length): its axes and Bresenham, its switches, and its exit speed, read
 * once from the plan (or rest when nothing follows it yet). The entry
 * speed goes over in leader steps, rounded down once: not through whole
 * units/s, which a unit coarser than a step would make a speed step.
 */
static void start_segment(struct x4_engine *e, struct x4_chan *c, u64 v_in)
{
	struct x4_path *pa = &e->path;
	struct x4_path_slot *s = slot_of(pa, pa->head);
	u32 tail = x4_load_acquire(&pa->tail);
	s64 steps[X4_AXES];
	u64 v_exit = 0, q = 0, r = 0;
	int i;

	if (v_in) {
		/* v_in * s->leader / (pa->leader * length) within 64 bits */
		q = x4_div(v_in, pa->leader);
		r = v_in - q * pa->leader;
		q = x4_div(q * s->leader + x4_div(r * s->leader, pa->leader),
			   s->seg.length);
	}

	for (i = 0; i < X4_AXES; i++)
		steps[i] = s->seg.steps[i];
	x4_plan_axes(&c->run, steps);
	x4_chan_bres_start(c);
	x4_chan_arm_switches(e, c);
	arm_probe(e, c, true);
	pa->started = true;
	pa->lonely = tail == pa->head + 1;
	if (!pa->lonely)
		v_exit = x4_load_acquire(&slot_of(pa, pa->head + 1)->entry);
	pa->leader = s->leader;
	pa->accel = s->accel;
	pa->exit = (u32)to_steps(s, v_exit);
	pa->pos = 0;
	pa->piece = 0;
	pa->v_end = (u32)q;
}

/* Flush the queue: the path is idle. */
static void flush(struct x4_engine *e)
{
	struct x4_path *pa = &e->path;

	x4_store_release(&pa->head, x4_load_acquire(&pa->tail));
	pa->state = X4_PATH_IDLE;
	pa->started = false;
	pa->abort = false;
	x4_write_once(pa->flushes, pa->flushes + 1); /* the glue reads it */
}

/*
 * When the running piece's last step is due: at c->origin + c->t_cur,
 * which the plan rounds down to a whole ns. The next piece counts from
 * there, so where the piece ends cruising (as most do on a path at its
 * feed), the fraction carries over: a path of thousands of pieces does
 * not run ahead of its plan by half a ns a piece.
 */
static u64 piece_end(struct x4_path *pa, const struct x4_chan *c)
{
	const struct x4_plan *p = &c->run;
	u64 t = c->origin + c->t_cur, x, r;

	if (p->last < p->n_cruise || p->last >= p->n_decel)
		return t;
	x = (2 * p->last - p->c_m0) * p->c_num; /* x4_plan_cruise_time() */
	r = x - x4_div(x, p->c_den) * p->c_den;
	pa->frac += x4_div(r << 32, p->c_den);
	t += pa->frac >> 32;
	pa->frac &= 0xffffffffull;
	return t;
}

/*
 * After the last step of the running piece (due at c->origin + c->t_cur):
 * plan the next piece, possibly of the next segment, and return true; or
 * return false when the path comes to rest here (c->path_cut: stopped).
 * Directions that change go out after the hold time (c->dir_fresh):
 * compared with the pins, as an axis that did not move in the segment
 * before has no direction in its plan.
 */
bool x4_path_next(struct x4_engine *e, struct x4_chan *c)
{
	struct x4_path *pa = &e->path;
	u64 t0;

	if (c->path_cut)
		return false;
	t0 = piece_end(pa, c);
	pa->pos += pa->piece;
	pa->piece = 0;
	if (pa->pos >= pa->leader) {
		u64 v = (u64)pa->v_end * slot_of(pa, pa->head)->seg.length;

		pa->done++;
		pa->started = false;
		x4_store_release(&pa->head, pa->head + 1);
		if (pa->head == x4_load_acquire(&pa->tail)) {
			pa->rest = X4_REST_DRY;
			return false;
		}
		if (!pa->v_end && pa->state == X4_PATH_HOLDING) {
			pa->rest = X4_REST_HELD;
			return false;
		}
		start_segment(e, c, v);
		/*
		 * A hold's brake that ends at the junction into a segment
		 * with a longer leader step enters it at 0 steps/s (rounded
		 * down): it stands held at that segment's start.
		 */
		if (pa->state == X4_PATH_HOLDING && !pa->v_end) {
			pa->rest = X4_REST_HELD;
			return false;
		}
		if (!x4_chan_phase_mode(e))
			c->dir_fresh = x4_chan_dir_changes(e, &c->run);
	} else if (!pa->v_end && pa->state == X4_PATH_HOLDING) {
		pa->rest = X4_REST_HELD;
		return false;
	}
	plan_piece(e, c);
	c->origin = t0;
	return true;
}

/*
 * The clock's high time at the last step of the running piece: half the
 * step interval at the piece's end speed, which the next piece starts
 * with (half_ns, the interval before, where the path comes to rest).
 */
u64 x4_path_end_half(const struct x4_engine *e, u64 half_ns)
{
	u32 v = e->path.v_end;

	return v ? x4_div(X4_NSEC_PER_SEC, 2ull * v) : half_ns;
}

/*
 * The path's channel came to rest: why decides what follows. A hold (or
 * an abort) stands HELD (flushed) wherever it came to rest: at the
 * queue's end too, or asked for while the channel ended (after its last
 * step, the direction hold or a phase mode's settle time). True: the
 * path goes on from there, as segments came while it ended after running
 * dry, or a resume undid the hold meanwhile: the caller starts it again
 * (x4_path_kick()).
 */
bool x4_path_ended(struct x4_engine *e, struct x4_chan *c)
{
	struct x4_path *pa = &e->path;

	c->path = false;
	if (c->path_cut || pa->rest == X4_REST_CUT) {
		flush(e);
		return false;
	}
	if (pa->state == X4_PATH_HOLDING) { /* the hold came to rest */
		pa->state = X4_PATH_HELD;
		if (pa->abort)
			flush(e);
		return false;
	}
	pa->state = X4_PATH_IDLE; /* a push kicks it again */
	pa->abort = false;
	if (pa->head == x4_load_acquire(&pa->tail))
		return false;
	if (pa->rest == X4_REST_DRY)
		pa->starved++; /* it stood for want of them */
	return true;
}

/* Start (or resume) the path from rest at its current place. */
static void begin_path(struct x4_engine *e, u64 now_ns)
{
	struct x4_path *pa = &e->path;
	struct x4_chan *c = &e->ch[0];
	u64 bres[X4_AXES];

	memcpy(bres, c->bres, sizeof(bres));
	if (!pa->started)
		start_segment(e, c, 0);
	pa->v_end = 0;
	pa->frac = 0;
	pa->state = X4_PATH_RUN;
	pa->rest = X4_REST_CUT;
	c->home = 0;
	plan_piece(e, c);
	x4_chan_begin(e, c, now_ns); /* directions now, the first step after */
	if (pa->pos) /* resumed within a segment: its Bresenham goes on */
		memcpy(c->bres, bres, sizeof(bres));
	arm_probe(e, c, false); /* x4_chan_begin() disarmed it */
	c->path = true;
	c->rate = (u32)(rate_max(e) *
			x4_chan_writes_per_step(e, x4_chan_mode_axes(e)));
	/* SETUP, then step 1 of the piece (x4_engine.c: begin_setup()). */
	c->n = 1;
	c->t_cur = x4_plan_time(&c->run, 1);
}


/*
 * Make the running piece end at the step pending now, so that the next
 * piece is planned from there with what changed (hold, override).
 */
static void cut_piece(struct x4_engine *e)
{
	struct x4_path *pa = &e->path;
	struct x4_chan *c = &e->ch[0];
	u8 phase = c->phase == X4_QUEUED ? c->phase_after : c->phase;
	u64 nb;

	if (!c->path)
		return;
	if (phase == X4_SETUP && !plan_speed2(&c->run, 0)) {
		/* Starting from rest: nothing moved yet. */
		if (pa->state == X4_PATH_HOLDING) {
			c->no_steps = true; /* held before its first step */
			pa->rest = X4_REST_HELD;
			return;
		}
		c->no_steps = false; /* a resume undoes such a hold */
		pa->rest = X4_REST_CUT;
		pa->v_end = 0;
		plan_piece(e, c);
		c->n = 1;
		c->t_cur = c->t_next;
		return;
	}
	if (phase == X4_RISE || phase == X4_SETUP) /* SETUP: a junction's */
		nb = c->n;
	else if (phase == X4_FALL)
		nb = c->n + 1;
	else
		return;
	if (nb >= c->run.last)
		return; /* the piece ends there anyway */
	pa->v_end = (u32)x4_isqrt(plan_speed2(&c->run, nb));
	pa->piece = (u32)nb;
	c->run.last = nb;
}

/*
 * The running segment's exit follows the plan: new segments came, or the
 * plan raised the entry of the one after it (a higher override), or
 * lowered it (a lower one: obeyed before the next segment where there is
 * room, plan_piece() brakes at the limit where there is not). Running,
 * its next piece, from the pending step, goes to the new exit speed;
 * holding or held, the resume does.
 */
static void follow_exit(struct x4_engine *e)
{
	struct x4_path *pa = &e->path;
	struct x4_chan *c = &e->ch[0];
	u64 v;

	if (pa->head + 1 == x4_load_acquire(&pa->tail))
		return;
	v = to_steps(slot_of(pa, pa->head),
		     x4_load_acquire(&slot_of(pa, pa->head + 1)->entry));
	if (v == pa->exit)
		return;
	if (pa->state == X4_PATH_RUN && pa->lonely &&
	    c->n >= c->run.n_decel)
		pa->starved++; /* it began to brake for want of segments */
	pa->lonely = false;
	pa->exit = (u32)v;
	if (pa->state == X4_PATH_RUN)
		cut_piece(e);
}

bool x4_path_kick(struct x4_engine *e, u64 now_ns)
{
	struct x4_path *pa = &e->path;

	if (pa->state != X4_PATH_IDLE && pa->started)
		follow_exit(e);
	if (pa->state != X4_PATH_IDLE || pa->head == x4_read_once(pa->tail))
		return false;
	begin_path(e, now_ns);
	return true;
}

int x4_path_hold(struct x4_engine *e, bool abort)
{
	struct x4_path *pa = &e->path;

	switch (pa->state) {
	case X4_PATH_IDLE: /* segments queued, not started yet */
		if (pa->head == x4_load_acquire(&pa->tail))
			return X4_ERR_NOT_ACTIVE;
		if (abort)
			flush(e);
		else /* a writer's kick does not start it, a resume does */
			pa->state = X4_PATH_HELD; /* before its start */
		return X4_OK;
	case X4_PATH_HELD:
		if (abort)
			flush(e);
		return X4_OK;
	default:
		pa->abort |= abort;
		if (pa->state == X4_PATH_RUN) {
			pa->state = X4_PATH_HOLDING;
			cut_piece(e);
		}
		return X4_OK;
	}
}

int x4_path_resume(struct x4_engine *e, u64 now_ns)
{
	struct x4_path *pa = &e->path;

	if (pa->abort)
		return X4_ERR_NOT_ACTIVE; /* an abort is under way */
	if (pa->state == X4_PATH_HOLDING) {
		pa->state = X4_PATH_RUN;
		cut_piece(e);
		return X4_OK;
	}
	if (pa->state != X4_PATH_HELD)
		return X4_ERR_NOT_ACTIVE;
	if (pa->head == x4_read_once(pa->tail)) {
		pa->state = X4_PATH_IDLE; /* held at its very end */
		return X4_OK;
	}
	begin_path(e, now_ns);
	return X4_OK;
}

int x4_path_set_probe(struct x4_engine *e, u8 input, bool nc)
{
	struct x4_path *pa = &e->path;

	if (input > X4_INPUTS)
		return X4_ERR_PARAM_FAIL;
	if (input == pa->probe_input && nc == pa->probe_nc)
		return X4_OK;
	if (x4_path_active(e))
		return X4_ERR_IS_ACTIVE; /* its probing segments were checked */
	pa->probe_input = input;
	pa->probe_nc = nc;
	return X4_OK;
}

int x4_path_set_override(struct x4_engine *e, u32 percent)
{
	if (!percent || percent > X4_PATH_OVERRIDE_MAX)
		return X4_ERR_PARAM_FAIL;
	e->path.override = (u16)percent;
	if (e->path.state == X4_PATH_RUN)
		cut_piece(e);
	return X4_OK;
}

void x4_path_get_status(const struct x4_engine *e, struct x4_path_status *st)
{
	const struct x4_path *pa = &e->path;
	const struct x4_chan *c = &e->ch[0];
	u32 head = pa->head;

	st->state = pa->state;
	st->queued = x4_read_once(pa->tail) - head;
	st->depth = pa->depth;
	st->override = pa->override;
	st->done = pa->done;
	st->starved = pa->starved;
	st->tag = st->queued ? slot_of(pa, head)->seg.tag : 0;
	st->speed = 0;
	if (c->path && (c->phase == X4_RISE || c->phase == X4_FALL))
		st->speed = (u32)to_path(slot_of(pa, head),
					 x4_isqrt(plan_speed2(&c->run, c->n)));
}
