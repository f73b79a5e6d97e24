// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: the engine on the port registers, paced by a hard-irq hrtimer
 * with absolute expiry times. A callback does a bounded amount of work:
 * the events that are due, at most X4_TICK_EVENTS of them and for at most
 * about X4_TICK_NS, then it re-arms, so that the ioctls, brake keys and
 * the other CPUs' interrupts get the lock and the CPU in between. What a
 * late callback leaves over fires in the next one; the engine keeps every
 * pulse and space at its minimum whatever the lateness.
 *
 * An edge whose pulse or space has less slack than the timer's usual
 * lateness (x4_engine_slack(); the X4Step API's 20 kHz with 25 us pulse
 * and space has none) would move the rest of its move at every late
 * timer. Such an edge is placed as drivers/pps/generators/pps_gen_parport.c
 * places its edges: the timer is armed early by the lateness it usually
 * has, the callback lets the engine work the edge out as if on time, then
 * waits on the clock for the edge's time, at most X4_SPIN_MAX_NS, and
 * writes it at once.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/limits.h>
#include <linux/module.h>
#include <linux/parport.h>

#include "x4step_compat.h"
#include "x4_req.h"
#include "x4step_events.h"
#include "x4step_port.h"

/* Pins 1, 14 and 17 (C0, C1, C3) are inverted by the port hardware. */
#define X4_CTL_HW_INVERT 0x0b
/* Pin 11 (S7, Busy) is inverted by the port hardware. */
#define X4_STATUS_HW_INVERT 0x80
/*
 * The fall of a configured clock pulse due this soon after its rise is
 * waited for in the callback instead of re-arming the timer, so that the
 * pulse lasts what was asked (the timer's jitter is of this order).
 */
#define X4_SPIN_NS 10000
/*
 * An edge without slack is waited for at most this long; its timer is
 * armed early by the estimated lateness plus X4_EARLY_NS, up to this. The
 * estimate follows a later timer at once and an earlier one by a quarter
 * of the difference per callback (pps_gen_parport.c's rule).
 */
#define X4_SPIN_MAX_NS 5000
#define X4_EARLY_NS 300
/*
 * The most clock reads of one wait, in case the clock does not advance
 * with interrupts off. A read and cpu_relax() take well over 1 ns on any
 * machine, so this is more than 16 us, above the longest wait
 * (X4_SPIN_NS): a wait that stops here has lasted past its time, and the
 * edge it writes then is late, never early.
 */
#define X4_SPIN_READS 16384
/* The kinds of port write (write_kind): a clock edge written or none. */
#define X4_WRITE_FALL 0
#define X4_WRITE_RISE 1
#define X4_WRITE_NONE 2
/*
 * The most events, and about the longest time, of one timer callback; one
 * that stops with more due gives the CPU back for X4_TICK_GAP_NS first
 * (re-armed in the past, the hrtimer core would run it again at once).
 */
#define X4_TICK_EVENTS 8
#define X4_TICK_NS 20000
#define X4_TICK_GAP_NS 5000

/* Wakes pollers when moves end (from the hard-irq timer). */
static void x4step_wake(struct irq_work *work)
{
	struct x4_port *x4 = container_of(work, struct x4_port, wake_work);

	wake_up_all(&x4->wait);
}

/* The data bits that user wiring inverts: set once, not per event. */
void x4step_port_set_invert(struct x4_port *x4, u8 clock_invert, u8 dir_invert)
{
	u8 bits = 0;
	int i;

	lockdep_assert_held(&x4->slock);
	for (i = 0; i < X4_AXES; i++) {
		if (clock_invert & (1u << i))
			bits |= X4_CLK_BIT(i);
		if (dir_invert & (1u << i))
			bits |= X4_DIR_BIT(i);
	}
	x4->clock_invert = clock_invert;
	x4->dir_invert = dir_invert;
	x4->data_invert = bits;
}

/*
 * Put the engine's pin levels on the port, writing only the registers
 * that change (port I/O is slow, and this runs in hard irq).
 */
