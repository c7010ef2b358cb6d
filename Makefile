# The two commands of the README, and the steps behind them.
#   make demo   install what is missing, build, run the simulated campaign
#   make check  install what is missing, build with GCC and Clang (warnings are errors), run every test,
#               the real-kernel suite (make check-vm) included
BUILD ?= build
BUILD_CLANG ?= build-clang
# The real-kernel suite's build of m2mlat; its downloads and kernel module are cached outside the clone,
# in $(M2MLAT_VM_CACHE) (default /var/cache/m2mlat-vm; see docs/testing.md).
BUILD_VM ?= build-vm
CMAKE_FLAGS ?=

# Debian 12 / Ubuntu 24.04 packages the build and the tests need.
PACKAGES := build-essential cmake ninja-build clang-14 pkg-config \
  libsqlite3-dev sqlite3 libcpp-httplib-dev libcli11-dev nlohmann-json3-dev libfmt-dev libtomlplusplus-dev \
  libgtest-dev libgmock-dev libbenchmark-dev libboost-math-dev \
  python3 python3-numpy python3-pandas python3-scipy chromium
# Packages of the real-kernel suite (make check-vm): QEMU, the guest's busybox, the tools to unpack
# Debian's kernel packages and pack the initramfs, ccache for the guest's build of m2mlat (whose shared
# libraries the initramfs carries). tests/vm/run.sh installs linux-headers of the guest's kernel itself.
VM_PACKAGES := qemu-system-x86 busybox-static cpio xz-utils kmod binutils ccache

.PHONY: all deps deps-vm build build-clang demo check check-vm test bench clean

all: build

# $(call install_missing,PACKAGES): apt-get install those not installed yet.
define install_missing
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing: $$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi
endef

deps:
	$(call install_missing,$(PACKAGES))

deps-vm: deps
	$(call install_missing,$(VM_PACKAGES))

build: deps
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo $(CMAKE_FLAGS)
	cmake --build $(BUILD)

build-clang: deps
	cmake -S . -B $(BUILD_CLANG) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++-14 \
	  -DM2MLAT_WERROR=ON -DM2MLAT_BENCH=OFF $(CMAKE_FLAGS)
	cmake --build $(BUILD_CLANG)

demo: build
	./$(BUILD)/m2mlat demo

check: CMAKE_FLAGS += -DM2MLAT_WERROR=ON
check: build build-clang
	ctest --test-dir $(BUILD) --output-on-failure -j2
	ctest --test-dir $(BUILD_CLANG) --output-on-failure -j2 -L unit
	$(MAKE) --no-print-directory check-vm

# The real-kernel suite (tests/vm/): Debian's 6.1 kernel under QEMU with gpio-sim, m2mlat in the guest.
check-vm: deps-vm
	M2MLAT_VM_BUILD=$(abspath $(BUILD_VM)) tests/vm/run.sh

bench: build
	bench/run.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(BUILD_CLANG) $(BUILD_VM)
