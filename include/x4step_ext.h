/* SPDX-License-Identifier: LGPL-2.1-or-later */
/**
 * @file x4step_ext.h
 * @brief Extensions to the X4Step C API: what the 1995 library could not
 *        configure. The documented X4 functions (x4step.h) stay as they are.
 */
#ifndef X4STEP_EXT_H
#define X4STEP_EXT_H

#include "x4step.h"

#ifdef __cplusplus
extern "C" {
#endif
#pragma GCC visibility push(default)

/**
 * Step signal timing of the open port, in nanoseconds, each 0..1000000:
 * clock pulse length (0: symmetric clock, the X4Step behaviour; else at
 * least 1000), minimum clock low time, direction setup before the first
 * step (X4Step: 100000) and direction hold after the last. Later moves
 * whose frequency cannot fit pulse + space are refused with
 * X4ErrFreqTooHigh.
 * @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive
 */
int X4SetStepTiming(long pulse_ns, long space_ns, long dir_setup_ns, long dir_hold_ns);

#define X4MODE_CLOCK_DIR 0      /**< step and direction signals */
#define X4MODE_SMC_PHASE 1      /**< SMC1500 half-step phases, motors off at rest */
#define X4MODE_SMC_PHASE_HOLD 2 /**< the same, reduced holding current at rest */

/** Choose how the open port drives its motors (X4MODE_*).
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive */
int X4SetOutputMode(int mode);

/*
 * Positioning (the ProStep4 model). Each axis (1..4) keeps a signed
 * 32-bit machine coordinate, updated by every step of every kind of move,
 * X4Load/X4Start moves included, and can move on its own to a coordinate
 * with its own ramp while other axes move. An X4Load/X4Start move needs
 * all its axes idle. Every function checks, in this order: X4Init
 * (X4ErrInitNotDone), its arguments (X4ErrParamFail), the state
 * (X4ErrIsActive: the axis moves; X4ErrNotActive: it does not).
 */

/* Phases of X4Home. */
#define X4HOME_PHASE1 1 /**< at vref1 until the reference switch becomes active */
#define X4HOME_PHASE2 2 /**< at vref2 until it changes again; then zero and synchronize */
#define X4HOME_AUTO (X4HOME_PHASE1 | X4HOME_PHASE2) /**< both, one after the other */
#define X4HOME_BRAKE 4 /**< with PHASE1: brake past the switch along the axis' ae */

/* State bits of X4GetAxisState (ProStep4's status register). */
#define X4AX_RUN 0x001    /**< the axis moves */
#define X4AX_SYNC 0x002   /**< the coordinate is referenced (X4Home, X4SetPosition) */
#define X4AX_ERROR 0x004  /**< an error bit is set */
#define X4AX_REF1 0x008   /**< reference run, phase 1 */
#define X4AX_REF2 0x010   /**< reference run, phase 2 */
#define X4AX_ACCEL 0x100  /**< accelerating */
#define X4AX_CRUISE 0x200 /**< at constant speed */
#define X4AX_DECEL 0x400  /**< decelerating */

/* Error bits of X4GetAxisState, cleared by the axis' next move. */
#define X4AXERR_REF_TRAVEL 1  /**< a reference phase went beyond sref */
#define X4AXERR_LIMIT_POS 2   /**< stopped at limit switch E+ */
#define X4AXERR_LIMIT_NEG 4   /**< stopped at limit switch E- */
#define X4AXERR_AMBIGUOUS 8   /**< the input serves other limits too */
#define X4AXERR_REF_PASSED 16 /**< phase 1's brake ran off the reference switch */

/**
 * Ramp of the axis' own moves (X4MoveTo, X4MoveBy): start at v0, speed up
 * with a0 to vm, slow down with ae to ve and stop there; a0 or ae 0: no
 * ramp on that side. Velocities in steps/s, accelerations in steps/s^2:
 * 1 <= vm <= 100000, v0 <= vm, ve <= vm, a0, ae <= 1000000, and vm / a0,
 * vm / ae (when not 0) at most 3600 s. Default: v0 = ve = 0, vm = 1000,
 * a0 = ae = 1000.
 * @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive
 */
int X4SetProfile(int axis, long v0, long ve, long vm, long a0, long ae);

/** Move axis on its own to the coordinate target (-2^31..2^31-1) with its
 *  profile; returns once it runs (X4GetAxisState tells when it ends).
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive */
int X4MoveTo(int axis, long target);

/** The same, by distance steps from where the axis is.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive */
int X4MoveBy(int axis, long distance);

/**
 * Reference run of axis (ProStep4 section 3), without ramps: phase 1 at
 * vref1 steps/s until the reference switch becomes active, where it stops
 * (with X4HOME_BRAKE it brakes past it along the axis' profile
 * deceleration ae, X4SetProfile, vref1 / ae at most 3600 s; the switch
 * must stay active over that distance, else X4AXERR_REF_PASSED), phase 2
 * 50 ms later from rest at vref2 until the switch changes again, then the
 * coordinate is 0 and the axis synchronized. Speeds are signed (the sign is the direction),
 * 1..100000 steps/s; each phase travels at most sref (1..2^31-1) steps,
 * else the axis stops with X4AXERR_REF_TRAVEL. phases: X4HOME_PHASE1,
 * X4HOME_PHASE2 or X4HOME_AUTO, with X4HOME_BRAKE or not. Needs the axis' reference input
 * (X4SetSwitches). X4BrakeAxis and X4StopAxis end it.
 * @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive
 */
int X4Home(int axis, long vref1, long vref2, long sref, int phases);

/** "Stop and zero": stop axis at once (with the axes moving interpolated
 *  with it), set its coordinate to position and mark it synchronized.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail */
int X4SetPosition(int axis, long position);

/** The machine coordinate of axis into *position.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail (axis, NULL) */
int X4GetPosition(int axis, long *position);

/** The X4AX_* state bits and X4AXERR_* error bits of axis; either pointer
 *  may be NULL.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail */
int X4GetAxisState(int axis, int *state, int *error);

/**
 * Inputs 1..5 (X4GetIn bits 0..4; 0 = none) as the reference switch and
 * the limit switches E+ and E- of axis. An input may serve several axes
 * and both directions (switches in parallel). An axis moving toward an
 * active limit is stopped by the module on that very step, with the axes
 * moving interpolated with it; moving away from it is allowed. Only while
 * no move runs.
 * @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive
 */
int X4SetSwitches(int axis, int ref_input, int plus_input, int minus_input);

/** Which inputs have normally closed switches: bit k for input k+1
 *  (0..31). Normally open switches are active while their pin is HIGH,
 *  normally closed ones while it is LOW. Only while no move runs.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive */
int X4SetSwitchPolarity(int nc_mask);

/** Brake the move of axis along its ramp (X4Brake for one axis; the axes
 *  moving interpolated with it brake too).
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrNotActive */
int X4BrakeAxis(int axis);

/** Stop the move of axis at once (X4Stop for one axis): the axis loses
 *  its synchronization.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrNotActive */
int X4StopAxis(int axis);

/*
 * Continuous paths (module interface 5; x4step_path.hpp has the details):
 * straight segments that run back to back, at path speeds planned ahead
 * in the kernel, so that the motors always stop on the path. A path owns
 * every axis while it runs or holds: X4Start and X4MoveTo fail with
 * X4ErrIsActive then. X4Brake holds a path, X4Stop stops it and flushes.
 */
typedef struct X4Segment {
  long steps[4];             /**< signed steps of axes 1..4, |steps| <= 16777216 */
  unsigned long length;      /**< its length along the path, in your unit, >= 1 */
  unsigned long top_speed;   /**< units/s */
  unsigned long entry_speed; /**< the most the corner before it allows, units/s */
  unsigned long accel;       /**< units/s^2; top_speed / accel at most 1800 s */
  unsigned long long tag;    /**< yours: X4PathState reports the running one's */
} X4Segment;

#define X4PATH_IDLE 0    /**< nothing runs, nothing queued */
#define X4PATH_RUN 1     /**< running */
#define X4PATH_HOLDING 2 /**< braking along the path to rest */
#define X4PATH_HELD 3    /**< at rest on the path: X4PathResume or X4PathAbort */

/** Queue count segments in order, waiting while the queue is full. A bad
 *  segment stops there: the ones before it are queued.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrNoSteps,
 *  X4ErrStepsTooHigh, X4ErrFreqTooHigh (faster than the port can step),
 *  X4ErrIsActive (another move runs), X4ErrNotActive (the path was
 *  flushed: X4PathClear first; or it is held and the queue is full:
 *  X4PathResume first) */
int X4PathAppend(const X4Segment *segments, int count);
/** Brake the path along it to rest. @return X4NoErr, X4ErrInitNotDone, X4ErrNotActive */
int X4PathHold(void);
/** Go on from a hold. @return X4NoErr, X4ErrInitNotDone, X4ErrNotActive */
int X4PathResume(void);
/** Hold, then flush the queue. @return X4NoErr, X4ErrInitNotDone, X4ErrNotActive */
int X4PathAbort(void);
/** After a flush (a stop, a limit, an abort, a brake key that aborts),
 *  X4PathAppend returns X4ErrNotActive until this. @return X4NoErr, X4ErrInitNotDone */
int X4PathClear(void);
/** Feed override, 1..200 percent of every top speed.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail */
int X4PathOverride(int percent);
/** The path's state (X4PATH_*), segments queued (the running one
 *  included), and the running segment's tag; any pointer may be NULL.
 *  @return X4NoErr, X4ErrInitNotDone */
int X4PathState(int *state, long *queued, unsigned long long *tag);

/*
 * Probing (module interface 6; G38.2..G38.5): a probing segment watches
 * the path's probe input on every step tick. Where the input first is in
 * the state it waits for, every axis' position is latched (X4PathProbe),
 * and the path brakes along it and is flushed (X4PathClear before more);
 * a probing segment that ends without that lets the path go on.
 */
#define X4PROBE_TOWARD 1 /**< until the probe input becomes active (G38.2, G38.3) */
#define X4PROBE_AWAY 2   /**< until it becomes inactive (G38.4, G38.5) */
/** The probe input: 1..5 (X4GetIn bit 0..4), 0: none; active_low non-zero
 *  for a normally closed probe. Only while no path is active.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive */
int X4PathProbeInput(int input, int active_low);
/** Queue one probing segment (mode X4PROBE_TOWARD or X4PROBE_AWAY), as
 *  X4PathAppend queues one. X4ErrParamFail also without a probe input.
 *  @return as X4PathAppend */
int X4PathAppendProbe(const X4Segment *segment, int mode);
/** The latch of the last probing segment that ran (cleared when one
 *  starts): whether it tripped, every axis' position then (position[4],
 *  0 without a trip) and its tag; any pointer may be NULL.
 *  @return X4NoErr, X4ErrInitNotDone */
int X4PathProbe(int *tripped, long *position, unsigned long long *tag);

#pragma GCC visibility pop
#ifdef __cplusplus
}
#endif

#endif /* X4STEP_EXT_H */
