/* SPDX-License-Identifier: GPL-2.0 WITH Linux-syscall-note */
/*
 * x4step: user-space interface of the x4step kernel module.
 *
 * One char device /dev/x4stepN per parallel port parportN. One process at
 * a time opens it read-write and controls the motors; any number may open
 * it read-only to watch (status, poll, events through read()). Structures
 * hold fixed-width fields only, are padded to 64 bits, and their reserved
 * fields must be zero, so 32-bit programs use the same layout and later
 * versions can extend them.
 *
 * The read-write open claims the parallel port; it fails with EBUSY while
 * another controller has the device, while the module still brakes the
 * moves of a controller that closed (close() starts the brake along the
 * ramps and returns; the port is kept until the motors stand), or while
 * another parport driver (lp, ppdev) has claimed the port. poll() reports
 * POLLIN when no move runs and no such brake is pending, POLLERR | POLLHUP
 * when the port went away, and (ABI 4) POLLPRI when the descriptor has
 * events to read() (struct x4step_event, below).
 *
 * Errors: every ioctl returns 0 or -1 with errno set.
 *   EINVAL  a parameter is out of range; for the ioctls with a
 *           `result` field the X4Step error code (1..13, as in
 *           x4step.h) is written back into it
 *   EBUSY   a move is running (X4ErrIsActive)
 *   EEXIST  a move is loaded already (X4ErrIsLoaded)
 *   ENODATA no move is loaded (X4ErrNotLoaded)
 *   ESRCH   no move is running (X4ErrNotActive)
 *   ERANGE  a start that the port's write budget cannot take beside the
 *           moves that run (module parameter write_budget, port writes
 *           per second); `result` is X4ErrFreqTooHigh
 *   EBADF   a state-changing ioctl on a read-only descriptor (all but
 *           X4STEP_ESTOP, which any descriptor may make)
 *   ENODEV  the parallel port went away
 *   ENOTTY  unknown ioctl
 */
#ifndef _UAPI_LINUX_X4STEP_H
#define _UAPI_LINUX_X4STEP_H

#include <linux/ioctl.h>
#include <linux/types.h>

/*
 * 2: positioning; 3: GET_TIMING counts every event, and shifts;
 * 4: events through read() (x4step_event, POLLPRI), X4STEP_SET_OUTPUTS,
 * status reads that leave an unclaimed port alone (X4STEP_ST_INPUTS_STALE);
 * 5: continuous paths (x4step_segment through write(), X4STEP_PATH_*),
 * X4STEP_ESTOP, and X4STEP_VEL_MAX 100000 (was 45000);
 * 6: probing segments (X4STEP_SEG_PROBE_*, x4step_path_config.probe,
 * X4STEP_GET_PROBE, X4STEP_SW_PROBE).
 * A version only adds: a program built for version N runs on any >= N.
 */
#define X4STEP_ABI_VERSION 6
#define X4STEP_AXES 4
#define X4STEP_MAX_BRAKE_CODES 20

/* X4STEP_GET_INFO */
struct x4step_info {
	__u32 abi_version; /* X4STEP_ABI_VERSION */
	__u32 axes; /* X4STEP_AXES */
	__u32 port; /* N of parportN */
	__u32 event_buffer; /* ABI 4: events kept per port (see x4step_event) */
	__u32 reserved[4];
};

/* X4STEP_LOAD: an interpolated move (X4Load). */
struct x4step_move {
	__s32 steps[X4STEP_AXES]; /* -16777216..16777216, one non-zero */
	__s32 freq_hz; /* leader frequency, 10..20000 */
	__s32 ramp_ms; /* 0..1000, and ramp_ms <= freq_hz */
	__u32 flags; /* must be 0 */
	__s32 result; /* out: X4Step error code */
};

/* X4STEP_MOVE_ENDLESS: one axis until braked (X4MovePos/X4MoveNeg). */
struct x4step_endless {
	__s32 axis; /* 1..4 */
	__s32 direction; /* +1 or -1 */
	__s32 freq_hz;
	__s32 ramp_ms;
	__u32 flags; /* must be 0 */
	__s32 result; /* out: X4Step error code */
	__u32 reserved[2];
};

/* Flags of struct x4step_status. */
#define X4STEP_ST_ACTIVE (1u << 0) /* a move runs (the AKTIV signal) */
#define X4STEP_ST_LOADED (1u << 1) /* a move is loaded */
/* A controller has the device open, or its moves still brake after close. */
#define X4STEP_ST_CONTROLLED (1u << 2)
/*
 * ABI 4: `inputs` were not read now but are the levels last read, at
 * inputs_time_ns (0: never): the module reads the port's status register
 * only while it has claimed the port, that is while a controller has the
 * device open (or its moves still brake after close). The rest of the
 * time another parport driver (lp, ppdev) may own the port, and x4step
 * leaves its registers alone. Also in x4step_axes.flags.
 */
#define X4STEP_ST_INPUTS_STALE (1u << 3)

