// SPDX-License-Identifier: GPL-2.0
/*
 * x4vport: a virtual parallel port for tests, in the spirit of gpio-sim.
 *
 * A parport low-level driver without hardware: it registers one port
 * (parportN, the lowest free number) whose register writes are recorded
 * with ktime_get_ns() time stamps, and whose status inputs a test sets.
 * Client drivers such as x4step attach to it like to a parport_pc port.
 *
 * Files in /sys/kernel/debug/x4vport/:
 *   port        (r)  N of parportN
 *   trace       (r)  the recorded register writes, oldest first, one per
 *                    line: "<t_ns> <reg> <val>", t_ns from ktime_get_ns()
 *                    (CLOCK_MONOTONIC), reg 'd' (data), 'c' (control) or
 *                    's' (status, set by a test through `status` or
 *                    `pins`, or changed by a switch), val the register
 *                    byte after the write, in hex ("0x0b"). Reading does
 *                    not consume.
 *   trace_pipe  (r)  the same lines, consumed as read; end of file when
 *                    the buffer is empty (it never blocks).
 *   clear       (w)  any write empties the buffer and zeroes `overruns`
 *                    and `reads`.
 *   count       (r)  number of entries held.
 *   overruns    (r)  writes not recorded because the buffer was full (the
 *                    oldest entries are kept, the newest dropped).
 *   reads       (r)  register reads through the port's operations
 *                    (read_data, read_control, read_status) since the
 *                    load or the last `clear`: a client that must leave a
 *                    port alone can be seen to do so.
 *   data        (r)  the data register (pins 2..9).
 *   control     (r)  the control register (bit 0 pin 1, bit 1 pin 14,
 *                    bit 2 pin 16, bit 3 pin 17, raw: bits 0, 1 and 3 are
 *                    inverted by real hardware; bit 4 irq enable, bit 5
 *                    data direction).
 *   status      (rw) the raw status register that read_status() returns
 *                    (bit 3 pin 15, bit 4 pin 13, bit 5 pin 12, bit 6
 *                    pin 10, bit 7 pin 11 inverted: a high pin 11 reads 0).
 *                    Inputs driven by switches (below) override what is
 *                    written: reading gives the register as the port
 *                    shows it, writing sets the levels of the others.
 *   pins        (rw) the five input pin levels, 1 = high, in X4GetIn order:
 *                    bit 0 pin 15, bit 1 pin 13, bit 2 pin 12, bit 3
 *                    pin 10, bit 4 pin 11. Writing computes `status` (its
 *                    bits 0..2 are kept), reading computes from it. Here
 *                    too, switches override the inputs they drive.
 *   positions   (rw) the machine: four signed step positions, axes 1..4,
 *                    "300 0 0 0". Each rising clock edge of an axis in a
 *                    data write counts +1 if the axis's direction bit is
 *                    high in that write, else -1 (x4step's wiring: data
 *                    bit 2i direction, 2i+1 clock of axis i+1). Writing
 *                    four numbers places the machine there (|n| <= 2^62);
 *                    the switches follow at once.
 *   switches    (rw) up to 8 switches on the machine, one per line:
 *                    "AXIS BIT KIND AT HYST POL STATE", STATE "active" or
 *                    "idle". Write lines (or ';'-separated commands):
 *                      add AXIS BIT below|above AT HYST no|nc
 *                      clear
 *                    AXIS 1..4; BIT the input, 0..4 in X4GetIn order;
 *                    `below` is active while position <= AT, `above`
 *                    while position >= AT; once active it stays active
 *                    until the position is more than HYST (>= 0) steps
 *                    back past AT (`above`: until position < AT - HYST).
 *                    POL `no`: the pin is high while active, `nc`: low
 *                    while active. Switches on one input are in
 *                    parallel: the input is active while any of them is,
 *                    and all must have the same POL (an `add` that mixes
 *                    them fails with EINVAL). A write is all or nothing.
 *                    An input with no switch keeps its `pins` level.
 *                    The status register follows the switches in the
 *                    data write that moves the machine (an 's' trace
 *                    entry right after its 'd' entry, when it changes), so
 *                    a client reading the status after a step sees the
 *                    new level, as with a switch wired to a real machine.
 *   irqoff      (w)  a late timer on demand: writing N (1..10000) busy-waits
 *                    N us with interrupts off on the writing CPU, as a
 *                    driver that holds a lock too long would do.
 * Numbers are read as "0x%02x" (registers) or decimal (counters); writes
 * take any base kstrtoull accepts ("0x78", "120"), positions, AT and HYST
 * any that kstrtoll accepts ("-400", "0x100").
 *
 * The initial state is a port with nothing plugged in: data 0x00, control
 * 0x0c (as parport_pc leaves it), all input pins pulled high (status
 * 0x78), no switch, and the machine at 0 0 0 0 once the module is loaded
 * (the core probes for daisy-chain devices when the port is announced,
 * which toggles the data pins: the machine is placed at 0 after that).
 *
 * Register semantics follow parport_pc: write_control() and
 * frob_control() change bits 0..3 only; bit 4 belongs to enable_irq() and
 * disable_irq(), bit 5 to data_forward() and data_reverse(); read_control()
 * returns bits 0..3. Every change of the data or control register,
 * whichever operation makes it, is one trace entry; the core's
 * restore_state() (on parport_claim()) writes the control register too.
 *
 * The write path runs in any context, also a hard-irq hrtimer on
 * PREEMPT_RT: it takes a raw spinlock for a few instructions, never
 * sleeps, never prints.
 *
 * The port's operations have no owner module, so the module can be
 * unloaded while clients are attached, like hardware that goes away:
 * parport_remove_port() calls the clients' detach(), then gives the port
 * the core's dead operations. A client must stop touching port->ops
 * when its detach() returns.
 */
