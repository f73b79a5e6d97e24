#!/bin/bash
# SPDX-License-Identifier: GPL-2.0
#
# Boot a Debian kernel under QEMU (TCG) with an emulated parallel port at 0x378,
# a busybox initramfs, parport/parport_pc/uinput loaded, and run one guest script.
#
# Usage: tests/qemu/run-guest.sh --kver VERSION --out DIR [--module FILE.ko]...
#            [--bin FILE]... [--icount] [--timeout SEC] [--monitor SOCK]
#            [--kernel IMAGE] GUEST_SCRIPT
#
# The guest script runs as `sh /test.sh` with X4MOD=/lib/x4 (where --module files
# go); --bin files go to /bin. Output in DIR:
#   console.log  the guest's serial console (also streamed to stdout)
#   dmesg.log    the guest's full kernel log, dumped after the script (2nd serial port)
#   lpt.log      QEMU's trace of every parallel port write (see tests/tools/x4trace)
#   lpt-test.log the same from the start of GUEST_SCRIPT on (no BIOS/probe writes)
# With --monitor SOCK, QEMU's monitor listens on that unix socket, and a guest line
# "X4MON <command>" on the console is sent to it (e.g. `echo X4MON sendkey esc`).
# --kernel boots IMAGE, the same kernel unpacked by pvh-kernel.sh, instead of
# /boot/vmlinuz-VERSION (3-7 s faster under TCG).
#
# Exit status: the guest script's status; 124 timeout; 125 no X4GUEST-EXIT line
# (guest crashed or QEMU failed); 126 kernel oops/BUG/WARNING/... in the logs;
# 120 the guest's own setup (parport, uinput) failed; 2 usage.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)

usage() {
	echo "usage: $0 --kver VERSION --out DIR [--module FILE.ko]... [--bin FILE]..." >&2
	echo "           [--icount] [--timeout SEC] [--monitor SOCK] [--kernel IMAGE] GUEST_SCRIPT" >&2
	exit 2
}
die() {
	echo "run-guest: $*" >&2
	exit 2
}

kver="" out="" icount=0 timeout_s=300 monitor="" script="" kernel=""
modules=() bins=()
while [ $# -gt 0 ]; do
	case "$1" in
	--kver) kver=${2:?}; shift 2 ;;
	--out) out=${2:?}; shift 2 ;;
	--module) modules+=("${2:?}"); shift 2 ;;
	--bin) bins+=("${2:?}"); shift 2 ;;
	--icount) icount=1; shift ;;
	--timeout) timeout_s=${2:?}; shift 2 ;;
	--monitor) monitor=${2:?}; shift 2 ;;
	--kernel) kernel=${2:?}; shift 2 ;;
	-h | --help) usage ;;
	-*) echo "run-guest: unknown option $1" >&2; usage ;;
	*) [ -z "$script" ] || usage; script=$1; shift ;;
	esac
done
if [ -z "$kver" ] || [ -z "$out" ] || [ -z "$script" ]; then usage; fi
[[ "$timeout_s" =~ ^[0-9]+$ ]] || die "--timeout needs whole seconds"
kernel=${kernel:-/boot/vmlinuz-$kver}
moddir=/lib/modules/$kver
[ -r "$kernel" ] || die "no kernel $kernel"
[ -d "$moddir" ] || die "no module tree $moddir"
[ -r "$script" ] || die "cannot read guest script $script"
for f in "${modules[@]}" "${bins[@]}"; do [ -r "$f" ] || die "cannot read $f"; done
command -v qemu-system-x86_64 >/dev/null || die "qemu-system-x86_64 not installed"
[ -x /bin/busybox ] || die "busybox-static not installed"

mkdir -p "$out"
out=$(cd "$out" && pwd)
root=$out/initramfs
rm -rf "$root" "$out"/{console,dmesg,lpt,lpt-test}.log "$out/initramfs.cpio.gz"
mkdir -p "$root"/{bin,sbin,usr/bin,usr/sbin,proc,sys,dev,tmp,lib/x4,lib/kmod}

# busybox insmod cannot load compressed modules: store them plain.
copy_module() { # SRC DESTDIR
	local src=$1 dst
	dst=$2/$(basename "$src")
	case "$src" in
	*.ko.xz) xz -dc "$src" >"${dst%.xz}" ;;
	*.ko.zst) zstd -q -dc "$src" >"${dst%.zst}" ;;
	*.ko.gz) gzip -dc "$src" >"${dst%.gz}" ;;
	*) cp "$src" "$dst" ;;
	esac
}
find_module() { # NAME SUBDIR -> path or nothing (built in)
	[ -d "$moddir/kernel/$2" ] || return 0
	find "$moddir/kernel/$2" -name "$1.ko" -o -name "$1.ko.*" 2>/dev/null | head -n1
}

