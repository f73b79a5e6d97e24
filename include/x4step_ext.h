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

#define X4MODE_CLOCK_DIR 0       /**< step and direction signals */
#define X4MODE_SMC_PHASE 1       /**< SMC1500 half-step phases, motors off at rest */
#define X4MODE_SMC_PHASE_HOLD 2  /**< the same, reduced holding current at rest */

/** Choose how the open port drives its motors (X4MODE_*).
 *  @return X4NoErr, X4ErrInitNotDone, X4ErrParamFail, X4ErrIsActive */
int X4SetOutputMode(int mode);

#ifdef __cplusplus
}
#endif

#endif /* X4STEP_EXT_H */