#define pr_fmt(fmt) KBUILD_MODNAME ": " fmt

#include <linux/atomic.h>
#include <linux/ctype.h>
#include <linux/debugfs.h>
#include <linux/fs.h>
#include <linux/kernel.h>
#include <linux/ktime.h>
#include <linux/module.h>
#include <linux/mutex.h>
#include <linux/parport.h>
#include <linux/platform_device.h>
#include <linux/seq_file.h>
#include <linux/slab.h>
#include <linux/spinlock.h>
#include <linux/string.h>
#include <linux/uaccess.h>
#include <linux/vmalloc.h>

/* Without it the parport core calls parport_pc directly, not our ops. */
#if !IS_ENABLED(CONFIG_PARPORT_NOT_PC)
#error "x4vport needs CONFIG_PARPORT_NOT_PC (Debian's kernels have it)"
#endif

static unsigned int ring_order = 20;
module_param(ring_order, uint, 0444);
MODULE_PARM_DESC(ring_order, "trace buffer holds 2^ring_order entries (10..24)");

/*
 * Announce the port without PARPORT_MODE_SAFEININT, as a USB adapter's
 * (uss720): its operations might sleep, and clients that drive a port in
 * interrupt context (x4step) must leave it alone. The operations are the
 * same; only the flag differs.
 */
static bool may_sleep;
module_param(may_sleep, bool, 0444);
MODULE_PARM_DESC(may_sleep, "announce a port whose operations may sleep (no PARPORT_MODE_SAFEININT)");

#define X4V_CTL_LINES 0x0f /* strobe, autofd, init, select */
#define X4V_CTL_IRQ 0x10
#define X4V_CTL_REVERSE 0x20
#define X4V_STATUS_PINS 0xf8
#define X4V_STATUS_BUSY 0x80 /* pin 11, inverted */
#define X4V_LINE_MAX 32 /* "18446744073709551615 c 0xff\n" */

#define X4V_AXES 4
#define X4V_INPUTS 5
#define X4V_SWITCHES 8
#define X4V_CLK_MASK 0xaa /* data bit 2i + 1: clock of axis i + 1 */
#define X4V_POS_MAX (1LL << 62) /* positions, AT and HYST: no overflow */
#define X4V_CMD_MAX 4096 /* longest write to `switches` */

struct x4v_entry {
	u64 t_ns;
	u8 reg; /* 'd', 'c' or 's' */
	u8 val;
};

struct x4v_switch {
	s64 at;
	s64 hyst; /* >= 0 */
	u8 axis; /* 0..3 */
	u8 bit; /* X4GetIn bit, 0..4 */
	bool above; /* active at position >= at, else at position <= at */
	bool nc; /* normally closed: the pin is low while active */
	bool active;
};

