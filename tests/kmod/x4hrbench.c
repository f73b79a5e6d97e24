// SPDX-License-Identifier: GPL-2.0
/*
 * x4hrbench: the baseline for x4step's timing benchmark. A bare hard-irq
 * hrtimer with absolute expiries, firing every period_ns ns count times,
 * measured exactly as x4step measures its step timer (expiry to callback,
 * same histogram). Test-only.
 *
 * /sys/kernel/debug/x4hrbench/run: write "PERIOD_NS COUNT" to run (blocks
 * until done); read for "events N p50 P p99 Q max M beyond B" (ns).
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/completion.h>
#include <linux/debugfs.h>
#include <linux/hrtimer.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/slab.h>
#include <linux/uaccess.h>
#include <linux/x4step.h>

#include "../../kmod/x4step_compat.h"

static struct {
	struct hrtimer timer;
	struct completion done;
	struct mutex lock; /* one run at a time */
	u64 period_ns;
	u64 left;
	struct x4step_timing t;
	struct dentry *dir;
} bench;

static enum hrtimer_restart bench_tick(struct hrtimer *timer)
{
	s64 late = ktime_to_ns(ktime_sub(ktime_get(), hrtimer_get_expires(timer)));
	u64 bucket = late > 0 ? (u64)late / X4STEP_TIMING_BUCKET_NS : 0;

	bench.t.events++;
	if (late > 0 && late > bench.t.late_max_ns)
		bench.t.late_max_ns = late;
	if (bucket < X4STEP_TIMING_BUCKETS)
		bench.t.hist[bucket]++;
	else
		bench.t.beyond++;
	if (--bench.left == 0) {
		complete(&bench.done);
		return HRTIMER_NORESTART;
	}
	hrtimer_add_expires_ns(timer, bench.period_ns);
	return HRTIMER_RESTART;
}

/* The lateness below which `permille` of the events fall, in ns. */
static u64 bench_percentile(unsigned int permille)
{
	u64 want = div_u64(bench.t.events * permille + 999, 1000), seen = 0;
	int i;

	for (i = 0; i < X4STEP_TIMING_BUCKETS; i++) {
		seen += bench.t.hist[i];
		if (seen >= want)
			return (u64)(i + 1) * X4STEP_TIMING_BUCKET_NS;
	}
	return bench.t.late_max_ns;
}

static ssize_t run_write(struct file *file, const char __user *ubuf,
			 size_t len, loff_t *ppos)
{
	char buf[48];
	u64 period, count;

	if (len >= sizeof(buf))
		return -EINVAL;
	if (copy_from_user(buf, ubuf, len))
		return -EFAULT;
	buf[len] = 0;
	if (sscanf(buf, "%llu %llu", &period, &count) != 2 ||
	    period < 1000 || !count)
		return -EINVAL;

	mutex_lock(&bench.lock);
	memset(&bench.t, 0, sizeof(bench.t));
	bench.period_ns = period;
	bench.left = count;
	reinit_completion(&bench.done);
	hrtimer_start(&bench.timer, ktime_add_ns(ktime_get(), period),
		      HRTIMER_MODE_ABS_HARD);
	wait_for_completion(&bench.done);
	mutex_unlock(&bench.lock);
	return len;
}

static ssize_t run_read(struct file *file, char __user *ubuf, size_t len,
			loff_t *ppos)
{
	char buf[160];
	int n;

	mutex_lock(&bench.lock);
	n = scnprintf(buf, sizeof(buf),
		      "events %llu p50 %llu p99 %llu max %llu beyond %llu\n",
		      bench.t.events, bench_percentile(500),
		      bench_percentile(990), bench.t.late_max_ns,
		      bench.t.beyond);
	mutex_unlock(&bench.lock);
	return simple_read_from_buffer(ubuf, len, ppos, buf, n);
}

static const struct file_operations run_fops = {
	.owner = THIS_MODULE,
	.read = run_read,
	.write = run_write,
	.llseek = default_llseek,
};

static int __init bench_init(void)
{
	mutex_init(&bench.lock);
	init_completion(&bench.done);
	x4_hrtimer_setup(&bench.timer, bench_tick, CLOCK_MONOTONIC,
			 HRTIMER_MODE_ABS_HARD);
	bench.dir = debugfs_create_dir(KBUILD_MODNAME, NULL);
	debugfs_create_file("run", 0600, bench.dir, NULL, &run_fops);
	return 0;
}

static void __exit bench_exit(void)
{
	debugfs_remove_recursive(bench.dir);
	hrtimer_cancel(&bench.timer);
}

module_init(bench_init);
module_exit(bench_exit);

MODULE_DESCRIPTION("Bare hrtimer lateness baseline for x4step (test only)");
MODULE_LICENSE("GPL");
