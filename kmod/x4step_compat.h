/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: the kernel API differences between the kernels it is built for
 * (6.1 to 6.12+), in one place. checkpatch's advice against version
 * checks is for in-tree code; this file is checked without it.
 */
#ifndef X4STEP_COMPAT_H
#define X4STEP_COMPAT_H

#include <linux/device.h>
#include <linux/hrtimer.h>
#include <linux/version.h>

/* class_create() lost its owner argument in 6.4. */
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 4, 0)
#define x4_class_create(name) class_create(name)
#else
#define x4_class_create(name) class_create(THIS_MODULE, name)
#endif

/* struct class's devnode() takes a const device since 6.2. */
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 2, 0)
#define X4_DEVNODE_CONST const
#else
#define X4_DEVNODE_CONST
#endif

/* parport drivers are all device-model drivers since 6.7. */
#if LINUX_VERSION_CODE < KERNEL_VERSION(6, 7, 0)
#define X4_PARPORT_DEVMODEL .devmodel = true,
#else
#define X4_PARPORT_DEVMODEL
#endif

/* hrtimer_setup() replaces hrtimer_init() from 6.13. */
static inline void x4_hrtimer_setup(struct hrtimer *timer,
				    enum hrtimer_restart (*fn)(struct hrtimer *),
				    clockid_t clock, enum hrtimer_mode mode)
{
#if LINUX_VERSION_CODE >= KERNEL_VERSION(6, 13, 0)
	hrtimer_setup(timer, fn, clock, mode);
#else
	hrtimer_init(timer, clock, mode);
	timer->function = fn;
#endif
}

#endif /* X4STEP_COMPAT_H */