static struct {
	raw_spinlock_t lock; /* guards everything below */
	struct x4v_entry *ring;
	u64 mask; /* ring size - 1 */
	u64 head; /* sequence number of the next entry written */
	u64 tail; /* sequence number of the oldest entry held */
	u64 overruns;
	atomic64_t reads; /* register reads by clients */
	u8 data;
	u8 control;
	u8 status; /* as read_status() returns it */
	u8 status_set; /* as set through `status` and `pins` */

	/* The machine. */
	s64 pos[X4V_AXES];
	struct x4v_switch sw[X4V_SWITCHES];
	unsigned int nsw;
	u8 sw_inputs; /* X4GetIn bits with a switch */
	u8 sw_nc; /* ... of which normally closed */

	struct parport *port;
	struct platform_device *pdev;
	struct dentry *dir;
} x4v;

/* Set a register and record the write. Caller holds x4v.lock. */
static void x4v_set_locked(u8 *reg, char name, u8 val)
{
	struct x4v_entry *e;

	WRITE_ONCE(*reg, val);
	if (x4v.head - x4v.tail > x4v.mask) {
		x4v.overruns++;
		return;
	}
	e = &x4v.ring[x4v.head & x4v.mask];
	e->t_ns = ktime_get_ns();
	e->reg = name;
	e->val = val;
	x4v.head++;
}

/* X4GetIn bits (pins 15, 13, 12, 10, 11) -> status register bits 3..7. */
static u8 x4v_pins_to_status(u8 pins)
{
	return (pins << 3) ^ X4V_STATUS_BUSY;
}

/*
 * Update the switches from the positions and the status register from
 * them; record the status if it changed, or anyway if @force. A few dozen
 * instructions: this runs in the data write path. Caller holds x4v.lock.
 */
static void x4v_update_locked(bool force)
{
	u8 active = 0, levels, mask, status;
	unsigned int i;

	for (i = 0; i < x4v.nsw; i++) {
		struct x4v_switch *sw = &x4v.sw[i];
		s64 p = x4v.pos[sw->axis];

		if (sw->above)
			sw->active = p >= sw->at - (sw->active ? sw->hyst : 0);
		else
			sw->active = p <= sw->at + (sw->active ? sw->hyst : 0);
		if (sw->active)
			active |= 1u << sw->bit;
	}
	/* Pin levels of the switched inputs: NO high, NC low while active. */
	levels = (active ^ x4v.sw_nc) & x4v.sw_inputs;
	mask = x4v.sw_inputs << 3;
	status = (x4v.status_set & ~mask) |
		 (x4v_pins_to_status(levels) & mask);
	if (force || status != x4v.status)
		x4v_set_locked(&x4v.status, 's', status);
}

/* Set a register and record the write. Any context. */
static void x4v_set(u8 *reg, char name, u8 val)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	x4v_set_locked(reg, name, val);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
}

/* Change some bits of the control register; returns the new value. */
static u8 x4v_frob_ctl(u8 mask, u8 val)
{
	unsigned long flags;
	u8 ctl;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	ctl = (x4v.control & ~mask) ^ val;
	x4v_set_locked(&x4v.control, 'c', ctl);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return ctl;
}

/* ---- parport operations ---- */

/*
 * The machine moves with the data writes: count the rising clock edges,
 * then let the switches follow. The hard-irq path of x4step's timer.
 */
static void x4v_write_data(struct parport *p, unsigned char d)
{
	unsigned long flags;
	unsigned int i;
	u8 rise;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	rise = d & ~x4v.data & X4V_CLK_MASK;
	x4v_set_locked(&x4v.data, 'd', d);
	if (rise) {
		for (i = 0; i < X4V_AXES; i++) {
			if (!(rise & (2u << (2 * i))))
				continue;
			if (d & (1u << (2 * i)))
				x4v.pos[i]++;
			else
				x4v.pos[i]--;
		}
		x4v_update_locked(false);
	}
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
}

static unsigned char x4v_read_data(struct parport *p)
{
	atomic64_inc(&x4v.reads);
	return READ_ONCE(x4v.data);
}

static void x4v_write_control(struct parport *p, unsigned char d)
{
	x4v_frob_ctl(X4V_CTL_LINES, d & X4V_CTL_LINES);
}

static unsigned char x4v_read_control(struct parport *p)
{
	atomic64_inc(&x4v.reads);
	return READ_ONCE(x4v.control) & X4V_CTL_LINES;
}

static unsigned char x4v_frob_control(struct parport *p, unsigned char mask,
				      unsigned char val)
{
	mask &= X4V_CTL_LINES;
	val &= X4V_CTL_LINES;
	return x4v_frob_ctl(mask, val);
}