/* Output pins in x4step_status.outputs and x4step_output.signal. */
#define X4STEP_OUT_SIGNAL1 (1u << 0) /* pin 1 */
#define X4STEP_OUT_SIGNAL2 (1u << 1) /* pin 14 */
#define X4STEP_OUT_BOOST (1u << 2) /* pin 16, driven by the engine */
#define X4STEP_OUT_AKTIV (1u << 3) /* pin 17, driven by the engine */

/*
 * X4STEP_GET_STATUS: readable on any descriptor, never blocks. Touches
 * no port register unless x4step has claimed the port (see
 * X4STEP_ST_INPUTS_STALE).
 */
struct x4step_status {
	__u32 flags; /* X4STEP_ST_* */
	__u32 last_brake_code; /* key code that braked the last move, or 0 */
	/* X4GetIn: bit0 pin15, bit1 pin13, bit2 pin12, bit3 pin10, bit4 pin11 */
	__u32 inputs; /* 1 = HIGH; see X4STEP_ST_INPUTS_STALE */
	__u32 outputs; /* X4STEP_OUT_* levels (1 = HIGH) */
	__s64 steps[X4STEP_AXES]; /* signed steps since the last start */
	__u64 moves_ended; /* counts moves that came to an end */
	__u32 data; /* data register pin levels (pins 2..9) */
	__u32 reserved0;
	__u64 brake_time_ns; /* CLOCK_MONOTONIC of the last brake request */
	__u64 inputs_time_ns; /* ABI 4: CLOCK_MONOTONIC the inputs were read */
};

/*
 * X4STEP_SET_OUTPUT: X4SetOut, ABI 1 to 3. Kept for the programs built
 * for them; it cannot be extended: new programs use X4STEP_SET_OUTPUTS.
 */
struct x4step_output {
	__u32 signal; /* X4STEP_OUT_SIGNAL1 or X4STEP_OUT_SIGNAL2 */
	__u32 level; /* 0 or 1 */
};

/*
 * X4STEP_SET_OUTPUTS (ABI 4): set the signals in `mask` to their bits in
 * `levels`, both in one write of the control register. EINVAL for an
 * empty mask, bits beyond the signals, levels outside the mask, or
 * non-zero flags or reserved words (kept for later use).
 */
struct x4step_outputs {
	__u32 mask; /* X4STEP_OUT_SIGNAL1 | X4STEP_OUT_SIGNAL2, non-zero */
	__u32 levels; /* 1 = HIGH */
	__u32 flags; /* must be 0 */
	__u32 reserved[5]; /* must be 0 */
};

/* X4STEP_SET_BRAKE_CODES: X4BrakeCodes. ESC (1) always brakes. */
struct x4step_brake_codes {
	__u32 count; /* 0..X4STEP_MAX_BRAKE_CODES */
	/* set-1 make (1..127) or break (129..255) codes */
	__u16 codes[X4STEP_MAX_BRAKE_CODES];
	__u32 reserved; /* must be 0 */
};

/* Output modes (x4step_config.output_mode). */
#define X4STEP_MODE_CLOCK_DIR 0 /* step and direction signals (X4Step) */
/* SMC800/SMC1500 half-step phase patterns, motors off at rest */
#define X4STEP_MODE_SMC_PHASE 1
#define X4STEP_MODE_SMC_PHASE_HOLD 2 /* the same, reduced current at rest */

/*
 * X4STEP_SET_CONFIG / X4STEP_GET_CONFIG: per-port wiring. SET_CONFIG only
 * while no move runs (EBUSY); it puts the port at rest for the new wiring
 * in one data write (phase modes: the motors' rest patterns), so no clock
 * makes an edge that a driver wired the new way counts as a step.
 */
/*
 * Brake keys reach applications too unless this is set: then, as in the
 * DOS library, a brake key pressed while a move runs is swallowed.
 */
#define X4STEP_CFG_KEYS_SWALLOW (1u << 0)
struct x4step_config {
	__u32 clock_invert; /* bit i: axis i+1 clock is active low */
	__u32 dir_invert; /* bit i: axis i+1 direction inverted */
	__u32 flags; /* X4STEP_CFG_* */
	__u32 output_mode; /* X4STEP_MODE_* */
	__u32 reserved[4];
};

/*
 * X4STEP_SET_STEP_TIMING / X4STEP_GET_STEP_TIMING: step signal timing of
 * the port, each at most 1 ms. Defaults from the module parameters (the
 * X4Step behaviour: symmetric clock, 100 us direction setup). Moves whose
 * frequency leaves less than pulse_ns + space_ns per step (symmetric
 * clock: less than space_ns per half period) are refused with
 * X4ErrFreqTooHigh.
 */
struct x4step_step_timing {
	__u32 pulse_ns; /* clock high time; 0: half the step period */
	__u32 space_ns; /* minimum clock low time */
	__u32 dir_setup_ns; /* directions before the first clock edge */
	__u32 dir_hold_ns; /* directions after the last clock edge */
	__u32 reserved[4];
};

