/* SPDX-License-Identifier: LGPL-2.1-or-later */
/**
 * @file x4step.h
 * @brief The X4Step C API (X4Step 1.0 manual, chapter 4) on Linux.
 *
 * Names, signatures, constants and behaviour as documented in the manual;
 * usable from C and C++. One port at a time, as in the manual; for several
 * ports use the C++ API (x4step.hpp). Link with -lx4step
 * (pkg-config x4step). Not thread-safe, like the original.
 *
 * One move at a time, as in the DOS library: X4Start, X4MovePos and
 * X4MoveNeg are X4ErrIsActive while any axis runs. (Independent
 * concurrent moves are the positioning extension's, x4step_ext.h.)
 *
 * Where the manual lists no code for a case, these are the answers:
 * - before X4Init, every function with a result: X4ErrInitNotDone;
 * - a negative ramp, more than 20 brake codes: X4ErrParamFail ("a
 *   parameter is not in its valid range", manual 4.1), nothing changed;
 * - a frequency within 10..20000 Hz that the port's configured step
 *   timing (x4step_ext.h) cannot run: X4ErrFreqTooHigh, checked after the
 *   paths (X4ErrStepsTooHigh, X4ErrNoSteps come first), as the port's state;
 * - a failure the manual has no code for: errno holds it, and the result
 *   is X4ErrLPTNotFound where the port cannot be used (EACCES, EPERM,
 *   EIO, ENODEV, ENXIO, EBADF, ENOTTY), else X4ErrParamFail.
 */
#ifndef X4STEP_H
#define X4STEP_H