static unsigned char x4v_read_status(struct parport *p)
{
	atomic64_inc(&x4v.reads);
	return READ_ONCE(x4v.status);
}

static void x4v_enable_irq(struct parport *p)
{
	x4v_frob_ctl(X4V_CTL_IRQ, X4V_CTL_IRQ);
}

static void x4v_disable_irq(struct parport *p)
{
	x4v_frob_ctl(X4V_CTL_IRQ, 0);
}

static void x4v_data_forward(struct parport *p)
{
	x4v_frob_ctl(X4V_CTL_REVERSE, 0);
}

static void x4v_data_reverse(struct parport *p)
{
	x4v_frob_ctl(X4V_CTL_REVERSE, X4V_CTL_REVERSE);
}

static void x4v_init_state(struct pardevice *dev, struct parport_state *s)
{
	s->u.pc.ctr = 0x0c;
	s->u.pc.ecr = 0;
}

static void x4v_save_state(struct parport *p, struct parport_state *s)
{
	s->u.pc.ctr = READ_ONCE(x4v.control);
}

static void x4v_restore_state(struct parport *p, struct parport_state *s)
{
	x4v_set(&x4v.control, 'c', s->u.pc.ctr);
}

/*
 * Not const: parport_register_port() takes a plain pointer. No owner:
 * see the comment at the top.
 */
static struct parport_operations x4v_ops = {
	.write_data = x4v_write_data,
	.read_data = x4v_read_data,

	.write_control = x4v_write_control,
	.read_control = x4v_read_control,
	.frob_control = x4v_frob_control,

	.read_status = x4v_read_status,

	.enable_irq = x4v_enable_irq,
	.disable_irq = x4v_disable_irq,

	.data_forward = x4v_data_forward,
	.data_reverse = x4v_data_reverse,

	.init_state = x4v_init_state,
	.save_state = x4v_save_state,
	.restore_state = x4v_restore_state,

	/* Block transfers: the core's software IEEE 1284 on our registers. */
	.epp_write_data = parport_ieee1284_epp_write_data,
	.epp_read_data = parport_ieee1284_epp_read_data,
	.epp_write_addr = parport_ieee1284_epp_write_addr,
	.epp_read_addr = parport_ieee1284_epp_read_addr,

	.ecp_write_data = parport_ieee1284_ecp_write_data,
	.ecp_read_data = parport_ieee1284_ecp_read_data,
	.ecp_write_addr = parport_ieee1284_ecp_write_addr,

	.compat_write_data = parport_ieee1284_write_compat,
	.nibble_read_data = parport_ieee1284_read_nibble,
	.byte_read_data = parport_ieee1284_read_byte,

	.owner = NULL,
};

/* ---- the trace ---- */

/* Copy entry @seq if it is held. */
static bool x4v_peek(u64 seq, struct x4v_entry *e)
{
	unsigned long flags;
	bool held;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	held = seq >= x4v.tail && seq < x4v.head;
	if (held)
		*e = x4v.ring[seq & x4v.mask];
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return held;
}

static int x4v_format(char *buf, const struct x4v_entry *e)
{
	return scnprintf(buf, X4V_LINE_MAX, "%llu %c 0x%02x\n",
			 e->t_ns, e->reg, e->val);
}

/* A snapshot reader: entries from the oldest held at open, in order. */
struct x4v_iter {
	u64 base; /* x4v.tail at open */
	struct x4v_entry e;
};

static void *x4v_seq_at(struct seq_file *m, loff_t pos)
{
	struct x4v_iter *it = m->private;

	return x4v_peek(it->base + pos, &it->e) ? it : NULL;
}

static void *x4v_seq_start(struct seq_file *m, loff_t *pos)
{
	return x4v_seq_at(m, *pos);
}

static void *x4v_seq_next(struct seq_file *m, void *v, loff_t *pos)
{
	++*pos;
	return x4v_seq_at(m, *pos);
}

static void x4v_seq_stop(struct seq_file *m, void *v)
{
}

static int x4v_seq_show(struct seq_file *m, void *v)
{
	const struct x4v_iter *it = v;

	seq_printf(m, "%llu %c 0x%02x\n", it->e.t_ns, it->e.reg, it->e.val);
	return 0;
}