/*
 * X4STEP_GET_TIMING: how late the step timer's events fired since the
 * last read by the controller, which resets it (a read-only descriptor
 * reads without resetting). An event is one edge or port write of a move;
 * its lateness is from its planned time to the moment it was fired
 * (the port write follows within the engine's few hundred instructions).
 * hist[i] counts lateness in [i, i + 1) * X4STEP_TIMING_BUCKET_NS; later
 * ones in `beyond`. No pulse or space is ever shortened to make up for
 * lateness: where the next step would come too soon the rest of that
 * move's schedule moves later, counted in `shifts` and `shifted_ns`.
 * A timer callback fires at most a few events, for at most about 20 us,
 * then re-arms: `capped` counts the callbacks that stopped at that limit.
 * An edge with less slack than the timer's usual lateness (at 20 kHz with
 * 25 us pulse and space: none) has its timer armed early by that lateness,
 * and the callback waits out the rest, at most a few microseconds, with
 * interrupts off: `spins` counts those edges and `spin_ns` the time spent
 * waiting (zero from modules before this, which had reserved fields here).
 */
#define X4STEP_TIMING_BUCKETS 512
#define X4STEP_TIMING_BUCKET_NS 64
struct x4step_timing {
	__u64 events;
	__u64 late_max_ns;
	__u64 beyond;
	__u64 reserved;
	__u32 hist[X4STEP_TIMING_BUCKETS];
	/* ABI 3 */
	__u64 callbacks; /* timer callbacks that fired events */
	__u64 capped;
	__u64 shifts;
	__u64 shifted_ns;
	__u64 spins; /* edges placed by a bounded wait in the callback */
	__u64 spin_ns; /* time spent in those waits */
	__u64 reserved3[2];
};

/*
 * Positioning (the ProStep4 model). Axes are numbered 1..4; an axis mask
 * has bit i for axis i + 1. Every step of every kind of move updates the
 * axis' machine coordinate (signed 32 bits, wrapping).
 */
#define X4STEP_VEL_MAX 100000 /* steps/s */
#define X4STEP_ACC_MAX 1000000 /* steps/s^2 */

/*
 * X4STEP_SET_PROFILE / X4STEP_GET_PROFILE: the ramp of an axis' own moves
 * (X4STEP_GOTO). Velocities in steps/s, accelerations in steps/s^2. The
 * axis starts at v0, accelerates with a0 to vm, and decelerates with ae
 * to ve, where it stops; a0 or ae 0: no ramp on that side. A move too
 * short to reach vm turns where the ramps meet; one too short to brake
 * from v0 to ve starts at the speed from which the ramp just reaches ve,
 * and one too short to accelerate to ve accelerates all the way (ending
 * slower than ve). Rules: 1 <= vm <= X4STEP_VEL_MAX,
 * v0 <= vm, ve <= vm, a0, ae <= X4STEP_ACC_MAX, and each ramp at most
 * 3600 s long. Default: v0 = ve = 0, a0 = ae = 1000, vm = 1000.
 */
struct x4step_profile {
	__u32 axis; /* 1..4 */
	__u32 v0; /* start velocity */
	__u32 ve; /* stop velocity */
	__u32 vm; /* maximum velocity */
	__u32 a0; /* acceleration */
	__u32 ae; /* deceleration */
	__u32 reserved[2];
};

/* Flags of struct x4step_goto. */
#define X4STEP_GOTO_RELATIVE (1u << 0) /* target[] are distances */

/*
 * X4STEP_GOTO: independent moves of the axes in `axes`, each with its own
 * profile, all started at once; other axes may be moving meanwhile. Each
 * axis must be idle. An axis already at its target does not move. An
 * absolute target is reached by the signed difference to the coordinate
 * (no wrap-around: INT32_MIN to INT32_MAX is 2^32 - 1 steps forward).
 */
struct x4step_goto {
	__u32 axes; /* axis mask, non-zero */
	__u32 flags; /* X4STEP_GOTO_* */
	__s32 target[X4STEP_AXES]; /* coordinates (or distances) */
	__s32 result; /* out: X4Step error code */
	__u32 reserved[3];
};

/* Phases of struct x4step_home. */
#define X4STEP_HOME_PHASE1 (1u << 0) /* at vref1 until REF becomes active */
#define X4STEP_HOME_PHASE2 (1u << 1) /* at vref2 until REF changes again */
#define X4STEP_HOME_AUTO (X4STEP_HOME_PHASE1 | X4STEP_HOME_PHASE2)
/* ABI 4: phase 1 brakes past REF along the axis' profile ae (with PHASE1) */
#define X4STEP_HOME_BRAKE (1u << 2)

