// SPDX-License-Identifier: GPL-2.0
// The manual's API from C: with no /dev/x4step3, X4Init(4) says the port
// is not there, and X4Start before a successful X4Init says so too.
#include <stdio.h>
#include <x4step.h>

int main(void)
{
	int init = X4Init(4), start = X4Start();

	printf("X4Init(4) = %d, X4Start() = %d\n", init, start);
	return init == X4ErrLPTNotFound && start == X4ErrInitNotDone ? 0 : 1;
}