static const struct seq_operations x4v_seq_ops = {
	.start = x4v_seq_start,
	.next = x4v_seq_next,
	.stop = x4v_seq_stop,
	.show = x4v_seq_show,
};

static int x4v_trace_open(struct inode *inode, struct file *file)
{
	struct x4v_iter *it;
	unsigned long flags;

	it = __seq_open_private(file, &x4v_seq_ops, sizeof(*it));
	if (!it)
		return -ENOMEM;
	raw_spin_lock_irqsave(&x4v.lock, flags);
	it->base = x4v.tail;
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return 0;
}

static const struct file_operations x4v_trace_fops = {
	.owner = THIS_MODULE,
	.open = x4v_trace_open,
	.read = seq_read,
	.llseek = seq_lseek,
	.release = seq_release_private,
};

/* Consume the oldest entry if it is still @seq. */
static void x4v_consume(u64 seq)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	if (x4v.tail == seq)
		x4v.tail++;
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
}

static ssize_t x4v_pipe_read(struct file *file, char __user *ubuf,
			     size_t len, loff_t *ppos)
{
	char line[X4V_LINE_MAX];
	struct x4v_entry e;
	unsigned long flags;
	size_t done = 0;
	u64 seq;
	int n;

	for (;;) {
		raw_spin_lock_irqsave(&x4v.lock, flags);
		seq = x4v.tail;
		raw_spin_unlock_irqrestore(&x4v.lock, flags);
		if (!x4v_peek(seq, &e))
			break;
		n = x4v_format(line, &e);
		if ((size_t)n > len - done) {
			if (!done)
				return -EINVAL; /* buffer shorter than a line */
			break;
		}
		if (copy_to_user(ubuf + done, line, n))
			return done ? done : -EFAULT;
		x4v_consume(seq);
		done += n;
		if (fatal_signal_pending(current))
			break;
		cond_resched();
	}
	return done;
}

static const struct file_operations x4v_pipe_fops = {
	.owner = THIS_MODULE,
	.open = nonseekable_open,
	.read = x4v_pipe_read,
};

static ssize_t x4v_clear_write(struct file *file, const char __user *ubuf,
			       size_t len, loff_t *ppos)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	x4v.tail = x4v.head;
	x4v.overruns = 0;
	atomic64_set(&x4v.reads, 0);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return len;
}

static const struct file_operations x4v_clear_fops = {
	.owner = THIS_MODULE,
	.open = nonseekable_open,
	.write = x4v_clear_write,
};

/* ---- registers and counters ---- */

static int x4v_port_get(void *data, u64 *val)
{
	*val = x4v.port->number;
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_port_fops, x4v_port_get, NULL, "%llu\n");

static int x4v_count_get(void *data, u64 *val)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	*val = x4v.head - x4v.tail;
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_count_fops, x4v_count_get, NULL, "%llu\n");

static int x4v_overruns_get(void *data, u64 *val)
{
	unsigned long flags;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	*val = x4v.overruns;
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_overruns_fops, x4v_overruns_get, NULL, "%llu\n");

static int x4v_reads_get(void *data, u64 *val)
{
	*val = atomic64_read(&x4v.reads);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_reads_fops, x4v_reads_get, NULL, "%llu\n");

static int x4v_data_get(void *data, u64 *val)
{
	*val = READ_ONCE(x4v.data);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_data_fops, x4v_data_get, NULL, "0x%02llx\n");

static int x4v_control_get(void *data, u64 *val)
{
	*val = READ_ONCE(x4v.control);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_control_fops, x4v_control_get, NULL,
			 "0x%02llx\n");

static int x4v_status_get(void *data, u64 *val)
{
	*val = READ_ONCE(x4v.status);
	return 0;
}

static int x4v_status_set(void *data, u64 val)
{
	unsigned long flags;

	if (val > 0xff)
		return -EINVAL;
	raw_spin_lock_irqsave(&x4v.lock, flags);
	x4v.status_set = val;
	x4v_update_locked(true);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_status_fops, x4v_status_get, x4v_status_set,
			 "0x%02llx\n");

static int x4v_pins_get(void *data, u64 *val)
{
	*val = ((READ_ONCE(x4v.status) ^ X4V_STATUS_BUSY) >> 3) & 0x1f;
	return 0;
}

