/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: the per-port state and the open files, shared by the module's
 * parts; each part's functions are in its own header (x4step_port.h,
 * x4step_events.h, x4step_path.h, ...).
 */
#ifndef X4STEP_DEV_H
#define X4STEP_DEV_H

#include <linux/cdev.h>
#include <linux/device.h>
#include <linux/hrtimer.h>
#include <linux/irq_work.h>
#include <linux/mutex.h>
#include <linux/spinlock.h>
#include <linux/wait.h>
#include <linux/workqueue.h>
#include <linux/x4step.h>

#include "x4_engine.h"
#include "x4_track.h"

#define X4_MAX_PORTS 16 /* minors: parport numbers 0..15 */
#define X4_EVENTS 256 /* events kept per port, a power of 2 */

/*
 * Locking: `lock` (a mutex) serializes open, release, ioctls and detach;
 * a path write() holds it a chunk of records at a time. The halts (BRAKE,
 * STOP, HALT, ESTOP, PATH_CTL HOLD and ABORT) and the reading ioctls take
 * only `slock`, so that nothing the mutex covers delays them.
 * `slock` (raw: taken in the hard-irq hrtimer callback, also on RT)
 * guards the engine, the brake codes and the port registers; it is taken
 * by the timer, the ioctls and the input handler, never held while
 * sleeping. The timer is (re)armed only under slock, by the ioctls that
 * start moves and by its own callback, with hrtimer_start().
 */
struct x4_port {
	struct device dev; /* lifetime: last of the files and the port */
	struct cdev cdev;
	struct parport *port;
	struct pardevice *pardev;
	struct mutex lock;
	struct file *controller; /* the one read-write opener */
	bool gone; /* the parport went away (set under both locks) */

	raw_spinlock_t slock;
	struct x4_engine eng;
	struct hrtimer timer;
	ktime_t epoch; /* engine time 0 */
	bool claimed; /* the registers are ours: write them, read them */
	/*
	 * The input pins as last read while the port was ours, and when
	 * (CLOCK_MONOTONIC, 0: never): status reads report these, marked
	 * stale, while another driver may own the port.
	 */
	u8 inputs;
	u64 inputs_ns;
	bool written_valid; /* the registers hold data_written, ctl_written */
	u8 data_written;
	u8 ctl_written;
	u8 clock_invert; /* axes whose clock is active low */
	u8 dir_invert; /* axes whose direction is inverted */
	u8 data_invert; /* the data bits XORed on output, from both */
	u32 cfg_flags;
	u16 brake_codes[X4STEP_MAX_BRAKE_CODES];
	u32 n_brake_codes;
	u32 last_brake_code;
	u64 brake_time_ns; /* CLOCK_MONOTONIC of the last brake */
	u64 moves_ended;

	struct x4step_timing timing; /* lateness of the timer, under slock */
	/*
	 * The on-time edges (x4step_port.c): when the timer was armed for,
	 * and whether early (for an edge without slack); the timer's usual
	 * lateness; the shortest port write seen (from the end of a wait
	 * to after the write; U32_MAX: none yet) of a write that clears a
	 * clock bit and of one that sets one (write_kind: the last write's,
	 * X4_WRITE_NONE if it changed no clock bit).
	 */
	ktime_t armed;
	bool armed_early;
	u8 write_kind;
	u32 late_est_ns;
	u32 write_ns[2];
	/* A goto is planned on a copy of the engine, outside slock (lock). */
	struct x4_engine plan_eng;
	struct x4_goto plan_goto;

	struct irq_work wake_work; /* wake pollers from the hard-irq timer */
	wait_queue_head_t wait; /* pollers, and readers of events */

	/*
	 * The event stream (x4step_events.c), under slock: a ring of
	 * X4_EVENTS, event `seq` at seq % X4_EVENTS, ev_seq the next one's.
	 * `ev` is the engine as last seen, and why the moves of each channel
	 * will end (engine/x4_track.c).
	 */
	struct x4step_event *events;
	u64 ev_seq;
	u64 ev_time_ns; /* the last event's time: times never go back */
	bool ev_closed; /* PORT_GONE is in the ring: readers end after it */
	struct x4_track ev;

	/*
	 * Deferred release (x4step_main.c). A controller that closes while
	 * moves run has them braked; the port stays claimed and no new
	 * controller may open ("releasing", under lock) until the engine is
	 * idle; then release_work stops the port and releases it.
	 */
	struct delayed_work release_work;
	bool releasing;

	/*
	 * Paths (x4step_path.c): the queue's storage (the engine's path
	 * points into it), changed under lock while no path is active.
	 */
	struct x4_path_slot *path_slots;
	u32 path_cfg_flags; /* X4STEP_PATH_KEYS_ABORT */
	bool path_room_wanted; /* a writer waits for room: wake it */
	struct mutex path_write_lock; /* one write(): before lock */
	struct delayed_work path_plan_work; /* the planner's pass, in time */
	u32 path_flushes_seen; /* the engine's flush count the writer knows */
};

/* One open file of /dev/x4stepN (file->private_data). */
struct x4_file {
	struct x4_port *x4;
	struct mutex read_lock; /* one read() at a time */
	u64 ev_next; /* the seq of the next event this file reads */
};

#endif /* X4STEP_DEV_H */
