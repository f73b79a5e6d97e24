/* SPDX-License-Identifier: GPL-2.0 */
/* x4step: the brake keys' input handler (x4step_keys.c). */
#ifndef X4STEP_KEYS_H
#define X4STEP_KEYS_H

int x4step_keys_init(void);
void x4step_keys_exit(void);

#endif /* X4STEP_KEYS_H */
