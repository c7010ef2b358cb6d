#!/usr/bin/env bash
# The real-kernel test suite: boots Debian's 6.1 kernel in QEMU with gpio-sim (and i2c-stub), runs the tests of
# guest/tests.sh against the real GPIO character device, and prints one line per test and
# "N passed, N failed" last. Exit 0 only if no test failed and the guest ran to the end.
#
#   tests/vm/run.sh [--m2mlat BINARY]
#
# Steps: host packages (apt-get, once) -> guest kernel, configfs.ko and gpio-sim.ko (kernel.sh, cached
# in $M2MLAT_VM_CACHE) -> m2mlat (CMake, Release, in $M2MLAT_VM_BUILD) and the static test driver
# (g++ -static) -> an initramfs (busybox, modules, the binaries with the shared libraries they load,
# guest/init, guest/tests.sh) -> QEMU with the uncompressed vmlinux through its PVH entry -> the console's
# "M2MLAT-VM ..." lines -> the report.
#
# Environment:
#   M2MLAT_VM_CACHE    downloads and the built kernel module (default /var/cache/m2mlat-vm)
#   M2MLAT_VM_BUILD    build folder of the guest's m2mlat and the driver (default <repo>/build-vm)
#   M2MLAT_VM_ACCEL    tcg (default) or kvm; KVM only where it works (not on PVM-nested hosts)
#   M2MLAT_VM_TIMEOUT  seconds before the guest is killed (default 600)
#   M2MLAT_VM_SMP, M2MLAT_VM_MEM  guest CPUs (default 1, see below) and MiB (default 512)
#   M2MLAT_VM_KERNEL   a kernel ABI name (6.1.0-NN-amd64) instead of the one linux-image-amd64 pulls in
#   M2MLAT_VM_VERBOSE  non-empty: print the details of passing tests too
#   M2MLAT_VM_SKIP     non-empty: skip the whole suite (reported as such)
set -euo pipefail
source "$(dirname "$0")/lib.sh"

parse_vm_args "$@"  # sets M2MLAT_BIN
BUILD=${M2MLAT_VM_BUILD:-$REPO/build-vm}
ACCEL=${M2MLAT_VM_ACCEL:-tcg}
TIMEOUT=${M2MLAT_VM_TIMEOUT:-600}
SMP=${M2MLAT_VM_SMP:-1}
MEM=${M2MLAT_VM_MEM:-512}
SECONDS=0

skip_unless_runnable "real-kernel suite"

ensure_packages "${VM_HOST_PACKAGES[@]}"
KERNEL_DIR=$(bash "$VM_DIR/kernel.sh")

# The guest's m2mlat: its own build folder, so the ordinary builds are untouched. -O2 as the other
# builds (GCC 12 gives false -Wrestrict warnings at -O3); no debug info, to keep the initramfs small.
# It is linked dynamically (cpp-httplib, for one, has no static archive in Debian): the initramfs
# carries the shared libraries it loads, from this host, which is the guest kernel's Debian release.
mkdir -p "$BUILD"
if [ -z "$M2MLAT_BIN" ]; then
  # The compiler's output goes to a log, shown only when the build fails. Compilations go through
  # ccache, its cache beside the kernel's: CI builds a fresh clone each time, and this build (the whole
  # project once more) would otherwise cost minutes on every run. The base folder makes the hits
  # independent of where the clone is.
  BUILD_LOG=$BUILD/build.log
  export CCACHE_DIR=$CACHE/ccache CCACHE_BASEDIR=$REPO CCACHE_NOHASHDIR=true
  if [ ! -f "$BUILD/build.ninja" ]; then
    log "configuring the guest's build in $BUILD"
    cmake -S "$REPO" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" \
      -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DM2MLAT_TESTS=OFF -DM2MLAT_BENCH=OFF \
      >"$BUILD_LOG" 2>&1 ||
      { tail -n 40 "$BUILD_LOG" >&2; die "configuring the guest's build failed (log: $BUILD_LOG)"; }
  fi
  log "building the guest's m2mlat (log: $BUILD_LOG)"
  cmake --build "$BUILD" --target m2mlat_exe >"$BUILD_LOG" 2>&1 ||
    { grep -v '^\[[0-9]*/[0-9]*\] ' "$BUILD_LOG" | tail -n 40 >&2; die "building the guest's m2mlat failed"; }
  M2MLAT_BIN=$BUILD/m2mlat