void x4step_port_write_locked(struct x4_port *x4)
{
	struct parport *port = x4->port;
	u8 data = x4->eng.data;
	u8 ctl = x4->eng.ctl ^ X4_CTL_HW_INVERT;
	u8 clk;

	lockdep_assert_held(&x4->slock);
	x4->write_kind = X4_WRITE_NONE;
	if (!x4->claimed)
		return;
	if (x4->eng.mode == X4_MODE_CLOCK_DIR)
		data ^= x4->data_invert;
	/*
	 * Only a write that changes a clock bit of known registers is an
	 * edge; one that sets a clock bit is a rise, whatever else changes.
	 */
	clk = (data ^ x4->data_written) & X4_CLK_MASK;
	if (clk && x4->written_valid)
		x4->write_kind = data & clk ? X4_WRITE_RISE : X4_WRITE_FALL;
	if (data != x4->data_written || !x4->written_valid)
		port->ops->write_data(port, data);
	if (ctl != x4->ctl_written || !x4->written_valid)
		port->ops->write_control(port, ctl);
	x4->data_written = data;
	x4->ctl_written = ctl;
	x4->written_valid = true;
}

/*
 * Minimums count from when the write was done, less the shortest write
 * of its kind seen (write_ns): a write that took its usual time counts
 * from its start, as its edge lies at the same point of every such write;
 * one that took longer (an NMI) from that much later. Then an edge placed
 * on time by a wait lets the next one be on time too. The kinds: a write
 * that sets bits (a rise) may cost the port driver more than one that
 * clears them (x4vport counts the machine's steps at rises). A write
 * that was no clock edge, or one of a kind not measured yet, counts from
 * its end: later, never earlier.
 */
static u32 x4step_write_base(const struct x4_port *x4)
{
	u32 w;

	if (x4->write_kind == X4_WRITE_NONE)
		return 0;
	w = x4->write_ns[x4->write_kind];
	return w == U32_MAX ? 0 : w;
}

static void x4step_port_written_locked(struct x4_port *x4)
{
	x4_engine_written(&x4->eng, ktime_get_ns() - x4step_write_base(x4) -
			  ktime_to_ns(x4->epoch));
}

/*
 * Fire and write what is due by engine time `until` (more writes of one
 * instant in phase mode, a stop's rest patterns).
 */
void x4step_port_drain_locked(struct x4_port *x4, u64 until)
{
	int c;

	lockdep_assert_held(&x4->slock);
	while (x4_engine_busy(&x4->eng) && x4_engine_due(&x4->eng) <= until) {
		c = x4->eng.cur - x4->eng.ch;
		x4_engine_fire(&x4->eng, until);
		x4step_port_write_locked(x4);
		x4step_port_written_locked(x4);
		x4step_events_fired_locked(x4, c);
	}
}

/* Put the port in the engine's rest state (all of it, in phase mode). */
void x4step_port_write_rest_locked(struct x4_port *x4)
{
	u8 bytes[X4_SMC_AXES];
	int i, n = x4_phase_rest_writes(&x4->eng, bytes);

	lockdep_assert_held(&x4->slock);
	for (i = 0; i < n; i++) {
		x4->eng.data = bytes[i];
		x4step_port_write_locked(x4);
	}
}

/* The port is going away: no register access from now on. */
void x4step_port_gone(struct x4_port *x4)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	x4->gone = true;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/*
 * The input pin levels (X4GetIn bits). Read from the port only while it is
 * ours: otherwise lp or ppdev may own it, and the last levels read are
 * returned (x4->claimed says which).
 */
u32 x4step_port_inputs_locked(struct x4_port *x4)
{
	u8 status;

	lockdep_assert_held(&x4->slock);
	if (x4->claimed && !x4->gone) {
		status = x4->port->ops->read_status(x4->port) ^
			 X4_STATUS_HW_INVERT;
		/* S3..S7 are pins 15, 13, 12, 10, 11: X4GetIn bits 0..4. */
		x4->inputs = (status >> 3) & 0x1f;
		x4->inputs_ns = ktime_get_ns();
	}
	return x4->inputs;
}

/* Count how late an event is written, `late` ns after it was due. */
static void x4step_account_lateness(struct x4_port *x4, s64 late)
{
	struct x4step_timing *t = &x4->timing;
	u64 bucket;

	lockdep_assert_held(&x4->slock);
	if (late < 0)
		late = 0;
	bucket = (u64)late / X4STEP_TIMING_BUCKET_NS;
	t->events++;
	if (late > t->late_max_ns)
		t->late_max_ns = late;
	if (bucket < X4STEP_TIMING_BUCKETS)
		t->hist[bucket]++;
	else
		t->beyond++;
}

