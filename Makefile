# The two commands of the README, and the steps behind them.
#   make demo   install what is missing, build, run the simulated campaign
#   make check  install what is missing, build with GCC and Clang (warnings are errors), run every test:
#               the unit tests again under Clang's sanitizers, the real-kernel suite (make check-vm), the
#               arm64 build, the packages and the fuzz targets
BUILD ?= build
BUILD_CLANG ?= build-clang
# RelWithDebInfo (-O2 -g) for the demo and the benchmarks; make check builds -O2 without debug info
# (debug info is a third of the compile time) and keeps the asserts.
BUILD_TYPE ?= RelWithDebInfo
CMAKE_FLAGS ?=
empty :=
space := $(empty) $(empty)

# Debian 12 / Ubuntu 24.04 packages: what building m2mlat needs (all `make demo` installs), then what
# the tests need besides (the test frameworks, the Clang tree, the programs the tests run).
# libpq-dev is named with the machine's architecture: its amd64 and arm64 packages cannot be installed
# side by side (not Multi-Arch: same), so the arm64 cross-build's libpq-dev:arm64 replaces it, and the
# next build of this machine's own must put it back (a check for "libpq-dev" alone would find the
# arm64 one installed).
HOST_ARCH := $(shell dpkg --print-architecture 2>/dev/null || echo amd64)
# `make demo` installs DEMO_PACKAGES without their recommends: g++ rather than build-essential (whose
# dpkg-dev, and the perl modules that come with it, the build does not use) and Boost's headers
# rather than libboost-math-dev (the compiled TR1 functions of Boost.Math are never linked).
DEMO_PACKAGES := g++ cmake ninja-build pkg-config \
  libsqlite3-dev libcpp-httplib-dev libpcap-dev libpq-dev:$(HOST_ARCH) libcli11-dev nlohmann-json3-dev libfmt-dev \
  libtomlplusplus-dev libboost-dev libzstd-dev liblz4-dev
BUILD_PACKAGES := build-essential $(DEMO_PACKAGES) libboost-math-dev
PACKAGES := $(BUILD_PACKAGES) clang-14 sqlite3 libgtest-dev libgmock-dev libbenchmark-dev \
  python3 python3-numpy python3-pandas python3-scipy chromium chrony rt-tests linuxptp libclang-rt-14-dev \
  postgresql
# R reads the exports in tests/integration/exports_readers.sh. Without its recommends (r-base-dev's
# compilers, r-recommended's libraries, the HTML docs): r-base-core alone installed in 20 s here.
NOREC_PACKAGES := r-base-core
# Packages of the real-kernel suite (make check-vm): QEMU, the guest's busybox, the tools to unpack
# Debian's kernel packages and pack the initramfs. The guest runs $(BUILD)/m2mlat (with its shared
# libraries in the initramfs). tests/vm/run.sh installs linux-headers of the guest's kernel itself.
# The two-guest test (tests/vm/twoguest.sh) also runs the host's chronyd and chronyc in its guests and
# judges with python3 (standard library), and finds free ports with ss (iproute2).
VM_PACKAGES := qemu-system-x86 busybox-static cpio xz-utils kmod binutils chrony python3 iproute2

.PHONY: all deps deps-build deps-demo deps-vm build build-clang demo check check-vm fuzz test bench clean
.PHONY: deps-arm64 deps-package cross-arm64 check-arm64 package check-package

all: build

# $(call step,WHAT): a line with the time in the log, so that a slow run shows where its time went.
step = @echo "== $$(date -u +%H:%M:%S) $(1)"

