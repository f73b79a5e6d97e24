# SPDX-License-Identifier: GPL-2.0
#
# x4step: stepper motors on the PC parallel port.
#   make            module (kmod/x4step.ko), libx4step, x4ctl
#   make check      installs what it needs, runs every test (host + QEMU)
#   make demo       a part program and the manual's first example on an emulated
#                   parallel port (QEMU), then simulated (scripts/demo.sh)
#   make bench      engine and module benchmarks (print figures)
#   make install    headers, library, x4ctl, module, udev rule, pkg-config

# The running kernel's build tree when it has one, else the newest Debian
# headers installed (non-RT); override with KDIR=...
KDIR ?= $(firstword $(wildcard /lib/modules/$(shell uname -r)/build) \
	$(lastword $(shell ls -d /usr/src/linux-headers-*-amd64 2>/dev/null | grep -v -- -rt- | sort -V)))
BUILD ?= $(CURDIR)/build
PREFIX ?= /usr/local
DESTDIR ?=

.PHONY: all module userspace deps check check-host check-qemu check-style check-debug demo bench install clean

all: module userspace

module:
	$(MAKE) -C $(KDIR) M=$(CURDIR) W=1 modules

userspace:
	cmake -S $(CURDIR) -B $(BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_INSTALL_PREFIX=$(PREFIX) -DX4STEP_WERROR=ON >/dev/null
	cmake --build $(BUILD) -j2

deps:
	scripts/deps.sh all

check: deps
	tests/run-all.sh

check-host: userspace
	cd $(BUILD) && ctest --output-on-failure

check-qemu:
	tests/qemu/run-suite.sh

check-style:
	tests/check-style.sh

# The QEMU suite on a kernel with lockdep, KASAN, UBSAN, atomic-sleep and
# debugobjects checks (built once, ~7 min on 2 idle cores, then cached).
check-debug: deps
	tests/debugkernel/run.sh

demo: deps
	scripts/demo.sh

bench: deps userspace
	tests/bench/run.sh

install: all
	DESTDIR=$(DESTDIR) cmake --install $(BUILD)
	$(MAKE) -C $(KDIR) M=$(CURDIR) INSTALL_MOD_DIR=extra INSTALL_MOD_PATH=$(DESTDIR) modules_install
	install -D -m 0644 kmod/60-x4step.rules $(DESTDIR)/etc/udev/rules.d/60-x4step.rules

clean:
	$(MAKE) -C $(KDIR) M=$(CURDIR) clean
	rm -rf $(BUILD)