static int x4v_pins_set(void *data, u64 val)
{
	unsigned long flags;

	if (val > 0x1f)
		return -EINVAL;
	raw_spin_lock_irqsave(&x4v.lock, flags);
	x4v.status_set = (x4v.status_set & ~X4V_STATUS_PINS) |
			 x4v_pins_to_status(val);
	x4v_update_locked(true);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return 0;
}
DEFINE_DEBUGFS_ATTRIBUTE(x4v_pins_fops, x4v_pins_get, x4v_pins_set,
			 "0x%02llx\n");

/* ---- the machine ---- */

/* Serialises the writers of `switches`; the write path never takes it. */
static DEFINE_MUTEX(x4v_sw_mutex);

/* The next blank-separated word of *@s, or NULL at the end. */
static char *x4v_word(char **s)
{
	char *w = skip_spaces(*s), *e = w;

	while (*e && !isspace(*e))
		e++;
	if (*e)
		*e++ = '\0';
	*s = e;
	return *w ? w : NULL;
}

/* A signed number in -X4V_POS_MAX..X4V_POS_MAX. */
static int x4v_parse_pos(const char *w, s64 *val)
{
	int ret;

	if (!w)
		return -EINVAL;
	ret = kstrtoll(w, 0, val);
	if (ret)
		return ret;
	if (*val < -X4V_POS_MAX || *val > X4V_POS_MAX)
		return -ERANGE;
	return 0;
}

/* Copy a write from user space as a string; kfree() it. */
static char *x4v_user_string(const char __user *ubuf, size_t len)
{
	if (len > X4V_CMD_MAX)
		return ERR_PTR(-E2BIG);
	return memdup_user_nul(ubuf, len);
}

static int x4v_positions_show(struct seq_file *m, void *v)
{
	s64 pos[X4V_AXES];
	unsigned long flags;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	memcpy(pos, x4v.pos, sizeof(pos));
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	seq_printf(m, "%lld %lld %lld %lld\n", pos[0], pos[1], pos[2], pos[3]);
	return 0;
}

static int x4v_positions_open(struct inode *inode, struct file *file)
{
	return single_open(file, x4v_positions_show, NULL);
}

static ssize_t x4v_positions_write(struct file *file,
				   const char __user *ubuf, size_t len,
				   loff_t *ppos)
{
	char *buf, *s;
	s64 pos[X4V_AXES];
	unsigned long flags;
	int i, ret = 0;

	buf = x4v_user_string(ubuf, len);
	if (IS_ERR(buf))
		return PTR_ERR(buf);
	s = buf;
	for (i = 0; i < X4V_AXES && !ret; i++)
		ret = x4v_parse_pos(x4v_word(&s), &pos[i]);
	if (!ret && x4v_word(&s))
		ret = -EINVAL;
	kfree(buf);
	if (ret)
		return ret;
	raw_spin_lock_irqsave(&x4v.lock, flags);
	memcpy(x4v.pos, pos, sizeof(pos));
	x4v_update_locked(false);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return len;
}

static const struct file_operations x4v_positions_fops = {
	.owner = THIS_MODULE,
	.open = x4v_positions_open,
	.read = seq_read,
	.write = x4v_positions_write,
	.llseek = seq_lseek,
	.release = single_release,
};

static int x4v_switches_show(struct seq_file *m, void *v)
{
	struct x4v_switch sw[X4V_SWITCHES];
	unsigned long flags;
	unsigned int i, n;

	raw_spin_lock_irqsave(&x4v.lock, flags);
	n = x4v.nsw;
	memcpy(sw, x4v.sw, n * sizeof(sw[0]));
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	for (i = 0; i < n; i++)
		seq_printf(m, "%u %u %s %lld %lld %s %s\n", sw[i].axis + 1,
			   sw[i].bit, sw[i].above ? "above" : "below",
			   sw[i].at, sw[i].hyst, sw[i].nc ? "nc" : "no",
			   sw[i].active ? "active" : "idle");
	return 0;
}

static int x4v_switches_open(struct inode *inode, struct file *file)
{
	return single_open(file, x4v_switches_show, NULL);
}