# $(call install_missing,PACKAGES[,APT OPTIONS]): apt-get install those not installed yet.
define install_missing
	@missing=$$(for p in $(1); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing: $$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(2) $$missing; \
	fi
endef

deps:
	$(call install_missing,$(PACKAGES))
	$(call install_missing,$(NOREC_PACKAGES),--no-install-recommends)

deps-build:
	$(call install_missing,$(BUILD_PACKAGES))

deps-demo:
	$(call install_missing,$(DEMO_PACKAGES),--no-install-recommends)

deps-vm: deps
	$(call install_missing,$(VM_PACKAGES))

# `cmake --build` leaves the job count to ninja (nproc + 2: 4 on two cores). Measured 2026-11-26 on the
# 2-core machine beside other builds (load 10), the Clang tree's store and formats libraries from
# scratch: -j2 177 s, -j4 143 s, the same CPU time (63 and 64 s), compilers' peak memory 0.70 and
# 1.27 GB. Not slower, more memory; CMAKE_BUILD_PARALLEL_LEVEL=2 sets another count.
# Everything, each file compiled alone (the settings `make demo` changes are set back explicitly): a
# developer's tree, rebuilt file by file, and each file checked to include what it uses. make check
# builds it as a unity build (below).
build: deps
	$(call step,build $(BUILD))
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) -DM2MLAT_TESTS=ON -DM2MLAT_BENCH=ON \
	  -DCMAKE_UNITY_BUILD=OFF -DM2MLAT_PCH=OFF -DM2MLAT_O1_MODULES= -DM2MLAT_TEST_OPTIMIZE= $(CMAKE_FLAGS)
	cmake --build $(BUILD)

# make check's three trees (GCC, Clang, arm64) are unity builds: eight source files of a target compiled
# as one, so each header is parsed and each template instantiated once per batch. Measured 2026-11-27
# on the 2-core machine, GCC -O2, CPU time: cli/ 602 s file by file, 171 s batched; the other
# libraries 816 s and 400 s (docs/testing.md).
UNITY := -DCMAKE_UNITY_BUILD=ON -DCMAKE_UNITY_BUILD_BATCH_SIZE=8

# Clang, warnings as errors, AddressSanitizer and UndefinedBehaviorSanitizer (any report fails), with
# the coverage instrumentation of libFuzzer: the same tree holds the unit tests and the fuzz targets,
# and nothing else (M2MLAT_EXECUTABLE=OFF: no executable, no cli/, which no test there runs).
SANITIZE := -fsanitize=address,undefined -fno-sanitize-recover=undefined -fsanitize=fuzzer-no-link
build-clang: deps
	$(call install_missing,libclang-rt-14-dev)
	$(call step,build $(BUILD_CLANG))
	cmake -S . -B $(BUILD_CLANG) -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=Release \
	  "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -gline-tables-only" "-DCMAKE_CXX_FLAGS=$(SANITIZE)" \
	  -DM2MLAT_WERROR=ON -DM2MLAT_FUZZ=ON -DM2MLAT_BENCH=OFF -DM2MLAT_EXECUTABLE=OFF $(UNITY)
	cmake --build $(BUILD_CLANG)

# The first run: only the m2mlat executable (no tests, no benchmarks, no debug info, a unity build
# with the precompiled header of M2MLAT_PCH, -O2, and -O1 for the layers of DEMO_O1_MODULES, whose
# code runs once a command: 20 % less compile, the demo's report byte-identical), then the simulated
# campaign, checked against its truth, and its HTML report in demo-report/. Measured 2026-11-26 from a
# minimal Debian 12 root on the idle 2-core machine (docs/testing.md): 2 min 14 s in all (packages
# 20 s, build 114 s, demo 1 s).
DEMO_O1_MODULES := cli net collect agent setup sync archive selftest capture
demo: deps-demo
	$(call step,build $(BUILD): m2mlat only)
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" \
	  -DM2MLAT_TESTS=OFF -DM2MLAT_BENCH=OFF -DM2MLAT_PCH=ON "-DM2MLAT_O1_MODULES=$(subst $(space),;,$(DEMO_O1_MODULES))" $(UNITY)
	cmake --build $(BUILD) --target m2mlat_exe
	$(call step,demo)
	./$(BUILD)/m2mlat demo --report demo-report