#ifdef __cplusplus
extern "C" {
#endif
/* The library builds with hidden symbols: what is declared here is its API. */
#pragma GCC visibility push(default)

/* Error codes (manual 4.1). */
#define X4NoErr 0            /**< no error */
#define X4ErrNoErr X4NoErr   /**< the manual's other spelling */
#define X4ErrNoSteps 1       /**< every path is 0 */
#define X4ErrFreqTooHigh 2   /**< frequency above 20000 Hz */
#define X4ErrFreqTooLow 3    /**< frequency below 10 Hz */
#define X4ErrRampTooHigh 4   /**< ramp above 1000 ms */
#define X4ErrRampFreq 5      /**< ramp in ms greater than frequency in Hz */
#define X4ErrLPTNotFound 6   /**< port missing (or held by another program) */
#define X4ErrNotActive 7     /**< no axis runs */
#define X4ErrParamFail 8     /**< parameter out of range */
#define X4ErrInitNotDone 9   /**< X4Init was not called */
#define X4ErrIsActive 10     /**< axes are running */
#define X4ErrNotLoaded 11    /**< nothing loaded to start */
#define X4ErrIsLoaded 12     /**< already loaded; load again after X4Start */
#define X4ErrStepsTooHigh 13 /**< a path beyond 16777216 steps */

/* X4SetOut signals. */
#define SIGNAL1ON 1  /**< pin 1 HIGH */
#define SIGNAL1OFF 2 /**< pin 1 LOW */
#define SIGNAL2ON 3  /**< pin 14 HIGH */
#define SIGNAL2OFF 4 /**< pin 14 LOW */

/* X4Init ports: LPTn is /dev/x4step(n-1), the kernel's parport(n-1). */
#define LPT1 1
#define LPT2 2
#define LPT3 3
#define LPT4 4

/**
 * Open port lpt (LPT1..LPT4) and clear the 1 ms timer. If a port is open
 * already it is released first, as by X4ReInit. The port starts from the
 * DOS library's state, whatever an earlier program (x4ctl, the C++ API)
 * configured: clock and direction outputs without inversions, the
 * module's default step timing, only ESC brakes, no limit or reference
 * switches, the default profiles.
 * @return X4NoErr, X4ErrParamFail (lpt not 1..4), X4ErrLPTNotFound (no
 *         /dev/x4stepN, or the port is taken: another program controls
 *         it, the module still brakes the motors of a program that ended
 *         while they ran, or another parport driver (lp; ppdev for a
 *         program using /dev/parportN) has claimed it. The holder's name
 *         is in /proc/sys/dev/parport/parport(lpt-1)/devices/active; the
 *         C++ API's exception says it; or the user may not open it:
 *         not in group lp, errno EACCES.) The first X4ErrLPTNotFound
 *         of a program writes one line on stderr ("libx4step:
 *         X4Init(LPT1): ...") that says what to fix: load the module,
 *         join group lp, free the port, or the simulator setting it
 *         refused.
 */
int X4Init(int lpt);

/** Release the port; running motors brake along their ramp first, and
 *  this returns when they stand, however long the brake takes.
 *  @return X4NoErr, X4ErrInitNotDone */
int X4ReInit(void);

/**
 * Load paths (steps, -16777216..16777216, at least one non-zero) for axes
 * 1..4: the longest runs at freq (10..20000 Hz) with ramp (0..1000 ms,
 * ramp <= freq) ramps, the others interpolated. May be called while a
 * move runs (preload). Checks in this order: X4ErrInitNotDone,
 * X4ErrFreqTooHigh, X4ErrFreqTooLow, X4ErrRampTooHigh, X4ErrRampFreq,
 * X4ErrStepsTooHigh, X4ErrNoSteps, X4ErrIsLoaded.
 */
int X4Load(long w1, long w2, long w3, long w4, int freq, int ramp);

/** Start the loaded move; clears the step counters.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrNotLoaded, X4ErrIsActive (any
 *          axis runs) */
int X4Start(void);

/** Brake the running move along its ramp.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrNotActive */
int X4Brake(void);

/** Emergency stop, no ramp: reference the machine afterwards.
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrNotActive */
int X4Stop(void);

/** @return 0 when all axes stand (or no port is open), >0 while running. */
int X4GetState(void);

/** @return steps of axis (1..4) since the last start, signed like the
 *          path; 0 for other axes or before X4Init. */
long X4GetSteps(int axis);

/**
 * Move axis (1..4) endlessly in positive / negative direction until
 * X4Brake, X4Stop or a brake key.
 * @return in this order of checks: X4ErrInitNotDone, X4ErrParamFail
 *         (axis), X4ErrFreqTooHigh, X4ErrFreqTooLow, X4ErrRampTooHigh,
 *         X4ErrRampFreq, X4ErrIsLoaded, X4ErrIsActive (any axis runs);
 *         else X4NoErr
 */
int X4MovePos(int axis, int freq, int ramp);
int X4MoveNeg(int axis, int freq, int ramp);

/**
 * Keys that brake a running move: up to 20 PC/AT set-1 codes, 0-terminated
 * (make code = press, make code + 128 = release). ESC (1) always brakes.
 * @return X4NoErr; X4ErrInitNotDone, X4ErrParamFail (NULL, more than 20)
 */
int X4BrakeCodes(char *codes);

/** @return the key code that braked the last move, 0 if none did. */
int X4LastBrakeCode(void);

/** Restart the 1 ms timer. */
void X4ClearTimer(void);

/** @return milliseconds since X4Init or X4ClearTimer (CLOCK_MONOTONIC). */
long X4GetTimer(void);

/** @return levels of the 5 inputs, 1 = HIGH: bit0 pin 15, bit1 pin 13,
 *          bit2 pin 12, bit3 pin 10, bit4 pin 11; 0 before X4Init. */
int X4GetIn(void);

/** Switch pin 1 or 14: SIGNAL1ON, SIGNAL1OFF, SIGNAL2ON, SIGNAL2OFF.
 *  @return X4NoErr; X4ErrInitNotDone, X4ErrParamFail (other values) */
int X4SetOut(int sig);

#pragma GCC visibility pop
#ifdef __cplusplus
}
#endif

#endif /* X4STEP_H */