/*
 * X4STEP_HOME: a reference run of one axis, without ramps (ProStep4
 * section 3): each phase starts and stops at its speed. Phase 1 stops
 * where REF becomes active, or with X4STEP_HOME_BRAKE brakes past it along
 * the axis' profile deceleration ae (vref1 / ae at most 3600 s; REF must
 * stay active over that distance, else the run ends there with
 * X4STEP_AXERR_REF_PASSED). Phase 2 starts from rest, 50 ms after phase 1
 * stood (the rotor and the switch settle), and stops where REF changes,
 * zeroing the coordinate and synchronizing the axis. Each phase travels
 * at most sref steps, else the axis stops with X4STEP_AXERR_REF_TRAVEL.
 * Needs a REF input for the axis (X4STEP_SET_SWITCHES).
 */
struct x4step_home {
	__u32 axis; /* 1..4 */
	__u32 phases; /* X4STEP_HOME_* */
	__s32 vref1; /* signed steps/s: direction and speed of phase 1 */
	__s32 vref2; /* ... of phase 2 */
	__u32 sref; /* maximum travel of a phase, 1..2^31 - 1 steps */
	__s32 result; /* out: X4Step error code */
	__u32 reserved[2];
};

/* How of struct x4step_halt. */
#define X4STEP_HALT_BRAKE 0 /* along the ramp */
#define X4STEP_HALT_STOP 1 /* at once: the axes lose their synchronization */

/*
 * X4STEP_HALT: brake or stop the moves of the axes in `axes`. The axes
 * moving interpolated with them halt too. ESRCH if none of them moves.
 */
struct x4step_halt {
	__u32 axes;
	__u32 how; /* X4STEP_HALT_* */
	__u32 reserved[2];
};

/*
 * X4STEP_SET_POSITION: "stop and zero": stop the axes in `axes` at once
 * (with their interpolated partners), then set their coordinates and
 * mark them synchronized.
 */
struct x4step_position {
	__u32 axes;
	__u32 reserved;
	__s32 position[X4STEP_AXES];
};

/*
 * X4STEP_SET_SWITCHES / X4STEP_GET_SWITCHES: inputs 1..5 (X4GetIn bits
 * 0..4) as reference and limit switches of the axes; 0 = none. An input
 * may serve several axes and both directions (switches in parallel); a
 * hit is then attributed to every axis that was moving toward such a
 * limit, flagged X4STEP_AXERR_AMBIGUOUS when more than one could have
 * caused it. Normally open switches are active while their pin is HIGH,
 * normally closed ones while it is LOW. Only while no move runs.
 */
struct x4step_switches {
	__u8 ref[X4STEP_AXES]; /* reference switch input of each axis */
	__u8 plus[X4STEP_AXES]; /* limit E+ */
	__u8 minus[X4STEP_AXES]; /* limit E- */
	__u8 nc; /* bit k: input k + 1 is normally closed */
	__u8 reserved[7];
};

/* State bits of struct x4step_axis (ProStep4's status register asr). */
#define X4STEP_AX_RUN (1u << 0) /* the axis moves */
#define X4STEP_AX_SYNC (1u << 1) /* the coordinate is referenced */
#define X4STEP_AX_ERROR (1u << 2) /* error != 0 */
#define X4STEP_AX_REF1 (1u << 3) /* reference run, phase 1 */
#define X4STEP_AX_REF2 (1u << 4) /* reference run, phase 2 */
#define X4STEP_AX_ACCEL (1u << 8) /* accelerating */
#define X4STEP_AX_CRUISE (1u << 9) /* at constant speed */
#define X4STEP_AX_DECEL (1u << 10) /* decelerating */
/* Error bits (ProStep4's error register), cleared by the axis' next move. */
#define X4STEP_AXERR_REF_TRAVEL (1u << 0) /* sref exceeded */
#define X4STEP_AXERR_LIMIT_POS (1u << 1) /* stopped at E+ */
#define X4STEP_AXERR_LIMIT_NEG (1u << 2) /* stopped at E- */
#define X4STEP_AXERR_AMBIGUOUS (1u << 3) /* the input serves other limits */
/* ABI 4: phase 1's brake (X4STEP_HOME_BRAKE) ran off the REF switch */
#define X4STEP_AXERR_REF_PASSED (1u << 4)

struct x4step_axis {
	__s32 position; /* machine coordinate */
	__u32 state; /* X4STEP_AX_* */
	__u32 error; /* X4STEP_AXERR_* */
	__u32 velocity; /* current speed, steps/s (the current step interval) */
};

/* X4STEP_GET_AXES: readable on any descriptor, never blocks. */
struct x4step_axes {
	struct x4step_axis axis[X4STEP_AXES];
	__u32 inputs; /* as x4step_status.inputs */
	__u32 switches; /* bit k: input k + 1 is active (after NO/NC) */
	__u32 flags; /* ABI 4: X4STEP_ST_INPUTS_STALE, or 0 */
	__u32 reserved;
};