check: BUILD_TYPE = Release
check: CMAKE_FLAGS += -DM2MLAT_WERROR=ON -DCMAKE_CXX_FLAGS_RELEASE=-O2 -DM2MLAT_TEST_OPTIMIZE=-O1 $(UNITY)
check: build build-clang
	$(call step,unit and integration tests: $(BUILD))
	ctest --test-dir $(BUILD) --output-on-failure -j2
	$(call step,unit tests under the sanitizers: $(BUILD_CLANG))
	ctest --test-dir $(BUILD_CLANG) --output-on-failure -j2 -L unit
	$(MAKE) --no-print-directory $(CHECK_VARS) check-vm fuzz
	$(MAKE) --no-print-directory $(CHECK_VARS) check-arm64 check-package
	$(call step,make check: all passed)
# The later steps depend on `build` too: hand them check's settings, or they would rebuild it.
CHECK_VARS = BUILD_TYPE=$(BUILD_TYPE) "CMAKE_FLAGS=$(CMAKE_FLAGS)"

# The real-kernel suite (tests/vm/): Debian's 6.1 kernel under QEMU with gpio-sim, $(BUILD)/m2mlat in
# the guest; its downloads and kernel module are cached in $(M2MLAT_VM_CACHE) (default
# /var/cache/m2mlat-vm; see docs/testing.md). Then the two-guest test: two such guests synchronised
# by chrony (and then not), collected from the host, the edges triggered in physical time.
check-vm: build deps-vm
	$(call step,real-kernel suite)
	tests/vm/run.sh --m2mlat $(BUILD)/m2mlat
	$(call step,two-guest test)
	tests/vm/twoguest.sh --m2mlat $(BUILD)/m2mlat

# The boards (docs/packaging.md): the arm64 cross-build with Debian's cross toolchain and multiarch
# arm64 libraries, its tests under qemu-aarch64, and the .deb packages for amd64 and arm64.
BUILD_ARM64 ?= build-arm64
PKG_DIR ?= dist
# The unit tests built and run for arm64 (empty: every namespace's): those of the code that runs on
# the boards or whose bytes and numbers cross between machines. Left out: the laptop's analysis,
# collector, report and self-tests (analysis collect report selftest), whose numbers on arm64 the
# store portability and integration tests check through the executable (docs/packaging.md).
ARM64_TEST_NAMESPACES ?= agent archive capture core formats markers net onset pairing process rt setup sim stats store sync
ARM64_PACKAGES := crossbuild-essential-arm64 g++-aarch64-linux-gnu qemu-user file libc6:arm64 libstdc++6:arm64 \
  libsqlite3-dev:arm64 libfmt-dev:arm64 libcpp-httplib-dev:arm64 libpcap-dev:arm64 libzstd-dev:arm64 liblz4-dev:arm64 libpq-dev:arm64 libgtest-dev:arm64 libgmock-dev:arm64 \
  libtomlplusplus-dev:arm64 libboost-dev:arm64 libboost-math-dev:arm64
PACKAGE_PACKAGES := dpkg-dev help2man debootstrap file sqlite3

deps-arm64: deps
	@if ! dpkg --print-foreign-architectures | grep -qx arm64; then \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  echo "adding the arm64 architecture to dpkg"; $$SUDO dpkg --add-architecture arm64; \
	fi
	$(call install_missing,$(ARM64_PACKAGES))

deps-package: deps
	$(call install_missing,$(PACKAGE_PACKAGES))

cross-arm64: deps-arm64
	$(call step,build $(BUILD_ARM64))
	cmake -S . -B $(BUILD_ARM64) -G Ninja -DCMAKE_TOOLCHAIN_FILE=$(CURDIR)/cmake/toolchain-aarch64.cmake \
	  -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" -DM2MLAT_WERROR=ON -DM2MLAT_BENCH=OFF $(UNITY) \
	  -DM2MLAT_TEST_OPTIMIZE=-O1 \
	  "-DM2MLAT_TEST_NAMESPACES=$(subst $(space),;,$(ARM64_TEST_NAMESPACES))"
	cmake --build $(BUILD_ARM64)