cp /bin/busybox "$root/bin/busybox"
# The applets' links in one process (ln for each took 2-4 s of every run).
/bin/busybox --list-full | (cd "$root" && perl -nle \
	'-e or -l or symlink("/bin/busybox", $_) or die "run-guest: cannot link $_: $!\n"')
# uinput and evdev (/dev/input/event*, to watch keys in tests) may be built in.
# lp and ppdev, the other parport clients, are there for tests to load.
for m in parport:drivers/parport parport_pc:drivers/parport uinput:drivers/input/misc evdev:drivers/input \
	lp:drivers/char ppdev:drivers/char; do
	src=$(find_module "${m%%:*}" "${m#*:}")
	if [ -n "$src" ]; then
		copy_module "$src" "$root/lib/kmod"
	else
		case "${m%%:*}" in
		parport*) die "${m%%:*} module not found under $moddir" ;;
		esac
	fi
done
for f in "${modules[@]}"; do copy_module "$f" "$root/lib/x4"; done
for f in "${bins[@]}"; do
	if readelf -l "$f" 2>/dev/null | grep -q 'Requesting program interpreter'; then
		echo "run-guest: warning: $f is dynamically linked; the guest has no libc" >&2
	fi
	install -m 0755 "$f" "$root/bin/"
done
install -m 0755 "$script" "$root/test.sh"

cat >"$root/init" <<'EOF'
#!/bin/sh
# x4step test guest: load parport, run /test.sh, report its status, power off.
export PATH=/bin:/sbin:/usr/bin:/usr/sbin HOME=/ X4MOD=/lib/x4
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t devtmpfs devtmpfs /dev
mount -t tmpfs tmpfs /tmp

# The console is a UART: wait until the driver has sent everything (its tx
# counter stops moving) so the last lines are not lost at power-off.
drain() {
	prev=x
	for _ in $(seq 100); do
		cur=$(grep '^0:' /proc/tty/driver/serial 2>/dev/null)
		[ "$cur" = "$prev" ] && return
		prev=$cur
		usleep 20000
	done
}
finish() {
	dmesg >/dev/ttyS1 2>/dev/null
	echo "X4GUEST-EXIT $1"
	drain
	poweroff -f
}

setup() {
	insmod /lib/kmod/parport.ko || return 1
	insmod /lib/kmod/parport_pc.ko || return 1
	if ! dmesg | grep -q 'parport0: PC-style at 0x378'; then
		echo "x4guest: parport_pc did not report 'parport0: PC-style at 0x378'"
		dmesg | grep -i parport
		return 1
	fi
	for m in uinput evdev; do
		if [ -e /lib/kmod/$m.ko ]; then
			insmod /lib/kmod/$m.ko || return 1
		fi
	done
	[ -c /dev/uinput ] || { echo "x4guest: no /dev/uinput"; return 1; }
}

if ! setup; then
	echo "x4guest: guest setup failed"
	finish 120
fi
# Mark the start of the test in QEMU's trace: writes to the status register
# change no pin, but QEMU traces them; run-guest.sh cuts lpt-test.log there.
for v in 130 064; do printf "\\$v" | dd of=/dev/port bs=1 seek=889 2>/dev/null; done
cd /
sh /test.sh
finish $?
EOF
chmod 0755 "$root/init"

(cd "$root" && find . | cpio -o -H newc --quiet) | gzip -1 >"$out/initramfs.cpio.gz"

# shellcheck disable=SC2054 # commas are QEMU's option syntax
qemu=(qemu-system-x86_64 -accel tcg -m 512 -smp 1 -nographic -no-reboot -nic none
	-kernel "$kernel" -initrd "$out/initramfs.cpio.gz"
	-append "console=ttyS0 quiet loglevel=4 panic=-1"
	-device isa-parallel,chardev=p0 -chardev null,id=p0
	-msg timestamp=on -trace parallel_ioport_write -D "$out/lpt.log"
	-serial "file:$out/console.log" -serial "file:$out/dmesg.log")
# shellcheck disable=SC2054
[ "$icount" = 1 ] && qemu+=(-icount shift=0,sleep=off)
if [ -n "$monitor" ]; then
	python=$(command -v /usr/bin/python3 || command -v python3) || die "--monitor needs python3"
	rm -f "$monitor"
	qemu+=(-monitor "unix:$monitor,server,nowait")
else
	qemu+=(-monitor none)
fi