/*
 * Events (ABI 4). read() on any descriptor, read-only ones included,
 * returns whole struct x4step_event records: as many as fit in the buffer
 * and are there (EINVAL for a buffer smaller than one). With none to read
 * it blocks, or fails with EAGAIN under O_NONBLOCK; once the port is gone
 * and everything is read, with ENODEV. A descriptor reads what happens
 * after its open(), from its own position: the module keeps the last
 * x4step_info.event_buffer events of the port (256), and a reader that
 * fell further behind resumes at the oldest one kept: the gap in `seq`
 * says how many it missed.
 *
 * poll(): POLLPRI when there are events to read. POLLIN keeps its meaning
 * (no move runs), so programs that wait for POLLIN, and libraries that
 * share the descriptor, are not woken for events: wait for POLLPRI (or
 * select()'s exceptfds, EPOLLPRI) to read them.
 *
 * A reader skips events of types it does not know, and treats `how`
 * values it does not know as "other": later versions add both (a path
 * queue's segments started and ended, hold and resume, starvation).
 * Reserved fields are zero.
 */
#define X4STEP_EV_MOVE_STARTED 1 /* how: X4STEP_KIND_*; axes: its axes */
#define X4STEP_EV_MOVE_ENDED 2 /* how: X4STEP_END_*; axes: its axes */
/* A brake was asked for; how: X4STEP_SRC_*, value: the key's code */
#define X4STEP_EV_BRAKE 3
/* A switch stopped a move; how: X4STEP_SW_*, value: the input 1..5 */
#define X4STEP_EV_SWITCH 4
#define X4STEP_EV_CONTROLLER 5 /* how: X4STEP_CTL_* */
#define X4STEP_EV_PORT_GONE 6 /* the last event of a port */

/* Kinds of moves (how of X4STEP_EV_MOVE_STARTED). */
#define X4STEP_KIND_LOADED 1 /* X4STEP_START: an interpolated move */
#define X4STEP_KIND_ENDLESS 2 /* X4STEP_MOVE_ENDLESS */
#define X4STEP_KIND_GOTO 3 /* X4STEP_GOTO: one per axis that moves */
#define X4STEP_KIND_HOME 4 /* X4STEP_HOME */
#define X4STEP_KIND_PATH 5 /* ABI 5: a path started, or resumed from a hold */

/* How moves end (how of X4STEP_EV_MOVE_ENDED). */
#define X4STEP_END_COMPLETED 1 /* as planned */
#define X4STEP_END_BRAKED 2 /* a brake was asked for while it ran */
#define X4STEP_END_STOPPED 3 /* at once: X4STEP_STOP, HALT, SET_POSITION, */
				/* the module's release, the port's removal */
#define X4STEP_END_LIMIT 4 /* a limit switch (see X4STEP_EV_SWITCH) */
#define X4STEP_END_HOMED 5 /* reference run done: at 0, synchronized */
#define X4STEP_END_REF_FOUND 6 /* a phase-1-only run found REF */
#define X4STEP_END_REF_TRAVEL 7 /* a reference phase went beyond sref */
#define X4STEP_END_REF_PASSED 8 /* phase 1's brake ran off the REF switch */
#define X4STEP_END_HELD 9 /* ABI 5: a path's hold reached rest on the path */
#define X4STEP_END_ABORTED 10 /* ABI 5: a path held, and its queue flushed */

/* Who asked for a brake (how of X4STEP_EV_BRAKE). */
#define X4STEP_SRC_IOCTL 1 /* X4STEP_BRAKE or X4STEP_HALT */
#define X4STEP_SRC_KEY 2 /* a brake key; value: its set-1 code */
#define X4STEP_SRC_CLOSE 3 /* the controller closed while moves ran */
/*
 * X4STEP_ESTOP, from any descriptor (a monitor's too); value: its
 * X4STEP_HALT_*. With X4STEP_HALT_STOP the moves end X4STEP_END_STOPPED.
 */
#define X4STEP_SRC_ESTOP 4

/* Switches (how of X4STEP_EV_SWITCH); one event per axis. */
#define X4STEP_SW_LIMIT_POS 1 /* E+ */
#define X4STEP_SW_LIMIT_NEG 2 /* E- */
#define X4STEP_SW_REF 3 /* REF: a reference phase ended */
/*
 * ABI 6: a probing segment's input reached the state it waits for; axes:
 * the path's (every axis of the output mode). The path ends ABORTED.
 */
#define X4STEP_SW_PROBE 4

/* Controllers (how of X4STEP_EV_CONTROLLER). */
#define X4STEP_CTL_OPENED 1
#define X4STEP_CTL_CLOSED 2 /* its moves, if any, brake (X4STEP_SRC_CLOSE) */
#define X4STEP_CTL_RELEASED 3 /* the port is free: a controller may open */

/* Flags of struct x4step_event. */
#define X4STEP_EVF_AMBIGUOUS (1u << 0) /* the input serves other limits */

