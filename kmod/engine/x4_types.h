/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step engine: the fixed-width types and the 64-bit division of the
 * kernel, also in user space. The engine is plain C with no floating
 * point and no allocation, compiled into the module, libx4step and the
 * host tests.
 */
#ifndef X4_TYPES_H
#define X4_TYPES_H

#ifdef __KERNEL__
#include <asm/barrier.h>
#include <linux/compiler.h>
#include <linux/math64.h>
#include <linux/types.h>
/*
 * The path queue (x4_path.c): a writer without the lock, the timer under
 * it. A release store publishes what was written before it (a slot, an
 * entry speed) to the acquire load that reads the value it stored.
 */
#define x4_load_acquire(p) smp_load_acquire(p)
/* Pairs with x4_load_acquire(). */
#define x4_store_release(p, v) smp_store_release(p, v)
/* A value another context writes (or reads) without the lock, unordered. */
#define x4_read_once(x) READ_ONCE(x)
#define x4_write_once(x, v) WRITE_ONCE(x, v)
/* 32-bit kernels have no 64-bit '/': every u64 division goes through here. */
#define x4_div(a, b) div64_u64((a), (b))
#else
#include <stdbool.h>
#include <stdint.h>
typedef uint8_t u8;
typedef int8_t s8;
typedef uint16_t u16;
typedef uint32_t u32;
typedef int32_t s32;
typedef uint64_t u64;
typedef int64_t s64;
#ifdef X4_DIV_EXTERN
/*
 * The 32-bit link check (tests/check-style.sh): x4_div out of line, so
 * that a raw u64 '/' left in the engine shows as __udivdi3.
 */
u64 x4_div64_u64(u64 a, u64 b);
#define x4_div(a, b) x4_div64_u64((a), (b))
#else
#define x4_div(a, b) ((u64)(a) / (u64)(b))
#endif
#define x4_load_acquire(p) __atomic_load_n((p), __ATOMIC_ACQUIRE)
#define x4_store_release(p, v) __atomic_store_n((p), (v), __ATOMIC_RELEASE)
#define x4_read_once(x) __atomic_load_n(&(x), __ATOMIC_RELAXED)
#define x4_write_once(x, v) __atomic_store_n(&(x), (v), __ATOMIC_RELAXED)
#endif

#define X4_NSEC_PER_SEC 1000000000ull

#endif /* X4_TYPES_H */