/*
 * Fire the engine's pending event at `now` and write it. Every event goes
 * through here, also those of other channels due at the same instant and
 * a phase step's further writes: each is counted, and each step that a
 * limit or REF watches has the switches looked at first.
 */
static void x4step_fire_locked(struct x4_port *x4, ktime_t now)
{
	struct x4_engine *e = &x4->eng;
	s64 t = ktime_to_ns(ktime_sub(now, x4->epoch));
	int c = e->cur - e->ch;

	lockdep_assert_held(&x4->slock);
	if (x4->claimed && x4_engine_rise_watched(e))
		x4_switch_sense(e, x4step_port_inputs_locked(x4));
	x4step_account_lateness(x4, t - (s64)x4_engine_due(e));
	x4_engine_fire(e, t);
	x4step_port_write_locked(x4);
	x4step_port_written_locked(x4);
	x4step_events_fired_locked(x4, c);
}

/*
 * The pending event has less slack than the timer's usual lateness, with
 * X4_EARLY_NS to spare (a rise's slack is its step before's: at the end
 * of a ramp the step is a little shorter).
 */
static bool x4step_tight_locked(struct x4_port *x4)
{
	return x4_engine_slack(&x4->eng) < (u64)x4->late_est_ns + X4_EARLY_NS;
}

/* ontime_spin: edges without slack are armed early and waited for. */
static bool ontime_spin = true;
module_param(ontime_spin, bool, 0644);
MODULE_PARM_DESC(ontime_spin, "arm the timer early and wait with interrupts off for edges without slack (default 1, 0: no such waits, those edges are as late as the timer)");

/*
 * (Re)arm the timer for the engine's next event, not before `earliest`;
 * early for an edge without slack.
 */
void x4step_port_arm_locked(struct x4_port *x4, ktime_t earliest)
{
	ktime_t due = ktime_add_ns(x4->epoch, x4_engine_due(&x4->eng));
	u64 early = 0;

	lockdep_assert_held(&x4->slock);
	if (!x4_engine_busy(&x4->eng))
		return;
	/*
	 * Beyond X4_SPIN_MAX_NS of lateness the wait cannot place the edge
	 * (x4step_wait_next()): arming early would only cost a callback.
	 */
	if (READ_ONCE(ontime_spin) && x4step_tight_locked(x4)) {
		early = (u64)x4->late_est_ns + X4_EARLY_NS;
		if (early > X4_SPIN_MAX_NS)
			early = 0;
		due = ktime_sub_ns(due, early);
	}
	x4->armed_early = early && ktime_after(due, earliest);
	x4->armed = ktime_after(due, earliest) ? due : earliest;
	hrtimer_start(&x4->timer, x4->armed, HRTIMER_MODE_ABS_HARD);
}

/* The timer fired at `now`: how late it usually is. */
static void x4step_note_lateness_locked(struct x4_port *x4, ktime_t now)
{
	s64 late = ktime_to_ns(ktime_sub(now, x4->armed));
	u32 est = x4->late_est_ns;

	if (late < 0)
		late = 0;
	if (late > U32_MAX)
		late = U32_MAX;
	if (late >= est)
		x4->late_est_ns = late;
	else
		x4->late_est_ns = est - (est - (u32)late) / 4;
}

/*
 * Whether the next event, due at `due` after `now`, is waited for: the
 * fall of a configured pulse shorter than the timer's jitter, or an edge
 * the timer was armed early for, or one as tight due within the bound.
 */
static bool x4step_wait_next(struct x4_port *x4, const struct x4_chan *fired,
			     ktime_t due, ktime_t now)
{
	s64 ahead = ktime_to_ns(ktime_sub(due, now));

	if (x4->eng.timing.pulse_ns && x4_engine_pulse_pending(&x4->eng, fired) &&
	    ahead <= X4_SPIN_NS)
		return true;
	return ahead <= X4_SPIN_MAX_NS && READ_ONCE(ontime_spin) &&
	       (x4->armed_early || x4step_tight_locked(x4));
}

/*
 * Fire the pending event before its time `due`: the engine works the edge
 * out as if on time, then the wait (x4step_wait_next() bounds it) ends at
 * `due` and the write follows at once. Counted in spins and spin_ns.
 */