fi
DRIVER_BIN=$BUILD/m2mlat-vm-driver
if [ ! -x "$DRIVER_BIN" ] || [ "$VM_DIR/driver.cpp" -nt "$DRIVER_BIN" ]; then
  log "building the test driver"
  g++ -std=c++20 -O2 -static -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion \
    -Wold-style-cast -Werror -o "$DRIVER_BIN" "$VM_DIR/driver.cpp"
fi

GYRO_BIN=$BUILD/m2mlat-vm-gyro
if [ ! -x "$GYRO_BIN" ] || [ "$VM_DIR/gyro_driver.cpp" -nt "$GYRO_BIN" ]; then
  log "building the gyroscope test driver"
  g++ -std=c++20 -O2 -static -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion \
    -Wold-style-cast -Werror -o "$GYRO_BIN" "$VM_DIR/gyro_driver.cpp"
fi

TRAFFIC_BIN=$BUILD/m2mlat-vm-traffic
if [ ! -x "$TRAFFIC_BIN" ] || [ "$VM_DIR/netem_traffic.cpp" -nt "$TRAFFIC_BIN" ]; then
  log "building the netem test's traffic program"
  g++ -std=c++20 -O2 -static -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion \
    -Wold-style-cast -Werror -o "$TRAFFIC_BIN" "$VM_DIR/netem_traffic.cpp"
fi

# The initramfs: an uncompressed cpio (the kernel would spend seconds decompressing under TCG).
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
ROOT=$WORK/root
mkdir -p "$ROOT"/{bin,dev,proc,sys,tmp,lib/modules}
cp /bin/busybox "$ROOT/bin/busybox"
file_is_static() { ! readelf -l "$1" | grep -q 'Requesting program interpreter'; }
file_is_static "$ROOT/bin/busybox" || die "/bin/busybox is not static (install busybox-static)"
# install_libraries BINARY [LIBRARY_PATH]: the shared libraries BINARY loads (and the dynamic loader),
# each at its own path in the guest.
install_libraries() {
  LD_LIBRARY_PATH=${2:-} ldd "$1" |
    awk '$2 == "=>" && $3 ~ /^\// { print $3 } $1 ~ /^\/.*ld-linux/ { print $1 }' |
    while read -r lib; do
      [ -e "$ROOT/${lib#"${3:-}"}" ] || install -D -m 0755 "$(readlink -f "$lib")" "$ROOT/${lib#"${3:-}"}"
    done
}
strip -o "$ROOT/bin/m2mlat" "$M2MLAT_BIN"
install_libraries "$M2MLAT_BIN"
cp "$DRIVER_BIN" "$ROOT/bin/m2mlat-vm-driver"
cp "$GYRO_BIN" "$ROOT/bin/m2mlat-vm-gyro"
cp "$TRAFFIC_BIN" "$ROOT/bin/m2mlat-vm-traffic"
cp "$KERNEL_DIR/configfs.ko" "$KERNEL_DIR/gpio-sim.ko" "$KERNEL_DIR/i2c-stub.ko" "$KERNEL_DIR/i2c-dev.ko" \
  "$KERNEL_DIR/veth.ko" "$KERNEL_DIR/sch_netem.ko" "$ROOT/lib/modules/"
# The netem test's ip and tc: the host's iproute2 (the guest kernel's Debian release; busybox's tc has
# no netem), with their libraries. `ip netns` keeps its namespaces in /run/netns.
mkdir -p "$ROOT/usr/sbin" "$ROOT/run"
for tool in ip tc; do
  cp "/usr/sbin/$tool" "$ROOT/usr/sbin/$tool"
  install_libraries "/usr/sbin/$tool"
done
install -m 0755 "$VM_DIR/guest/init" "$ROOT/init"

