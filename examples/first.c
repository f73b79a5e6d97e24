/* SPDX-License-Identifier: LGPL-2.1-or-later */
/*
 * The X4Step manual's first example ("interpolierte Fahrt aller Achsen"):
 * load a move of the four axes, start it, load the way back while it runs,
 * wait for the first move to end and start the second. Written out as a
 * whole program, with the results checked.
 *
 * Build it against the installed library (README.md here):
 *   cc -o first first.c $(pkg-config --cflags --libs x4step)
 *   cc -static -o first first.c $(pkg-config --static --cflags --libs x4step)
 * Run it on the module's /dev/x4step0 (LPT1), or on the simulated port:
 *   X4STEP_SIM=1 ./first
 */
#include <stdio.h>
#include <x4step.h>

/* Print what failed and its X4Step error code; the code, 0 if none. */
static int failed(const char *what, int err)
{
	if (err)
		fprintf(stderr, "first: %s: X4Step error %d\n", what, err);
	return err;
}

int main(void)
{
	int err = X4Init(LPT1);

	if (err) {
		failed("X4Init(LPT1)", err);
		fprintf(stderr, "first: no /dev/x4step0? load the module (modprobe x4step) and join group lp, or run with X4STEP_SIM=1\n");
		return 1;
	}
	if (failed("X4Load", X4Load(1000, 800, 600, 400, 1000, 50)) || /* load the axes */
	    failed("X4Start", X4Start()) || /* start */
	    failed("X4Load (preload)", X4Load(-1000, -800, -600, -400, 1000, 50))) { /* load the way back */
		X4ReInit();
		return 1;
	}
	while (X4GetState()) /* wait */
		;
	if (failed("X4Start (the way back)", X4Start())) { /* start */
		X4ReInit();
		return 1;
	}
	while (X4GetState())
		;
	printf("done: %ld %ld %ld %ld\n", X4GetSteps(1), X4GetSteps(2), X4GetSteps(3), X4GetSteps(4));
	return failed("X4ReInit", X4ReInit()) ? 1 : 0;
}
