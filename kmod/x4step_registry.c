// SPDX-License-Identifier: GPL-2.0
/*
 * x4step: the ports served, by parport number. The parport client
 * (x4step_main.c) adds a port once its device exists and removes it before
 * the port goes; the brake keys' input handler (x4step_keys.c) reads the
 * table under RCU, in the input event's context.
 */
#include <linux/rcupdate.h>

#include "x4step_motion.h"
#include "x4step_registry.h"

/* Read by the input handler under RCU. */
static struct x4_port __rcu *x4_ports[X4_MAX_PORTS];

/* Serve `x4` as parport `number` (0..X4_MAX_PORTS - 1). */
void x4step_registry_add(struct x4_port *x4, int number)
{
	rcu_assign_pointer(x4_ports[number], x4);
}

/*
 * Serve parport `number` no more; returns its port, or NULL if it had
 * none. Once this returns, the input handler no longer sees it.
 */
struct x4_port *x4step_registry_remove(int number)
{
	struct x4_port *x4;

	if (number < 0 || number >= X4_MAX_PORTS)
		return NULL;
	x4 = rcu_dereference_protected(x4_ports[number], true);
	if (!x4)
		return NULL;
	RCU_INIT_POINTER(x4_ports[number], NULL);
	synchronize_rcu();
	return x4;
}

/* A key event on any keyboard: true if it braked a move and is swallowed. */
bool x4step_registry_brake_key(u32 code)
{
	struct x4_port *x4;
	bool swallow = false;
	int i;

	rcu_read_lock();
	for (i = 0; i < X4_MAX_PORTS; i++) {
		x4 = rcu_dereference(x4_ports[i]);
		if (x4 && x4step_motion_brake_key(x4, code))
			swallow |= READ_ONCE(x4->cfg_flags) &
				   X4STEP_CFG_KEYS_SWALLOW;
	}
	rcu_read_unlock();
	return swallow;
}
