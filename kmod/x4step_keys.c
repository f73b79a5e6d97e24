// SPDX-License-Identifier: GPL-2.0
/*
 * x4step brake keys: an input handler on every keyboard that brakes a
 * running move when one of its brake codes arrives (X4BrakeCodes), in the
 * input event's own context, with no round trip through user space.
 *
 * Codes are the PC/AT scan code set 1 of the X4Step manual: make code c
 * (1..127) for a press, break code c + 128 for the release; the Linux key
 * codes are translated by engine/x4_keys.h, as for the simulated keys.
 *
 * With X4STEP_CFG_KEYS_SWALLOW, a brake key pressed while a move runs is
 * swallowed, and so are that key's auto-repeats and its release, even once
 * the move has ended. Any other press passes, and so does its release, even
 * if that release brakes (a break code): applications see a key's press and
 * release together or not at all, never a key stuck down. As sysrq does,
 * each keyboard's handle keeps a bitmap of the keys whose press it swallowed.
 *
 * The handler is a filter, ahead of evdev on every keyboard, but the input
 * core delivers a grabbed device's events to the grabbing handle only
 * (input_pass_values()): while a process holds a keyboard with EVIOCGRAB,
 * its keys, ESC too, never reach this handler and brake nothing.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/input.h>
#include <linux/slab.h>

#include "x4_keys.h"
#include "x4step_keys.h"
#include "x4step_registry.h"

#define X4_KEY_ESC 1

/* One per keyboard. */
struct x4_key_handle {
	struct input_handle handle;
	/* Keys whose press was swallowed; under the device's event_lock. */
	DECLARE_BITMAP(swallowed, KEY_CNT);
};

/*
 * Runs under the input device's event lock with interrupts off, which also
 * serialises the handle's bitmap: only the engine's raw spinlock is taken.
 * Returns true to swallow the event.
 */
static bool x4step_key_filter(struct input_handle *handle, unsigned int type,
			      unsigned int code, int value)
{
	struct x4_key_handle *kh =
		container_of(handle, struct x4_key_handle, handle);
	bool swallow;
	u8 make;

	if (type != EV_KEY)
		return false;
	make = x4_key_code(code); /* 0 for any code >= 128 */
	if (!make)
		return false;
	if (value == 2) /* auto-repeat is no new press: it goes with the press */
		return test_bit(code, kh->swallowed);
	if (value) {
		swallow = x4step_registry_brake_key(make);
		/* Assigned either way: a grab may have taken the last release. */
		__assign_bit(code, kh->swallowed, swallow);
		return swallow;
	}
	/* A release brakes on its own code but is swallowed with its press. */
	x4step_registry_brake_key(make + 128);
	return __test_and_clear_bit(code, kh->swallowed);
}

static int x4step_key_connect(struct input_handler *handler,
			      struct input_dev *dev,
			      const struct input_device_id *id)
{
	struct x4_key_handle *kh;
	struct input_handle *handle;
	int ret;

	kh = kzalloc(sizeof(*kh), GFP_KERNEL);
	if (!kh)
		return -ENOMEM;
	handle = &kh->handle;
	handle->dev = dev;
	handle->handler = handler;
	handle->name = KBUILD_MODNAME;

	ret = input_register_handle(handle);
	if (ret)
		goto err_free;
	ret = input_open_device(handle);
	if (ret)
		goto err_unregister;
	return 0;

err_unregister:
	input_unregister_handle(handle);
err_free:
	kfree(kh);
	return ret;
}

static void x4step_key_disconnect(struct input_handle *handle)
{
	input_close_device(handle);
	input_unregister_handle(handle);
	kfree(container_of(handle, struct x4_key_handle, handle));
}

static const struct input_device_id x4_key_ids[] = {
	{
		.flags = INPUT_DEVICE_ID_MATCH_EVBIT | INPUT_DEVICE_ID_MATCH_KEYBIT,
		.evbit = { BIT_MASK(EV_KEY) },
		.keybit = { [BIT_WORD(KEY_ESC)] = BIT_MASK(KEY_ESC) },
	}, /* keyboards: anything that has an ESC key */
	{ },
};

static struct input_handler x4_key_handler = {
	.filter = x4step_key_filter,
	.connect = x4step_key_connect,
	.disconnect = x4step_key_disconnect,
	.name = KBUILD_MODNAME,
	.id_table = x4_key_ids,
};

int x4step_keys_init(void)
{
	return input_register_handler(&x4_key_handler);
}

void x4step_keys_exit(void)
{
	input_unregister_handler(&x4_key_handler);
}
