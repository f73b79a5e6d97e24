// SPDX-License-Identifier: GPL-2.0
/*
 * A minimal x4step client for the x4vport guest test (static,
 * runs in the busybox initramfs).
 *
 *   x4vctl DEV inputs                  print X4GetIn as "inputs=0x..", read
 *                                      by a controller (the module reads
 *                                      the port only while it has claimed
 *                                      it for one)
 *   x4vctl DEV inputs-ro               the same through a read-only open:
 *                                      "inputs=0x.. err=0 stale=1" when no
 *                                      controller has the port
 *   x4vctl DEV move STEPS FREQ RAMP    axis 1 move, wait until it ends
 *   x4vctl DEV hold-endless FREQ SECS  endless move on axis 1, keep the
 *                                      device open SECS seconds (the test
 *                                      removes the port meanwhile), then
 *                                      try status, info, stop and poll
 *   x4vctl DEV close-braking VM AE     a goto of axis 1 at VM steps/s, then
 *                                      close while it runs: the module
 *                                      brakes at AE steps/s^2 (VM / AE
 *                                      seconds) after close() has returned
 */
#include <errno.h>
#include <fcntl.h>
#include <linux/x4step.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>

static int get_status(int fd, struct x4step_status *st)
{
	memset(st, 0, sizeof(*st));
	return ioctl(fd, X4STEP_GET_STATUS, st) ? errno : 0;
}

static int cmd_inputs(const char *dev, int mode)
{
	struct x4step_status st;
	int fd = open(dev, mode | O_CLOEXEC);
	int err;

	if (fd < 0) {
		perror(dev);
		return 1;
	}
	err = get_status(fd, &st);
	printf("inputs=0x%02x err=%d stale=%d\n", st.inputs, err,
	       !!(st.flags & X4STEP_ST_INPUTS_STALE));
	close(fd);
	return err ? 1 : 0;
}

static int cmd_move(int fd, int steps, int freq_hz, int ramp_ms)
{
	struct x4step_move m = { { steps, 0, 0, 0 }, freq_hz, ramp_ms, 0, -1 };
	struct pollfd p = { fd, POLLIN, 0 };
	struct x4step_status st;
	int err;

	if (ioctl(fd, X4STEP_LOAD, &m)) {
		printf("LOAD errno %d result %d\n", errno, m.result);
		return 1;
	}
	if (ioctl(fd, X4STEP_START)) {
		printf("START errno %d\n", errno);
		return 1;
	}
	while (poll(&p, 1, 30000) == 1 && !(p.revents & POLLIN))
		;
	err = get_status(fd, &st);
	printf("move done err=%d steps=%lld ended=%llu flags=0x%x\n", err,
	       (long long)st.steps[0], (unsigned long long)st.moves_ended,
	       st.flags);
	return err || st.steps[0] != steps;
}

static int cmd_hold_endless(int fd, int freq_hz, int secs)
{
	struct x4step_endless en = { 1, 1, freq_hz, 0, 0, -1, { 0, 0 } };
	struct pollfd p = { fd, POLLIN, 0 };
	struct x4step_status st;
	struct x4step_info info;
	int err;

	if (ioctl(fd, X4STEP_MOVE_ENDLESS, &en)) {
		printf("ENDLESS errno %d result %d\n", errno, en.result);
		return 1;
	}
	printf("RUNNING\n");
	fflush(stdout);
	sleep(secs);
	err = get_status(fd, &st);
	printf("after: GET_STATUS err=%d (%s)\n", err, strerror(err));
	memset(&info, 0, sizeof(info));
	err = ioctl(fd, X4STEP_GET_INFO, &info) ? errno : 0;
	printf("after: GET_INFO err=%d port=%u\n", err, info.port);
	err = ioctl(fd, X4STEP_STOP) ? errno : 0;
	printf("after: STOP err=%d (%s)\n", err, strerror(err));
	err = poll(&p, 1, 0);
	printf("after: poll=%d revents=0x%x\n", err, p.revents);
	return 0;
}

static int cmd_close_braking(int *fd, int vm, int ae)
{
	struct x4step_profile pr = { 1, 0, 0, vm, 100000, ae, { 0, 0 } };
	struct x4step_goto go = { 1, X4STEP_GOTO_RELATIVE, { 1000000, 0, 0, 0 },
				  -1, { 0, 0, 0 } };
	struct x4step_axes ax;
	struct timespec t0, t1;
	int n;

	if (ioctl(*fd, X4STEP_SET_PROFILE, &pr) || ioctl(*fd, X4STEP_GOTO, &go)) {
		printf("GOTO errno %d result %d\n", errno, go.result);
		return 1;
	}
	/*
	 * At speed (99 %: the speed is 1e9 / the step interval), seen from the
	 * axis, not after a fixed sleep: without -icount a loaded host lets the
	 * guest do less in its time. Then the brake lasts VM / AE seconds.
	 */
	for (n = 0; n < 5000; n++) {
		memset(&ax, 0, sizeof(ax));
		if (ioctl(*fd, X4STEP_GET_AXES, &ax) == 0 &&
		    ax.axis[0].velocity >= (unsigned int)vm / 100 * 99)
			break;
		usleep(2000);
	}
	if (n == 5000) {
		printf("not at %d steps/s after 5000 looks\n", vm);
		return 1;
	}
	clock_gettime(CLOCK_BOOTTIME, &t0);
	close(*fd);
	clock_gettime(CLOCK_BOOTTIME, &t1);
	*fd = -1;
	/* closed_ms: CLOCK_BOOTTIME, as /proc/uptime, for the caller's bounds */
	printf("closed while moving at %u steps/s: close() took %ld us, closed_ms=%ld\n",
	       ax.axis[0].velocity,
	       (long)((t1.tv_sec - t0.tv_sec) * 1000000 +
		      (t1.tv_nsec - t0.tv_nsec) / 1000),
	       (long)(t0.tv_sec * 1000 + t0.tv_nsec / 1000000));
	return 0;
}

int main(int argc, char **argv)
{
	int fd, ret = 2;

	if (argc >= 3 && !strcmp(argv[2], "inputs"))
		return cmd_inputs(argv[1], O_RDWR);
	if (argc >= 3 && !strcmp(argv[2], "inputs-ro"))
		return cmd_inputs(argv[1], O_RDONLY);
	if (argc < 4) {
		fprintf(stderr, "usage: see the comment at the top of the source\n");
		return 2;
	}
	fd = open(argv[1], O_RDWR | O_CLOEXEC);
	if (fd < 0) {
		perror(argv[1]);
		return 1;
	}
	if (!strcmp(argv[2], "move") && argc == 6)
		ret = cmd_move(fd, atoi(argv[3]), atoi(argv[4]), atoi(argv[5]));
	else if (!strcmp(argv[2], "hold-endless") && argc == 5)
		ret = cmd_hold_endless(fd, atoi(argv[3]), atoi(argv[4]));
	else if (!strcmp(argv[2], "close-braking") && argc == 5)
		ret = cmd_close_braking(&fd, atoi(argv[3]), atoi(argv[4]));
	if (fd >= 0)
		close(fd);
	return ret;
}
