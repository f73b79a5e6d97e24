/* SPDX-License-Identifier: GPL-2.0 */
/*
 * x4step: the ports served, by parport number (x4step_registry.c): the
 * parport client adds and removes them, the brake keys reach them all.
 */
#ifndef X4STEP_REGISTRY_H
#define X4STEP_REGISTRY_H

#include "x4step_dev.h"

void x4step_registry_add(struct x4_port *x4, int number);
struct x4_port *x4step_registry_remove(int number);
bool x4step_registry_brake_key(u32 code);

#endif /* X4STEP_REGISTRY_H */