struct x4step_event {
	__u64 seq; /* 1, 2, 3, ... per port */
	__u64 timestamp_ns; /* CLOCK_MONOTONIC; never decreases */
	__u32 type; /* X4STEP_EV_* */
	__u32 axes; /* axis mask (bit i: axis i + 1), or 0 */
	__u32 how; /* by type, above */
	__u32 value; /* by type, above; else 0 */
	__s32 position[X4STEP_AXES]; /* every axis' coordinate then */
	__u32 flags; /* X4STEP_EVF_* */
	__u32 reserved[3];
};

#define X4STEP_IOC_MAGIC 0xB4

/*
 * X4STEP_ESTOP: the emergency halt of every move on the port, whoever
 * controls it. Unlike the other state-changing ioctls it is allowed on
 * any descriptor, read-only ones too: anyone who may open the device
 * (group lp) can halt the motors of another program's controller, or
 * the brake of one that closed. `how` is X4STEP_HALT_BRAKE (along the
 * ramps) or X4STEP_HALT_STOP (at once: the axes lose their
 * synchronization). The event stream shows an X4STEP_EV_BRAKE with
 * how X4STEP_SRC_ESTOP and value `how`, then the ends of the moves.
 * A path is aborted (held, then flushed; a held one at once). EINVAL for
 * another `how` or non-zero flags or reserved words; ESRCH if no move
 * runs and no path stands held; ENODEV once the port is gone. Modules before this
 * ioctl answer ENOTTY.
 */
struct x4step_estop {
	__u32 how; /* X4STEP_HALT_* */
	__u32 flags; /* must be 0 */
	__u32 reserved[2]; /* must be 0 */
};

/* Read the interface version. */
#define X4STEP_GET_INFO _IOR(X4STEP_IOC_MAGIC, 0x00, struct x4step_info)
/* Load (or preload while a move runs) an interpolated move. */
#define X4STEP_LOAD _IOWR(X4STEP_IOC_MAGIC, 0x01, struct x4step_move)
/* Start the loaded move; clears the step counters. */
#define X4STEP_START _IO(X4STEP_IOC_MAGIC, 0x02)
/* Brake along the ramp. */
#define X4STEP_BRAKE _IO(X4STEP_IOC_MAGIC, 0x03)
/* Emergency stop: no further step. */
#define X4STEP_STOP _IO(X4STEP_IOC_MAGIC, 0x04)
/* Start an endless move of one axis. */
#define X4STEP_MOVE_ENDLESS _IOWR(X4STEP_IOC_MAGIC, 0x05, struct x4step_endless)
/* Read the status. */
#define X4STEP_GET_STATUS _IOR(X4STEP_IOC_MAGIC, 0x06, struct x4step_status)
/* Set output signal 1 or 2 (ABI 1..3; see X4STEP_SET_OUTPUTS). */
#define X4STEP_SET_OUTPUT _IOW(X4STEP_IOC_MAGIC, 0x07, struct x4step_output)
/* Set the brake keys. */
#define X4STEP_SET_BRAKE_CODES _IOW(X4STEP_IOC_MAGIC, 0x08, struct x4step_brake_codes)
/* Set and read the wiring configuration (only while no move runs). */
#define X4STEP_SET_CONFIG _IOW(X4STEP_IOC_MAGIC, 0x09, struct x4step_config)
#define X4STEP_GET_CONFIG _IOR(X4STEP_IOC_MAGIC, 0x0a, struct x4step_config)
/* Set and read the step timing (only while no move runs). */
#define X4STEP_SET_STEP_TIMING _IOW(X4STEP_IOC_MAGIC, 0x0c, struct x4step_step_timing)
#define X4STEP_GET_STEP_TIMING _IOR(X4STEP_IOC_MAGIC, 0x0d, struct x4step_step_timing)
/* Read the timer lateness statistics (the controller's read resets them). */
#define X4STEP_GET_TIMING _IOR(X4STEP_IOC_MAGIC, 0x0b, struct x4step_timing)
/* The same in ABI 2's size: only the fields up to hist[] (2080 bytes). */
#define X4STEP_TIMING_V2_SIZE (4 * 8 + 4 * X4STEP_TIMING_BUCKETS)
#define X4STEP_GET_TIMING_V2 _IOC(_IOC_READ, X4STEP_IOC_MAGIC, 0x0b, \
				  X4STEP_TIMING_V2_SIZE)