static void x4step_fire_on_time_locked(struct x4_port *x4, ktime_t due)
{
	struct x4_engine *e = &x4->eng;
	int c = e->cur - e->ch;
	unsigned int reads = X4_SPIN_READS;
	ktime_t start, now, done;
	s64 w;
	int k;

	lockdep_assert_held(&x4->slock);
	if (x4->claimed && x4_engine_rise_watched(e))
		x4_switch_sense(e, x4step_port_inputs_locked(x4));
	x4_engine_fire(e, ktime_to_ns(ktime_sub(due, x4->epoch)));
	start = ktime_get();
	for (now = start; ktime_before(now, due); now = ktime_get()) {
		if (unlikely(!--reads))
			break;
		cpu_relax();
	}
	x4step_port_write_locked(x4);
	done = ktime_get();
	if (unlikely(!reads)) {
		/* Each such wait would cost this again: no more of them. */
		WRITE_ONCE(ontime_spin, false);
		pr_warn_once("the clock did not reach a wait's end in %d reads with interrupts off: ontime_spin off\n",
			     X4_SPIN_READS);
	}
	/*
	 * Learn the shortest write of each kind (U32_MAX: none yet) from
	 * edges only. The first one may hold a delay before the pin changed,
	 * so its edge alone may count from before the pin's change; the
	 * baseline only decreases afterwards, so no later write counts from
	 * earlier than its own start.
	 */
	k = x4->write_kind;
	if (k != X4_WRITE_NONE) {
		w = min_t(s64, ktime_to_ns(ktime_sub(done, now)), U32_MAX);
		if (w < x4->write_ns[k])
			x4->write_ns[k] = w;
	}
	x4_engine_written(e, ktime_to_ns(ktime_sub(done, x4->epoch)) -
			  x4step_write_base(x4));
	x4step_account_lateness(x4, ktime_to_ns(ktime_sub(now, due)));
	x4->timing.spins++;
	x4->timing.spin_ns += ktime_to_ns(ktime_sub(now, start));
	x4step_events_fired_locked(x4, c);
}

/* Wake pollers when moves ended since the last look. */
void x4step_port_note_ends_locked(struct x4_port *x4)
{
	lockdep_assert_held(&x4->slock);
	if (x4->moves_ended != x4->eng.ends) {
		x4->moves_ended = x4->eng.ends;
		irq_work_queue(&x4->wake_work);
	}
}

/*
 * The timer freed slots of the path's queue that its writer waits for
 * (x4step_path_write(), x4step_path_poll()): wake it.
 */
void x4step_port_room_locked(struct x4_port *x4)
{
	if (!x4_path_active(&x4->eng))
		return;
	/*
	 * The timer advanced head, then reads wanted; a writer sets wanted,
	 * then reads head (wait_event()'s set_current_state(), or the barrier
	 * in x4step_path_poll()): with this barrier one of them sees the other.
	 */
	smp_mb();
	if (READ_ONCE(x4->path_room_wanted) && x4_path_room(&x4->eng)) {
		WRITE_ONCE(x4->path_room_wanted, false);
		irq_work_queue(&x4->wake_work);
	}
}

/*
 * The timer re-arms itself with hrtimer_start() under slock rather than
 * returning HRTIMER_RESTART: an ioctl may start another axis' move (and
 * arm the timer) while this callback waits for the lock on another CPU;
 * then the timer is queued again and this callback leaves it alone.
 */
static enum hrtimer_restart x4step_tick(struct hrtimer *timer)
{
	struct x4_port *x4 = container_of(timer, struct x4_port, timer);
	struct x4_engine *e = &x4->eng;
	const struct x4_chan *fired = NULL;
	unsigned long flags;
	ktime_t now, due, end, earliest = 0;
	int n = 0;

	raw_spin_lock_irqsave(&x4->slock, flags);
	if (!x4_engine_busy(e) || hrtimer_is_queued(timer))
		goto out;
	now = ktime_get();
	x4step_note_lateness_locked(x4, now);
	end = ktime_add_ns(now, X4_TICK_NS);
	for (;;) {
		/* The armed event may have been stopped: fire what is due. */
		due = ktime_add_ns(x4->epoch, x4_engine_due(e));
		if (ktime_after(due, now)) {
			if (n >= X4_TICK_EVENTS || ktime_after(now, end) ||
			    !x4step_wait_next(x4, fired, due, now))
				break;
			x4->armed_early = false;
			fired = e->cur;
			x4step_fire_on_time_locked(x4, due);
			n++;
			if (!x4_engine_busy(e))
				break;
			now = ktime_get();
			continue;
		} else if (n >= X4_TICK_EVENTS || ktime_after(now, end)) {
			/* More is due: the next callback, after a gap. */
			x4->timing.capped++;
			earliest = ktime_add_ns(now, X4_TICK_GAP_NS);
			break;
		}
		fired = e->cur;
		x4step_fire_locked(x4, now);
		n++;
		if (!x4_engine_busy(e))
			break;
		now = ktime_get();
	}
	if (n)
		x4->timing.callbacks++;
	x4->timing.shifts += e->shifts;
	x4->timing.shifted_ns += e->shifted_ns;
	e->shifts = 0;
	e->shifted_ns = 0;
	x4step_port_arm_locked(x4, earliest);
	x4step_port_note_ends_locked(x4);
	x4step_port_room_locked(x4);
out:
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	return HRTIMER_NORESTART;
}

