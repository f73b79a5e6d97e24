/* SPDX-License-Identifier: GPL-2.0 WITH Linux-syscall-note */
/*
 * x4step: user-space interface of the x4step kernel module.
 *
 * One char device /dev/x4stepN per parallel port parportN. One process at
 * a time opens it read-write and controls the motors; any number may open
 * it read-only to watch (status, poll). Structures hold fixed-width fields
 * only, are padded to 64 bits, and their reserved fields must be zero, so
 * 32-bit programs use the same layout and later versions can extend them.
 *
 * Errors: every ioctl returns 0 or -1 with errno set.
 *   EINVAL  a parameter is out of range; for X4STEP_LOAD and
 *           X4STEP_MOVE_ENDLESS the X4Step error code (1..13, as in
 *           x4step.h) is written back into `result`
 *   EBUSY   a move is running (X4ErrIsActive)
 *   EEXIST  a move is loaded already (X4ErrIsLoaded)
 *   ENODATA no move is loaded (X4ErrNotLoaded)
 *   ESRCH   no move is running (X4ErrNotActive)
 *   EBADF   a state-changing ioctl on a read-only descriptor
 *   ENODEV  the parallel port went away
 *   ENOTTY  unknown ioctl
 */
#ifndef _UAPI_LINUX_X4STEP_H
#define _UAPI_LINUX_X4STEP_H

#include <linux/ioctl.h>
#include <linux/types.h>

#define X4STEP_ABI_VERSION 1
#define X4STEP_AXES 4
#define X4STEP_MAX_BRAKE_CODES 20

/* X4STEP_GET_INFO */
struct x4step_info {
	__u32 abi_version; /* X4STEP_ABI_VERSION */
	__u32 axes; /* X4STEP_AXES */
	__u32 port; /* N of parportN */
	__u32 reserved[5];
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
#define X4STEP_ST_CONTROLLED (1u << 2) /* a controller has the device open */

/* Output pins in x4step_status.outputs and x4step_output.signal. */
#define X4STEP_OUT_SIGNAL1 (1u << 0) /* pin 1 */
#define X4STEP_OUT_SIGNAL2 (1u << 1) /* pin 14 */
#define X4STEP_OUT_BOOST (1u << 2) /* pin 16, driven by the engine */
#define X4STEP_OUT_AKTIV (1u << 3) /* pin 17, driven by the engine */

/* X4STEP_GET_STATUS: readable on any descriptor, never blocks. */
struct x4step_status {
	__u32 flags; /* X4STEP_ST_* */
	__u32 last_brake_code; /* key code that braked the last move, or 0 */
	/* X4GetIn: bit0 pin15, bit1 pin13, bit2 pin12, bit3 pin10, bit4 pin11 */
	__u32 inputs; /* 1 = HIGH */
	__u32 outputs; /* X4STEP_OUT_* levels (1 = HIGH) */
	__s64 steps[X4STEP_AXES]; /* signed steps since the last start */
	__u64 moves_ended; /* counts moves that came to an end */
	__u32 data; /* data register pin levels (pins 2..9) */
	__u32 reserved0;
	__u64 brake_time_ns; /* CLOCK_MONOTONIC of the last brake request */
	__u32 reserved[2];
};

/* X4STEP_SET_OUTPUT: X4SetOut. */
struct x4step_output {
	__u32 signal; /* X4STEP_OUT_SIGNAL1 or X4STEP_OUT_SIGNAL2 */
	__u32 level; /* 0 or 1 */
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

/* X4STEP_SET_CONFIG / X4STEP_GET_CONFIG: per-port wiring. */
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
 * X4STEP_GET_TIMING: how late the step timer fired (hrtimer expiry to the
 * callback) since the last read, which resets it. hist[i] counts
 * lateness in [i, i + 1) * X4STEP_TIMING_BUCKET_NS; later ones in
 * `beyond`.
 */
#define X4STEP_TIMING_BUCKETS 512
#define X4STEP_TIMING_BUCKET_NS 64
struct x4step_timing {
	__u64 events;
	__u64 late_max_ns;
	__u64 beyond;
	__u64 reserved;
	__u32 hist[X4STEP_TIMING_BUCKETS];
};

#define X4STEP_IOC_MAGIC 0xB4

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
/* Set output signal 1 or 2. */
#define X4STEP_SET_OUTPUT _IOW(X4STEP_IOC_MAGIC, 0x07, struct x4step_output)
/* Set the brake keys. */
#define X4STEP_SET_BRAKE_CODES _IOW(X4STEP_IOC_MAGIC, 0x08, struct x4step_brake_codes)
/* Set and read the wiring configuration (only while no move runs). */
#define X4STEP_SET_CONFIG _IOW(X4STEP_IOC_MAGIC, 0x09, struct x4step_config)
#define X4STEP_GET_CONFIG _IOR(X4STEP_IOC_MAGIC, 0x0a, struct x4step_config)
/* Set and read the step timing (only while no move runs). */
#define X4STEP_SET_STEP_TIMING _IOW(X4STEP_IOC_MAGIC, 0x0c, struct x4step_step_timing)
#define X4STEP_GET_STEP_TIMING _IOR(X4STEP_IOC_MAGIC, 0x0d, struct x4step_step_timing)
/* Read and reset the timer lateness statistics. */
#define X4STEP_GET_TIMING _IOR(X4STEP_IOC_MAGIC, 0x0b, struct x4step_timing)

#endif /* _UAPI_LINUX_X4STEP_H */