/* Parse "AXIS BIT below|above AT HYST no|nc" (after "add"). */
static int x4v_parse_switch(char *s, struct x4v_switch *sw)
{
	const char *kind, *pol;
	unsigned int axis, bit;
	int ret;

	memset(sw, 0, sizeof(*sw));
	if (kstrtouint(x4v_word(&s) ?: "", 0, &axis) || axis < 1 ||
	    axis > X4V_AXES)
		return -EINVAL;
	if (kstrtouint(x4v_word(&s) ?: "", 0, &bit) || bit >= X4V_INPUTS)
		return -EINVAL;
	kind = x4v_word(&s);
	if (!kind || (strcmp(kind, "below") && strcmp(kind, "above")))
		return -EINVAL;
	ret = x4v_parse_pos(x4v_word(&s), &sw->at);
	if (ret)
		return ret;
	ret = x4v_parse_pos(x4v_word(&s), &sw->hyst);
	if (ret)
		return ret;
	if (sw->hyst < 0)
		return -EINVAL;
	pol = x4v_word(&s);
	if (!pol || (strcmp(pol, "no") && strcmp(pol, "nc")) || x4v_word(&s))
		return -EINVAL;
	sw->axis = axis - 1;
	sw->bit = bit;
	sw->above = !strcmp(kind, "above");
	sw->nc = !strcmp(pol, "nc");
	return 0;
}

/*
 * Apply the commands in @buf to the table @sw of *@n switches; *@kept
 * becomes the number of leading switches that were there before.
 */
static int x4v_switch_commands(char *buf, struct x4v_switch *sw,
			       unsigned int *n, unsigned int *kept)
{
	struct x4v_switch new;
	char *line, *cmd;
	unsigned int i;
	int ret;

	while ((line = strsep(&buf, "\n;"))) {
		cmd = x4v_word(&line);
		if (!cmd)
			continue;
		if (!strcmp(cmd, "clear")) {
			if (x4v_word(&line))
				return -EINVAL;
			*n = 0;
			*kept = 0;
			continue;
		}
		if (strcmp(cmd, "add"))
			return -EINVAL;
		ret = x4v_parse_switch(line, &new);
		if (ret)
			return ret;
		if (*n >= X4V_SWITCHES)
			return -ENOSPC;
		for (i = 0; i < *n; i++)
			if (sw[i].bit == new.bit && sw[i].nc != new.nc)
				return -EINVAL;
		sw[(*n)++] = new;
	}
	return 0;
}

static ssize_t x4v_switches_write(struct file *file, const char __user *ubuf,
				  size_t len, loff_t *ppos)
{
	struct x4v_switch sw[X4V_SWITCHES];
	unsigned int i, n, kept;
	unsigned long flags;
	char *buf;
	u8 inputs = 0, nc = 0;
	int ret;

	buf = x4v_user_string(ubuf, len);
	if (IS_ERR(buf))
		return PTR_ERR(buf);
	mutex_lock(&x4v_sw_mutex);
	raw_spin_lock_irqsave(&x4v.lock, flags);
	n = x4v.nsw;
	memcpy(sw, x4v.sw, sizeof(sw));
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	kept = n;
	ret = x4v_switch_commands(buf, sw, &n, &kept);
	if (ret)
		goto out;
	for (i = 0; i < n; i++) {
		inputs |= 1u << sw[i].bit;
		if (sw[i].nc)
			nc |= 1u << sw[i].bit;
	}
	raw_spin_lock_irqsave(&x4v.lock, flags);
	/* The switches kept keep their state, which may have changed since. */
	for (i = 0; i < kept; i++)
		sw[i].active = x4v.sw[i].active;
	memcpy(x4v.sw, sw, sizeof(sw));
	x4v.nsw = n;
	x4v.sw_inputs = inputs;
	x4v.sw_nc = nc;
	x4v_update_locked(false);
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
out:
	mutex_unlock(&x4v_sw_mutex);
	kfree(buf);
	return ret ? ret : len;
}

static ssize_t x4v_irqoff_write(struct file *file, const char __user *ubuf,
				size_t len, loff_t *ppos)
{
	unsigned long flags;
	unsigned int us;
	u64 end;
	int ret;

	ret = kstrtouint_from_user(ubuf, len, 0, &us);
	if (ret)
		return ret;
	if (!us || us > 10000)
		return -EINVAL;
	local_irq_save(flags);
	end = ktime_get_ns() + (u64)us * NSEC_PER_USEC;
	while (ktime_get_ns() < end)
		cpu_relax();
	local_irq_restore(flags);
	return len;
}

static const struct file_operations x4v_irqoff_fops = {
	.owner = THIS_MODULE,
	.open = nonseekable_open,
	.write = x4v_irqoff_write,
};

