# The two commands of the README, and the steps behind them.
#   make demo   install what is missing, build, run the simulated campaign
#   make check  install what is missing, build with GCC and Clang (warnings are errors), run every test
BUILD ?= build
BUILD_CLANG ?= build-clang
CMAKE_FLAGS ?=

# Debian 12 / Ubuntu 24.04 packages the build and the tests need.
PACKAGES := build-essential cmake ninja-build clang-14 pkg-config \
  libsqlite3-dev sqlite3 libcli11-dev nlohmann-json3-dev libfmt-dev libtomlplusplus-dev \
  libgtest-dev libgmock-dev libbenchmark-dev libboost-math-dev \
  python3 python3-numpy python3-pandas

.PHONY: all deps build build-clang demo check test bench clean

all: build

deps:
	@missing=$$(for p in $(PACKAGES); do dpkg-query -W -f='$${Status}\n' $$p 2>/dev/null | grep -q '^install ok installed' || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "installing: $$missing"; \
	  if [ "$$(id -u)" = 0 ]; then SUDO=; else SUDO=sudo; fi; \
	  $$SUDO apt-get update -qq && DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $$missing; \
	fi

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

bench: build
	bench/run.sh $(BUILD)

clean:
	rm -rf $(BUILD) $(BUILD_CLANG)