pids=()
# shellcheck disable=SC2317 # called by trap
cleanup() {
	local p
	for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# The timeout counts the seconds QEMU could run: wall time less the time its
# busiest thread waited for a CPU (/proc/PID/task/*/schedstat, field 2, ns).
# On an idle host that is wall time; on a host loaded many times over, a
# guest that is merely slow is not killed, and a hung guest (idle, not
# waiting for a CPU) still is. Without schedstat it is wall time.
qemu_waited_ns() { # PID
	cat /proc/"$1"/task/*/schedstat 2>/dev/null | awk '$2 > m { m = $2 } END { printf "%.0f\n", m }'
}
watchdog() { # PID
	local t0 now waited _
	set +e
	t0=$(date +%s%N)
	while kill -0 "$1" 2>/dev/null; do
		sleep 1
		now=$(date +%s%N)
		waited=$(qemu_waited_ns "$1")
		if [ $(((now - t0 - waited) / 1000000000)) -ge "$timeout_s" ]; then
			echo "$(((now - t0) / 1000000000)) $((waited / 1000000000))" >"$out/timeout"
			kill -TERM "$1" 2>/dev/null
			for _ in 1 2 3 4 5; do
				sleep 1
				kill -0 "$1" 2>/dev/null || return
			done
			kill -KILL "$1" 2>/dev/null
			return
		fi
	done
}

: >"$out/console.log"
rm -f "$out/timeout"
start=$(date +%s.%N)
"${qemu[@]}" </dev/null &
qpid=$!
pids+=("$qpid")
watchdog "$qpid" &
pids+=("$!")
# Stream the console for the developer (without SeaBIOS's terminal resets);
# with a monitor, also forward X4MON lines.
stream() {
	# -s: notice QEMU's end within 0.1 s, not tail's default 1 s.
	tail -n +1 -f -s 0.1 --pid="$qpid" "$out/console.log" |
		sed -u -e 's/\x1bc//g' -e 's/\x1b\[[?0-9;]*[a-zA-Z]//g'
}
if [ -n "$monitor" ]; then
	stream | while IFS= read -r line; do
		printf '%s\n' "$line"
		line=${line%$'\r'}
		case "$line" in
		X4MON\ *) "$python" "$here/qemu-monitor.py" "$monitor" "${line#X4MON }" >&2 || true ;;
		esac
	done &
else
	stream &
fi
pids+=("$!")
set +e
wait "$qpid"
qrc=$?
set -e
wait "${pids[2]}" 2>/dev/null || true
kill "${pids[1]}" 2>/dev/null || true
pids=()
secs=$(echo "$start $(date +%s.%N)" | awk '{printf "%.1f", $2 - $1}')

# lpt-test.log: the trace after the start marker (0x58 then 0x34 written to
# addr 1), without SeaBIOS's and parport_pc's probing writes.
awk '/parallel_ioport_write/ {
	if (on) { print; next }
	if (prev && /write \[SW\] addr 0x01 val 0x34$/) { on = 1; next }
	prev = /write \[SW\] addr 0x01 val 0x58$/
}' "$out/lpt.log" >"$out/lpt-test.log" 2>/dev/null || true

status=$(tr -d '\r' <"$out/console.log" | sed -n 's/^.*X4GUEST-EXIT \([0-9][0-9]*\)$/\1/p' | tail -n1)

# A kernel report fails the run even if the script passed: WARN() splats are
# KERN_WARNING, below the console loglevel, so dmesg.log is scanned too.
bad='WARNING: CPU:|WARNING: at |cut here \]|BUG: |kernel BUG at|Oops|general protection fault|Call Trace:|sleeping function called from invalid context|KASAN|UBSAN|possible circular locking|possible recursive locking|inconsistent lock state|WARNING: |turning off the locking correctness validator|DEBUG_LOCKS_WARN_ON|suspicious RCU usage|detected stalls|Kernel panic'
reports=$(cat "$out/console.log" "$out/dmesg.log" 2>/dev/null | tr -d '\r' | grep -a -E "$bad" |
	awk '!seen[$0]++ { n++; if (n <= 30) print } END { if (n > 30) print "... and " n - 30 " more lines" }' || true)

if [ -f "$out/timeout" ]; then
	read -r wall waited <"$out/timeout"
	echo "run-guest: TIMEOUT after ${timeout_s}s ($kver; ${wall}s of wall time, ${waited}s of it waiting for a CPU); logs in $out" >&2
	[ -z "$reports" ] || printf 'run-guest: kernel reports:\n%s\n' "$reports" >&2
	exit 124
fi
if [ -z "$status" ]; then
	echo "run-guest: no X4GUEST-EXIT line (guest crashed? qemu status $qrc) after ${secs}s; see $out/console.log" >&2
	[ -z "$reports" ] || printf 'run-guest: kernel reports:\n%s\n' "$reports" >&2
	exit 125
fi
if [ -n "$reports" ]; then
	echo "run-guest: kernel reported problems ($kver), see $out/console.log and $out/dmesg.log:" >&2
	printf '%s\n' "$reports" >&2
	exit 126
fi
echo "run-guest: $kver: guest exit $status after ${secs}s" >&2
exit "$status"