# Unit tests under the emulator (ctest prefixes them with it), the uAPI layout on both architectures,
# the integration subset, and stores crossing between amd64 and arm64.
check-arm64: build cross-arm64
	$(call step,arm64 tests under qemu-aarch64)
	ctest --test-dir $(BUILD_ARM64) --output-on-failure -j2 -L unit
	tests/packaging/abi_layout.sh
	tests/packaging/arm64_integration.sh $(BUILD_ARM64)/m2mlat
	tests/packaging/store_portability.sh $(BUILD)/m2mlat $(BUILD_ARM64)/m2mlat

# $(PKG_DIR)/m2mlat_<version>-1_{amd64,arm64}.deb, and in $(PKG_DIR)/upgrade the amd64 one again with a
# higher version for the upgrade test.
package: build cross-arm64 deps-package
	$(call step,packages)
	rm -rf $(PKG_DIR) && mkdir -p $(PKG_DIR)/upgrade
	cpack --config $(BUILD)/CPackConfig.cmake -B $(PKG_DIR) >$(PKG_DIR)/cpack-amd64.log
	cpack --config $(BUILD_ARM64)/CPackConfig.cmake -B $(PKG_DIR) >$(PKG_DIR)/cpack-arm64.log
	version=$$(sed -n 's/^set(CPACK_PACKAGE_VERSION "\(.*\)")/\1/p' $(BUILD)/CPackConfig.cmake); \
	  cpack --config $(BUILD)/CPackConfig.cmake -B $(PKG_DIR)/upgrade -D CPACK_PACKAGE_VERSION=$$version+upgradetest \
	  >$(PKG_DIR)/cpack-upgrade.log
	rm -rf $(PKG_DIR)/_CPack_Packages $(PKG_DIR)/upgrade/_CPack_Packages
	@ls -l $(PKG_DIR)/*.deb $(PKG_DIR)/upgrade/*.deb

check-package: package
	$(call step,package tests)
	tests/packaging/irq_affinity.sh
	tests/packaging/deb_contents.sh $(PKG_DIR)/m2mlat_*_amd64.deb $(PKG_DIR)/m2mlat_*_arm64.deb
	@if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO tests/packaging/deb_install.sh $(PKG_DIR)/m2mlat_*_amd64.deb $(PKG_DIR)/upgrade/m2mlat_*_amd64.deb

# The parsers' fuzz targets (fuzz/: the agent's requests, the wire, chronyc, pmc, cyclictest): clang's
# libFuzzer in the sanitizer build ($(BUILD_CLANG)), the whole library instrumented, each run for
# FUZZ_TIME seconds from its seed corpus (new inputs go to $(BUILD_CLANG)/corpus). FUZZ_SEED fixes
# libFuzzer's random seed, so that make check explores the same inputs on every run (a finding then
# reproduces, rather than failing one CI run in many); FUZZ_SEED=0 draws a new seed each run.
FUZZ_TIME ?= 15
FUZZ_SEED ?= 1
FUZZ_TARGETS := query_params session_body authorization wire_decode chronyc_output pmc_output cyclictest_output
fuzz: build-clang
	$(call step,fuzz targets)
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p $(BUILD_CLANG)/corpus/$$t && \
	  echo "fuzz_$$t: $(FUZZ_TIME) s" && \
	  ./$(BUILD_CLANG)/fuzz/fuzz_$$t -max_total_time=$(FUZZ_TIME) -seed=$(FUZZ_SEED) -print_final_stats=1 \
	    $(BUILD_CLANG)/corpus/$$t fuzz/corpus/$$t 2> $(BUILD_CLANG)/fuzz_$$t.log || { tail -40 $(BUILD_CLANG)/fuzz_$$t.log; exit 1; }; \
	  grep -E '^stat::number_of_executed_units' $(BUILD_CLANG)/fuzz_$$t.log; \
	done

bench: build
	bench/run.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(BUILD_CLANG) $(BUILD_ARM64) $(PKG_DIR)
