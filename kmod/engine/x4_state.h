/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: its state, the structs that every level of the engine
 * shares and the glue and the tests read. Types and constants only: each
 * level's header declares its functions (x4_chan.h; x4_switch.h,
 * x4_path.h, x4_phase.h, x4_status.h; x4_engine.h on top), and includes
 * only the headers below it.
 */
#ifndef X4_STATE_H
#define X4_STATE_H

#include "x4_check.h"
#include "x4_plan.h"

/*
 * The X4Step clock's shortest half period (20 kHz): without a configured
 * pulse, no clock high or low time is shorter than this, however late the
 * timer; where a move plans shorter ones (a profile move above 20 000
 * steps/s), none is shorter than half of what it plans.
 */
#define X4_CLOCK_MIN_NS 25000u
/*
 * Port writes per second that the moves of one port may need together,
 * by default (x4_engine.budget): a leader step is two writes (clock up and
 * down), a phase-mode step one per motor. See docs/timing.md for where the
 * figure comes from.
 */
#define X4_WRITE_BUDGET 200000u

/* Control outputs as pin levels. */
#define X4_CTL_SIGNAL1 0x01 /* pin 1 */
#define X4_CTL_SIGNAL2 0x02 /* pin 14 */
#define X4_CTL_BOOST 0x04 /* pin 16: high while ramping */
#define X4_CTL_AKTIV 0x08 /* pin 17: high while a move runs */

#define X4_SMC_AXES 3 /* motors X, Y, Z: select bits 0x00, 0x40, 0x80 */

/* Reference and limit switches: inputs 1..5 (X4GetIn bit 0..4), 0 none. */
struct x4_switches {
	u8 ref[X4_AXES];
	u8 plus[X4_AXES];
	u8 minus[X4_AXES];
	u8 nc; /* bit k: input k + 1 is active while LOW */
};
#define X4_INPUTS 5

/* Per-axis state and error bits, as ProStep4's asr and error registers. */
#define X4_AX_RUN 0x001
#define X4_AX_SYNC 0x002
#define X4_AX_ERROR 0x004
#define X4_AX_REF1 0x008
#define X4_AX_REF2 0x010
#define X4_AX_ACCEL 0x100
#define X4_AX_CRUISE 0x200
#define X4_AX_DECEL 0x400
#define X4_AXERR_REF_TRAVEL 0x1
#define X4_AXERR_LIMIT_POS 0x2
#define X4_AXERR_LIMIT_NEG 0x4
#define X4_AXERR_AMBIGUOUS 0x8
#define X4_AXERR_REF_PASSED 0x10
/*
 * A reference run's phase 2 starts this long after phase 1 stood: a stop
 * without a ramp leaves the rotor ringing, and a switch bouncing; phase 2
 * starts from rest and watches a settled switch (GRBL pauses 250 ms).
 */
#define X4_HOME_SETTLE_NS 50000000ull

struct x4_axis_state {
	s32 position;
	u32 state; /* X4_AX_* */
	u32 error; /* X4_AXERR_* */
	u32 velocity; /* steps/s */
};

enum x4_phase {
	X4_IDLE, /* nothing pending */
	X4_SETUP, /* move started: directions out, first step pending */
	X4_RISE, /* clock rising edge of step n pending */
	X4_FALL, /* clock falling edge of step n pending */
	X4_END, /* end of move pending */
	X4_QUEUED, /* phase mode: more writes of the same instant */
};

/*
 * A channel runs one move: an interpolated one over several axes, or an
 * axis' own move. Channel i runs the moves whose lowest axis is i, so
 * moves on disjoint axes never share one.
 */
struct x4_chan {
	struct x4_plan run;
	enum x4_phase phase;
	bool no_steps; /* braked before its first step */
	u8 stepping; /* clock bits set by the current step */
	u8 ctl; /* AKTIV while it runs, BOOST while it ramps */
	u8 halt_mask; /* inputs that end the move ... */
	u8 halt_flip; /* ... when (inputs ^ halt_flip) & halt_mask */
	u8 deferred; /* limits left behind: armed once they are released */
	u8 home; /* X4_HOME_PHASE1/2 running, 0: no reference run */
	u8 home_next; /* phase 2 follows phase 1 */
	bool home_brake; /* phase 1 brakes past REF along the axis' ae */
	bool ref_found; /* phase 1 found REF: it stops, or brakes past it */
	u8 ref_bit;
	u64 origin; /* engine time of leader step 0 */
	u64 n; /* current leader step index */
	u64 t_cur; /* T(n) */
	u64 t_next; /* T(n + 1), when n < last */
	u64 t_pending; /* engine time of the pending event */
	u64 half_ns; /* high time of the current step */
	u64 high_min; /* shortest high time of the current step */
	u64 space_min; /* shortest low time (phase mode: step) after it */
	u32 rate; /* port writes per second at the move's top speed */
	u32 home_rate; /* a reference run's, at its faster phase */
	u64 bres[X4_AXES]; /* Bresenham accumulators of the minor axes */
	u8 queue[X4_SMC_AXES]; /* phase mode: more writes due at t_pending */
	u8 queued;
	u8 qhead;
	u8 phase_after; /* the phase when the queue is done, due at t_after */
	u64 t_after;
	s32 vref2; /* reference run: phase 2 speed */
	u32 sref;
	bool path; /* runs the path (x4_path.c): channel 0 only */
	bool path_cut; /* ... and was stopped: the path ends here */
	u8 dir_fresh; /* clocks whose direction changed at dir_ready - setup */
	u64 dir_ready; /* ... and may step from then on */
	u8 probe_mask; /* a probing segment's input (x4_path.c) ... */
	u8 probe_flip; /* ... trips it when (levels ^ probe_flip) & probe_mask */
};