static const struct file_operations x4v_switches_fops = {
	.owner = THIS_MODULE,
	.open = x4v_switches_open,
	.read = seq_read,
	.write = x4v_switches_write,
	.llseek = seq_lseek,
	.release = single_release,
};

static void x4v_debugfs_init(void)
{
	struct dentry *d = debugfs_create_dir(KBUILD_MODNAME, NULL);

	x4v.dir = d;
	debugfs_create_file_unsafe("port", 0444, d, NULL, &x4v_port_fops);
	debugfs_create_file("trace", 0444, d, NULL, &x4v_trace_fops);
	debugfs_create_file("trace_pipe", 0444, d, NULL, &x4v_pipe_fops);
	debugfs_create_file("clear", 0200, d, NULL, &x4v_clear_fops);
	debugfs_create_file("irqoff", 0200, d, NULL, &x4v_irqoff_fops);
	debugfs_create_file_unsafe("count", 0444, d, NULL, &x4v_count_fops);
	debugfs_create_file_unsafe("overruns", 0444, d, NULL,
				   &x4v_overruns_fops);
	debugfs_create_file_unsafe("reads", 0444, d, NULL, &x4v_reads_fops);
	debugfs_create_file_unsafe("data", 0444, d, NULL, &x4v_data_fops);
	debugfs_create_file_unsafe("control", 0444, d, NULL,
				   &x4v_control_fops);
	debugfs_create_file_unsafe("status", 0644, d, NULL, &x4v_status_fops);
	debugfs_create_file_unsafe("pins", 0644, d, NULL, &x4v_pins_fops);
	debugfs_create_file("positions", 0644, d, NULL, &x4v_positions_fops);
	debugfs_create_file("switches", 0644, d, NULL, &x4v_switches_fops);
}

/* ---- module ---- */

static int __init x4v_init(void)
{
	struct parport *port;
	unsigned long flags;
	int ret;

	if (ring_order < 10 || ring_order > 24)
		return -EINVAL;
	raw_spin_lock_init(&x4v.lock);
	x4v.mask = (1ULL << ring_order) - 1;
	x4v.ring = vmalloc(array_size(x4v.mask + 1, sizeof(*x4v.ring)));
	if (!x4v.ring)
		return -ENOMEM;
	x4v.data = 0;
	x4v.control = 0x0c;
	x4v.status = x4v_pins_to_status(0x1f);
	x4v.status_set = x4v.status;
	memset(x4v.pos, 0, sizeof(x4v.pos));
	x4v.nsw = 0;
	x4v.sw_inputs = 0;
	x4v.sw_nc = 0;

	x4v.pdev = platform_device_register_simple(KBUILD_MODNAME,
						   PLATFORM_DEVID_NONE,
						   NULL, 0);
	if (IS_ERR(x4v.pdev)) {
		ret = PTR_ERR(x4v.pdev);
		goto err_ring;
	}

	port = parport_register_port(0, PARPORT_IRQ_NONE, PARPORT_DMA_NONE,
				     &x4v_ops);
	if (!port) {
		ret = -ENOMEM;
		goto err_pdev;
	}
	port->modes = PARPORT_MODE_PCSPP;
	if (!may_sleep)
		port->modes |= PARPORT_MODE_SAFEININT;
	port->dev = &x4v.pdev->dev;
	x4v.port = port;
	x4v_debugfs_init();
	pr_info("%s: virtual port\n", port->name);
	parport_announce_port(port);
	/* The core's daisy-chain probe in there toggled the data pins. */
	raw_spin_lock_irqsave(&x4v.lock, flags);
	memset(x4v.pos, 0, sizeof(x4v.pos));
	raw_spin_unlock_irqrestore(&x4v.lock, flags);
	return 0;

err_pdev:
	platform_device_unregister(x4v.pdev);
err_ring:
	vfree(x4v.ring);
	return ret;
}

static void __exit x4v_exit(void)
{
	/* Clients detach; from here on the port has the core's dead ops. */
	parport_remove_port(x4v.port);
	debugfs_remove_recursive(x4v.dir);
	/* Freed when the last client drops its reference. */
	parport_del_port(x4v.port);
	platform_device_unregister(x4v.pdev);
	vfree(x4v.ring);
}

module_init(x4v_init);
module_exit(x4v_exit);

MODULE_DESCRIPTION("Virtual parallel port for tests, with a write trace");
MODULE_LICENSE("GPL");
