/* SPDX-License-Identifier: GPL-2.0 OR LGPL-2.1-or-later */
/*
 * x4step: the brake keys' codes, once for the module's input handler
 * (kmod/x4step_keys.c) and libx4step's simulated keys (lib/sim). Codes are
 * the PC/AT scan code set 1 of the X4Step manual: make code c (1..127)
 * for a press, c + 128 for the release. Linux key codes 1..88 are set-1
 * make codes already; an extended key gets the code its MF2 keyboard
 * sends after the E0 prefix.
 */
#ifndef X4_KEYS_H
#define X4_KEYS_H

#include <linux/input-event-codes.h>

#include "x4_types.h"

struct x4_key {
	const char *name; /* the simulator's name for it, or NULL */
	u16 key; /* the Linux key code */
	u8 code; /* its set-1 make code */
};

/*
 * The keys with a name, and every key beyond 88 that has a set-1 code; a
 * key code 0 ends the table.
 */
static const struct x4_key x4_keys[] = {
	{ "esc", KEY_ESC, 1 },
	{ "backspace", KEY_BACKSPACE, 14 },
	{ "tab", KEY_TAB, 15 },
	{ "enter", KEY_ENTER, 28 },
	{ "space", KEY_SPACE, 57 },
	{ NULL, KEY_KPENTER, 28 },
	{ NULL, KEY_RIGHTCTRL, 29 },
	{ NULL, KEY_KPSLASH, 53 },
	{ NULL, KEY_SYSRQ, 55 },
	{ NULL, KEY_RIGHTALT, 56 },
	{ NULL, KEY_PAUSE, 69 },
	{ "home", KEY_HOME, 71 },
	{ "up", KEY_UP, 72 },
	{ "pgup", KEY_PAGEUP, 73 },
	{ "left", KEY_LEFT, 75 },
	{ "right", KEY_RIGHT, 77 },
	{ "end", KEY_END, 79 },
	{ "down", KEY_DOWN, 80 },
	{ "pgdn", KEY_PAGEDOWN, 81 },
	{ "insert", KEY_INSERT, 82 },
	{ "delete", KEY_DELETE, 83 },
	{ NULL, KEY_LEFTMETA, 91 },
	{ NULL, KEY_RIGHTMETA, 92 },
	{ NULL, KEY_COMPOSE, 93 },
	{ NULL, 0, 0 },
};

/* The set-1 make code of Linux key code `key`; 0 if it has none. */
static inline u8 x4_key_code(unsigned int key)
{
	const struct x4_key *k;

	if (key >= 1 && key <= 88)
		return (u8)key;
	for (k = x4_keys; k->key; k++)
		if (k->key == key)
			return k->code;
	return 0;
}

#endif /* X4_KEYS_H */