/* Default step timing of new ports (X4STEP_SET_STEP_TIMING changes it). */
static unsigned int pulse_ns;
module_param(pulse_ns, uint, 0444);
MODULE_PARM_DESC(pulse_ns, "clock pulse length in ns, 0: symmetric clock (default)");
static unsigned int space_ns;
module_param(space_ns, uint, 0444);
MODULE_PARM_DESC(space_ns, "minimum clock low time in ns (default 0)");
static unsigned int dir_setup_ns = X4_DIR_SETUP_NS;
module_param(dir_setup_ns, uint, 0444);
MODULE_PARM_DESC(dir_setup_ns, "direction setup before the first step in ns (default 100000)");
static unsigned int dir_hold_ns;
module_param(dir_hold_ns, uint, 0444);
MODULE_PARM_DESC(dir_hold_ns, "direction hold after the last step in ns (default 0)");
static unsigned int write_budget = X4_WRITE_BUDGET;
module_param(write_budget, uint, 0444);
MODULE_PARM_DESC(write_budget, "port writes per second all moves of a port may need together (default 200000, 0: no limit)");

void x4step_port_init(struct x4_port *x4)
{
	struct x4_timing t = { pulse_ns, space_ns, dir_setup_ns, dir_hold_ns };

	raw_spin_lock_init(&x4->slock);
	x4_engine_init(&x4->eng);
	if (x4_engine_configure(&x4->eng, &t, X4_MODE_CLOCK_DIR))
		pr_warn("step timing parameters out of range (1000..1000000 ns), using the defaults\n");
	x4->eng.budget = write_budget;
	x4->write_kind = X4_WRITE_NONE;
	x4->write_ns[X4_WRITE_FALL] = U32_MAX;
	x4->write_ns[X4_WRITE_RISE] = U32_MAX;
	init_waitqueue_head(&x4->wait);
	init_irq_work(&x4->wake_work, x4step_wake);
	x4_hrtimer_setup(&x4->timer, x4step_tick, CLOCK_MONOTONIC,
			 HRTIMER_MODE_ABS_HARD);
	x4->epoch = ktime_get();
}

/*
 * The controller claimed the port: drive it from the idle state the last
 * controller left (step counters stay readable, as after any stop).
 */
void x4step_port_claimed(struct x4_port *x4)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4->slock, flags);
	x4->claimed = true;
	x4->written_valid = false; /* the claim restored some other state */
	x4step_port_write_rest_locked(x4);
	x4step_port_inputs_locked(x4); /* for status reads after the release */
	raw_spin_unlock_irqrestore(&x4->slock, flags);
}

/*
 * Stop whatever runs, at once, and forget the loaded move; all outputs
 * low. Then the registers are no longer ours.
 */
void x4step_port_quiesce(struct x4_port *x4)
{
	unsigned long flags;

	lockdep_assert_held(&x4->lock);
	raw_spin_lock_irqsave(&x4->slock, flags);
	x4step_events_stop_locked(x4, x4->eng.busy);
	x4_engine_stop(&x4->eng);
	x4step_port_drain_locked(x4, U64_MAX);
	x4step_events_update_locked(x4, -1, 0);
	x4->eng.loaded = false;
	x4->eng.ctl = 0;
	x4step_port_write_rest_locked(x4);
	/* The last levels while the port is ours. */
	x4step_port_inputs_locked(x4);
	x4->claimed = false;
	x4->moves_ended = x4->eng.ends;
	raw_spin_unlock_irqrestore(&x4->slock, flags);
	hrtimer_cancel(&x4->timer);
	irq_work_sync(&x4->wake_work);
	wake_up_all(&x4->wait);
}