/*
 * The path's queue and its state (x4_path.h tells who writes what, and
 * when).
 */
/* A queued segment and its planned entry speed (path units/s). */
struct x4_path_slot {
	struct x4_segment seg;
	u32 leader; /* the leader axis' steps: max |steps[i]| */
	u32 v_rate; /* the path speed of the port's fastest leader rate */
	u32 limit; /* its entry's limit: corner, reversal, top speed */
	u32 accel; /* its leader's acceleration, steps/s^2 */
	u64 two_as; /* 2 a length, path units: v^2 gained or lost along it */
	u32 entry; /* the writer stores it, the timer reads it (once) */
	u32 v_rev; /* the fastest entry an axis reversing into it allows */
	u8 dirs; /* the direction pins after it (X4_DIR_BIT) */
};

enum x4_path_state {
	X4_PATH_IDLE, /* nothing runs; segments queued start at the next kick */
	X4_PATH_RUN,
	X4_PATH_HOLDING, /* braking along the path to rest */
	X4_PATH_HELD, /* at rest on the path: resume, or abort */
};

/* Why the path's channel came to rest (x4_path.c, when it ends). */
enum x4_path_rest {
	X4_REST_CUT, /* stopped at once, or at a limit: the queue is flushed */
	X4_REST_DRY, /* the queue ran empty */
	X4_REST_HELD, /* a hold reached rest */
};

/*
 * The probe latch: where the last probing segment that ran stopped
 * waiting (x4_path.h). Cleared when a probing segment starts.
 */
struct x4_probe_latch {
	bool tripped; /* its input reached the awaited state */
	s32 position[X4_AXES]; /* every axis' coordinate at that step tick */
	u64 tag; /* the probing segment's */
	u64 runs; /* probing segments started */
	u64 trips; /* ... and tripped */
};

struct x4_path {
	struct x4_path_slot *slot; /* `depth` slots, from the glue */
	u32 depth; /* a power of 2; 0: no queue */
	u32 head; /* the running (or next) segment; the timer's */
	u32 tail; /* the next free slot; the writer's */
	u8 state; /* enum x4_path_state, under the engine's lock */
	u8 rest; /* enum x4_path_rest */
	bool abort; /* flush the queue once held */
	bool started; /* the segment at head has started */
	bool lonely; /* it started with nothing queued after it */
	u16 override; /* percent of v_max, 1..200 */
	/* The running segment, in its leader's steps and steps/s. */
	u32 leader;
	u32 accel;
	u32 exit; /* its planned end speed, fixed at its start */
	u32 pos; /* steps done before the running piece */
	u32 piece; /* steps of the running piece */
	u32 v_end; /* speed at the end of the running piece */
	u32 flushes; /* queues flushed: the glue's writers learn of them */
	/* The writer's backward pass (x4_path_plan()). */
	u32 plan; /* the slot whose entry it plans next */
	u32 plan_tail; /* the tail it started from */
	u64 planned; /* entries it planned: its cost, for the tests */
	u64 done; /* segments completed */
	u64 starved; /* refills that came after the path began to stop */
	u64 frac; /* the ns fraction the pieces' ends left out, 32.32 */
	u8 probe_input; /* 1..5 (X4GetIn bit 0..4), 0: none */
	bool probe_nc; /* ... active while LOW */
	struct x4_probe_latch latch;
};

struct x4_engine {
	struct x4_chan ch[X4_AXES];
	struct x4_plan next; /* the loaded (preloaded) move */
	bool loaded;
	u8 busy; /* bit i: channel i runs */
	bool solo; /* only one channel runs */
	/* The channel whose event is due first (copies must not run). */
	struct x4_chan *cur;
	u64 due; /* its time */
	u64 ends; /* counts moves that came to an end */

	u8 data; /* current pin levels */
	u8 ctl;
	struct x4_timing timing;
	u8 mode; /* enum x4_output_mode */
	u8 smc_phase[X4_SMC_AXES]; /* half-step table index of each motor */

	s64 steps[X4_AXES]; /* signed steps since the axis' last start */
	u32 pos_base[X4_AXES]; /* coordinate = pos_base + steps, mod 2^32 */
	u8 sync; /* bit i: axis i's coordinate is referenced */
	u8 err[X4_AXES]; /* X4_AXERR_* */
	struct x4_profile prof[X4_AXES];
	struct x4_switches sw;
	u8 inputs; /* active switches (after NO/NC), last sampled */
	u8 levels; /* ... and the input levels (X4GetIn bits) they came from */

	/*
	 * A late event never makes a pulse, space or phase step shorter than
	 * its minimum: the channel's remaining schedule moves instead. These
	 * count how often and by how much (the glue reads and clears them).
	 */
	u64 shifts;
	u64 shifted_ns;
	struct x4_chan *fired; /* the channel of the last step edge fired */
	bool edge_shifted; /* ... and that edge moved its schedule already */
	u32 budget; /* port writes per second, all moves together; 0: none */
	struct x4_path path;
};

#endif /* X4_STATE_H */