/* Positioning: profiles, independent moves, homing, halts, switches. */
#define X4STEP_SET_PROFILE _IOW(X4STEP_IOC_MAGIC, 0x10, struct x4step_profile)
#define X4STEP_GET_PROFILE _IOWR(X4STEP_IOC_MAGIC, 0x11, struct x4step_profile)
#define X4STEP_GOTO _IOWR(X4STEP_IOC_MAGIC, 0x12, struct x4step_goto)
#define X4STEP_HOME _IOWR(X4STEP_IOC_MAGIC, 0x13, struct x4step_home)
#define X4STEP_HALT _IOW(X4STEP_IOC_MAGIC, 0x14, struct x4step_halt)
#define X4STEP_SET_POSITION _IOW(X4STEP_IOC_MAGIC, 0x15, struct x4step_position)
#define X4STEP_SET_SWITCHES _IOW(X4STEP_IOC_MAGIC, 0x16, struct x4step_switches)
#define X4STEP_GET_SWITCHES _IOR(X4STEP_IOC_MAGIC, 0x17, struct x4step_switches)
#define X4STEP_GET_AXES _IOR(X4STEP_IOC_MAGIC, 0x18, struct x4step_axes)
/* ABI 4: set output signals 1 and 2. */
#define X4STEP_SET_OUTPUTS _IOW(X4STEP_IOC_MAGIC, 0x19, struct x4step_outputs)
/* Emergency halt of every move, from any descriptor, read-only ones too. */
#define X4STEP_ESTOP _IOW(X4STEP_IOC_MAGIC, 0x20, struct x4step_estop)

/*
 * Continuous paths (ABI 5). The controller streams segments with write():
 * whole struct x4step_segment records (EINVAL for another size). A segment
 * moves the axes by `steps` (Bresenham, as X4STEP_LOAD's moves) along
 * `length` units of the path (a unit user space chooses: the leader axis'
 * steps lie at equal distances), at path speeds in units/s. A unit may be
 * coarser than a step (mm): speeds are planned in whole units/s, and run
 * and carried from segment to segment in steps. The module
 * plans ahead over its queue, so that the queue as planned always ends at
 * rest: if the writer is late, the path slows down and stops on it; when a
 * controller closes or dies, the path holds and its queue is flushed.
 *
 * write() queues whole records, in order, and returns the bytes of those
 * queued. A full queue blocks, or under O_NONBLOCK returns what fit (EAGAIN
 * if none did); poll() reports POLLOUT when there is room. A bad record
 * fails with EINVAL (ERANGE: faster than the port's rate, EBUSY: other
 * moves run) and is not queued; records before it in the same write() are
 * queued and counted. A path owns every axis while it is active (running,
 * holding, held or queued): X4Step moves and gotos fail with EBUSY.
 *
 * Once a path's queue is flushed (a stop, an emergency stop, a limit, an
 * abort, a brake key with X4STEP_PATH_KEYS_ABORT), write() fails with
 * ECANCELED until the controller acknowledges it with X4STEP_PATH_CLEAR
 * (or a new controller opens): a program streaming a path learns that it
 * was stopped, instead of running the rest of it from where it stood.
 *
 * Where an axis reverses at a junction, the planner caps the junction's
 * speed so that the axis' first step in the new segment comes no sooner
 * than dir_setup_ns after its direction changed, which is dir_hold_ns
 * after the clock of the segment before fell (X4STEP_SET_STEP_TIMING): a
 * reversal never makes the path wait in the middle of a junction. An axis
 * whose first step comes late enough anyway costs no speed.
 *
 * Starts and ends show in the event stream: MOVE_STARTED (KIND_PATH), and
 * MOVE_ENDED with COMPLETED (the queue ran empty), HELD, ABORTED, STOPPED
 * or LIMIT, with the path's axes: every axis of the output mode, whichever
 * segments move; the abort of a held path ends it (ABORTED) at once. A hold
 * stands HELD wherever it comes to rest, at the queue's end too: what is
 * written then waits for a resume. X4STEP_BRAKE and brake keys hold a
 * path (keys: then abort, with X4STEP_PATH_KEYS_ABORT, a held path too);
 * X4STEP_ESTOP's brake and the controller's close abort it; X4STEP_STOP
 * stops it at once and flushes.
 *
 * Probing (ABI 6; G38.2..G38.5): a segment with X4STEP_SEG_PROBE_TOWARD or
 * X4STEP_SEG_PROBE_AWAY watches the path's probe input (x4step_path_config
 * .probe; a probing segment without one is EINVAL) on every step tick, as
 * a limit switch is watched. At the first tick the input is in the state
 * the segment waits for (TOWARD: active, AWAY: inactive), the module
 * latches every axis' coordinate: the position at which the input changed,
 * before that tick's step, whatever the speed. Then the path brakes along
 * the path with the segment's acceleration, as a hold does, and its queue
 * is flushed, as an abort's is (write() fails with ECANCELED until
 * X4STEP_PATH_CLEAR); the events show an X4STEP_EV_SWITCH with how
 * X4STEP_SW_PROBE, then the path's end, ABORTED. A segment that starts
 * from rest with the input in that state already trips at its first tick
 * and makes no step. A probing segment that ends without a trip lets the
 * path go on. X4STEP_GET_PROBE reads the latch of the last probing
 * segment that started; it is cleared when one starts. Emergency stops,
 * limits, brake keys and the controller's close act as on any segment.
 */
#define X4STEP_SEG_PROBE_TOWARD (1u << 0) /* ABI 6: until the probe is active */
#define X4STEP_SEG_PROBE_AWAY (1u << 1) /* ABI 6: until it is inactive */