# Debian's gpiomon (gpiod 1.6, dynamically linked), for the performance comparison: its packages
# fetched into the cache once, its C library from the host (the same Debian release), each library at
# its own path in the guest. Without it that one test is skipped.
add_gpiomon() {
  local x=$WORK/gpiod p deb lib
  mkdir -p "$x"
  for p in gpiod libgpiod2; do
    deb=$(ls -1 "$CACHE/debs/${p}"_*_amd64.deb 2>/dev/null | tail -n1)
    if [ -z "$deb" ]; then
      (cd "$CACHE/debs" && apt_download "$p") || return 1
      deb=$(ls -1 "$CACHE/debs/${p}"_*_amd64.deb | tail -n1)
    fi
    dpkg-deb -x "$deb" "$x"
  done
  install -D -m 0755 "$x/usr/bin/gpiomon" "$ROOT/bin/gpiomon"
  install_libraries "$x/usr/bin/gpiomon" "$x/usr/lib/x86_64-linux-gnu" "$x"
}
add_gpiomon || log "gpiomon unavailable: the performance comparison will be skipped"
cp "$VM_DIR/guest/tests.sh" "$ROOT/tests.sh"
(cd "$ROOT" && find . -print0 | cpio --null -o -H newc --quiet) >"$WORK/initramfs.cpio"

# Boot. One guest CPU by default: the edge's interrupt thread (SCHED_FIFO) then runs before the
# driver's next write, whatever the host does. With two, the host may deschedule the vCPU thread that
# runs it for milliseconds while the other vCPU goes on writing, and gpio-sim drops edges that arrive
# while the interrupt is still masked (invisibly: seqno counts events, not edges). panic=-1 and
# -no-reboot turn a kernel panic into QEMU's exit; the timeout catches a hang.
CONSOLE=$BUILD/vm-console.log
log "booting $(basename "$KERNEL_DIR") under QEMU ($ACCEL, $SMP CPUs, $MEM MiB); console in $CONSOLE"
case $ACCEL in
  tcg) ACCEL_ARGS=(-accel tcg,thread=multi -cpu max) ;;
  kvm) ACCEL_ARGS=(-accel kvm -cpu host) ;;
  *) die "M2MLAT_VM_ACCEL must be tcg or kvm" ;;
esac
BOOT_START=$SECONDS
set +e
timeout --foreground -k 10 "$TIMEOUT" qemu-system-x86_64 "${ACCEL_ARGS[@]}" -smp "$SMP" -m "$MEM" \
  -nographic -no-reboot -net none -kernel "$KERNEL_DIR/vmlinux" -initrd "$WORK/initramfs.cpio" \
  -append 'console=ttyS0 quiet panic=-1' </dev/null >"$CONSOLE" 2>&1
QEMU_RC=$?
set -e
# Serial lines end in CR LF; a result line may follow other output on the same line (the firmware's).
tr -d '\r' <"$CONSOLE" | sed 's/^.\{1,\}\(M2MLAT-VM [A-Z]\)/\1/' >"$CONSOLE.tmp" && mv "$CONSOLE.tmp" "$CONSOLE"

# The report: the guest's result lines, its details for the tests that did not pass.
passed=0 failed=0 skipped=0
declare -A details
while IFS= read -r line; do
  case $line in
    "M2MLAT-VM INFO "*)
      rest=${line#M2MLAT-VM INFO }
      name=${rest%%: *}
      details[$name]+="      ${rest#*: }"$'\n' ;;
    "M2MLAT-VM PASS "* | "M2MLAT-VM FAIL "* | "M2MLAT-VM SKIP "*)
      read -r _ result name secs <<<"$line"
      printf '%s %-28s %6s s\n' "$result" "$name" "$secs"
      case $result in
        PASS) passed=$((passed + 1)) ;;
        FAIL) failed=$((failed + 1)); printf '%s' "${details[$name]:-}" ;;
        SKIP) skipped=$((skipped + 1)); printf '%s' "${details[$name]:-}" | head -n 1 ;;
      esac
      [ -n "${M2MLAT_VM_VERBOSE:-}" ] && [ "$result" = PASS ] && printf '%s' "${details[$name]:-}"
      ;;
  esac
done <"$CONSOLE"

if ! grep -q '^M2MLAT-VM END' "$CONSOLE"; then
  failed=$((failed + 1))
  echo "FAIL guest: did not run to the end (qemu exit $QEMU_RC after $((SECONDS - BOOT_START)) s); last console lines:"
  tail -n 20 "$CONSOLE" | sed 's/^/      /'
fi
echo "guest time $((SECONDS - BOOT_START)) s, total $SECONDS s; $skipped skipped"
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ] && [ "$passed" -gt 0 ]
