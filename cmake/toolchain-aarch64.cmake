# Cross-compiling m2mlat for 64-bit ARM boards (Raspberry Pi 4/5 with a 64-bit OS) on a Debian amd64
# host with Debian's cross toolchain and multiarch libraries:
#
#   dpkg --add-architecture arm64 && apt-get update
#   apt-get install crossbuild-essential-arm64 qemu-user libsqlite3-dev:arm64 libfmt-dev:arm64 ...
#   cmake -S . -B build-arm64 -G Ninja -DCMAKE_TOOLCHAIN_FILE=cmake/toolchain-aarch64.cmake
#
# There is no separate sysroot: the arm64 -dev packages install their libraries into
# /usr/lib/aarch64-linux-gnu (and their CMake and pkg-config files below it) beside the amd64 ones, and
# their headers into the shared /usr/include. Tests run under QEMU's user-mode emulator
# (CMAKE_CROSSCOMPILING_EMULATOR: ctest and gtest_discover_tests prefix every test program with it).
# docs/packaging.md has the package list, the timings and what runs under emulation.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(M2MLAT_TRIPLET aarch64-linux-gnu)

set(CMAKE_C_COMPILER ${M2MLAT_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${M2MLAT_TRIPLET}-g++)
# find_library and find_package look in /usr/lib/<this>/ (and lib/<this>/cmake), never in the host's
# /usr/lib/x86_64-linux-gnu.
set(CMAKE_LIBRARY_ARCHITECTURE ${M2MLAT_TRIPLET})
# GCC notes on arm64 that passing some aggregates (std::pair<long double, long double> in Boost.Math)
# changed in GCC 10.1: it matters only when linking with code built by older compilers, which the
# package never does.
set(CMAKE_CXX_FLAGS_INIT -Wno-psabi)

# Programs (code generators, pkg-config, strip) are the host's; libraries, headers and packages the
# target's. The cross toolchain's own tree comes first; then the multiarch /usr.
set(CMAKE_FIND_ROOT_PATH /usr/${M2MLAT_TRIPLET} /usr)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# pkg-config (cpp-httplib): only the arm64 .pc files and the architecture-independent ones. Setting
# PKG_CONFIG_LIBDIR replaces the host's default search path instead of adding to it.
set(ENV{PKG_CONFIG_LIBDIR} /usr/lib/${M2MLAT_TRIPLET}/pkgconfig:/usr/share/pkgconfig)
set(ENV{PKG_CONFIG_PATH} "")
set(ENV{PKG_CONFIG_SYSROOT_DIR} "")

# The emulator for tests (and for generating the man pages from the arm64 binary). No -L prefix: the
# program's dynamic loader and its libraries all come from the multiarch arm64 packages
# (/lib/ld-linux-aarch64.so.1, /lib/aarch64-linux-gnu), the same glibc build. The cross toolchain's
# own tree (/usr/aarch64-linux-gnu) is only for linking: its loader is an older glibc build than the
# multiarch libc.so.6 the loader finds, and that pair must never meet (a mismatched ld.so and libc
# share private structures: pthread_create looped forever in a thread-stack list read at the wrong
# offset).
find_program(M2MLAT_QEMU_AARCH64 NAMES qemu-aarch64 qemu-aarch64-static)
if(M2MLAT_QEMU_AARCH64)
  set(CMAKE_CROSSCOMPILING_EMULATOR ${M2MLAT_QEMU_AARCH64})
endif()