struct x4step_segment {
	__s32 steps[X4STEP_AXES]; /* |steps| <= 16777216, at least one non-zero */
	__u32 length; /* path units, 1..2^31 - 1 */
	__u32 v_max; /* path units/s, 1..2^31 - 1 */
	__u32 v_entry; /* the most the corner before it allows, units/s; 0: stop */
	__u32 accel; /* path units/s^2; v_max / accel <= 1800 s */
	__u64 tag; /* reported while it runs (e.g. a program line) */
	__u32 flags; /* ABI 6: one X4STEP_SEG_PROBE_* or none; else 0 */
	__u32 reserved; /* must be 0 */
};
/*
 * The leader's rate (v_max * leader steps / length) must fit the port's
 * step timing and write budget at 100 % (else ERANGE); its acceleration
 * (accel * leader / length) be 1..1000000 steps/s^2 (else EINVAL).
 */

#define X4STEP_PATH_DEPTH_MIN 256
#define X4STEP_PATH_DEPTH_MAX 4096
#define X4STEP_PATH_KEYS_ABORT (1u << 0) /* brake keys: hold, then abort */
#define X4STEP_PATH_PROBE_NC (1u << 1) /* ABI 6: the probe is active while LOW */

/*
 * X4STEP_SET_PATH_CONFIG: KEYS_ABORT any time; depth, the probe input and
 * PROBE_NC only while no path is active, unless they stay as they are
 * (EBUSY). EINVAL: unknown flags, probe above 5, reserved not 0.
 */
struct x4step_path_config {
	__u32 depth; /* segments the queue holds: a power of 2, 256..4096; 0 keeps it */
	__u32 flags; /* X4STEP_PATH_KEYS_ABORT, X4STEP_PATH_PROBE_NC */
	__u32 probe; /* ABI 6: the probe input 1..5 (X4GetIn bit 0..4), 0: none */
	__u32 reserved; /* 0 */
};

/*
 * HOLD: brake along the path to rest; segments queued but not started yet
 * stand HELD (a resume starts them). ESRCH: no segment queued.
 */
#define X4STEP_PATH_HOLD 1
#define X4STEP_PATH_RESUME 2 /* go on from a hold */
#define X4STEP_PATH_ABORT 3 /* hold, then flush the queue */
#define X4STEP_PATH_CLEAR 5 /* accept segments again after a flush */
/* value: feed override, 1..200 percent of every v_max (not of v_entry: corners stay) */
#define X4STEP_PATH_OVERRIDE 4

/* X4STEP_PATH_CTL */
struct x4step_path_ctl {
	__u32 cmd; /* X4STEP_PATH_* */
	__u32 value; /* OVERRIDE's percent, else 0 */
	__u32 reserved[2]; /* 0 */
};

#define X4STEP_PATH_IDLE 0
#define X4STEP_PATH_RUN 1
#define X4STEP_PATH_HOLDING 2
#define X4STEP_PATH_HELD 3

/* X4STEP_GET_PATH: readable on any descriptor. */
struct x4step_path_status {
	__u32 state; /* X4STEP_PATH_IDLE .. HELD */
	__u32 queued; /* segments queued, the running one included */
	__u32 depth;
	__u32 override; /* percent */
	__u32 speed; /* path units/s now */
	__u32 flags; /* as configured */
	__u64 tag; /* of the running (or next) segment, 0: none */
	__u64 done; /* segments completed on this port since it appeared */
	__u64 starved; /* refills that came after the path began to stop */
	__u32 reserved[4];
};

#define X4STEP_PROBE_TRIPPED (1u << 0) /* the input reached the awaited state */

/* X4STEP_GET_PROBE (ABI 6): readable on any descriptor. */
struct x4step_probe {
	__u32 flags; /* X4STEP_PROBE_TRIPPED */
	__u32 input; /* the probe input configured now, 0: none */
	__u64 tag; /* the last probing segment's that started; 0: none yet */
	__s32 position[X4STEP_AXES]; /* every axis' coordinate at the trip, else 0 */
	__u64 runs; /* probing segments started on this port since it appeared */
	__u64 trips; /* ... and tripped */
	__u32 reserved[4];
};

#define X4STEP_SET_PATH_CONFIG _IOW(X4STEP_IOC_MAGIC, 0x1a, struct x4step_path_config)
#define X4STEP_GET_PATH_CONFIG _IOR(X4STEP_IOC_MAGIC, 0x1b, struct x4step_path_config)
#define X4STEP_PATH_CTL _IOW(X4STEP_IOC_MAGIC, 0x1c, struct x4step_path_ctl)
#define X4STEP_GET_PATH _IOR(X4STEP_IOC_MAGIC, 0x1d, struct x4step_path_status)
#define X4STEP_GET_PROBE _IOR(X4STEP_IOC_MAGIC, 0x1e, struct x4step_probe)

#endif /* _UAPI_LINUX_X4STEP_H */
