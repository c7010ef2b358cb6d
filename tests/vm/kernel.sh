#!/usr/bin/env bash
# Prepares the guest kernel: prints the folder that holds, for Debian's current 6.1 kernel,
#   vmlinux       the uncompressed ELF image (QEMU boots it through its PVH entry: about 3 s under TCG,
#                 against 7-9 s for the xz-compressed bzImage)
#   configfs.ko   Debian's module (gpio-sim is configured through configfs)
#   gpio-sim.ko   gpio-sim, which Debian does not build (CONFIG_GPIO_SIM unset), built here out of
#                 tree from Debian's own linux-source-6.1 against linux-headers of the same ABI
#   e1000.ko      Debian's module for QEMU's default NIC (the two-guest test, twoguest.sh, networks
#                 its guests with it)
#   i2c-stub.ko, i2c-dev.ko  Debian's modules: an SMBus adapter with a register file at a chosen
#                 address, and /dev/i2c-N for it (the gyroscope tests read an "MPU-6050" there)
#   veth.ko, sch_netem.ko  Debian's modules: virtual Ethernet pairs and netem's delay, for the
#                 packet-capture test across a delayed link (packets.netem)
# Everything is fetched with `apt-get download` and built once into $M2MLAT_VM_CACHE/<abi>/; later runs
# find it there and return at once. Kernel sources are unpacked in a temporary folder and deleted:
# nothing of the kernel ever enters the clone.
#
# Usage: tests/vm/kernel.sh            (prints the folder on stdout; progress goes to stderr)
set -euo pipefail
source "$(dirname "$0")/lib.sh"

ABI=$(kernel_abi)
OUT=$CACHE/$ABI
# Debian's own modules the guests load, as paths below the image package's /lib/modules/<abi>/kernel.
IMAGE_MODULES=(fs/configfs/configfs.ko drivers/net/ethernet/intel/e1000/e1000.ko drivers/i2c/i2c-stub.ko
  drivers/i2c/i2c-dev.ko drivers/net/veth.ko net/sched/sch_netem.ko)
have_modules() {
  local m
  for m in "${IMAGE_MODULES[@]}"; do [ -s "$OUT/$(basename "$m")" ] || return 1; done
}
if [ -s "$OUT/vmlinux" ] && [ -s "$OUT/gpio-sim.ko" ] && have_modules; then
  echo "$OUT"
  exit 0
fi
# A cache filled before a module was added to IMAGE_MODULES needs only the image package again.
BUILT=
[ -s "$OUT/vmlinux" ] && [ -s "$OUT/gpio-sim.ko" ] && BUILT=1

# The headers package puts the kbuild tree in /usr/src and its scripts in /usr/lib/linux-kbuild-6.1;
# it is only needed on the host, to build the module.
if [ -z "$BUILT" ]; then
  ensure_packages "${VM_HOST_PACKAGES[@]}" "linux-headers-$ABI"
  KBUILD=/usr/src/linux-headers-$ABI
  [ -f "$KBUILD/Makefile" ] || die "linux-headers-$ABI is installed but $KBUILD/Makefile is missing"
fi

as_root mkdir -p "$CACHE"
as_root chown "$(id -u):$(id -g)" "$CACHE"
mkdir -p "$CACHE/debs" "$OUT"

# The image package's version (e.g. 6.1.192-2) names the source package's version too: the module
# must be built from the very sources the image was built from.
VERSION=$(apt-cache show "linux-image-$ABI" | sed -n 's/^Version: //p' | head -n1)
[ -n "$VERSION" ] || die "apt-cache knows no package linux-image-$ABI"
IMAGE_DEB=$CACHE/debs/linux-image-${ABI}_${VERSION}_amd64.deb
SOURCE_DEB=$CACHE/debs/linux-source-6.1_${VERSION}_all.deb
(
  cd "$CACHE/debs"
  [ -s "$IMAGE_DEB" ] || { log "downloading linux-image-$ABI $VERSION"; apt_download "linux-image-$ABI=$VERSION"; }
  [ -n "$BUILT" ] || [ -s "$SOURCE_DEB" ] ||
    { log "downloading linux-source-6.1 $VERSION"; apt_download "linux-source-6.1=$VERSION"; }
)

TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# 1. The image: the compressed kernel and the modules, from the package's data (the host's /boot and
#    /lib/modules are not touched).
log "unpacking linux-image-$ABI"
dpkg-deb --fsys-tarfile "$IMAGE_DEB" |
  tar -x -C "$TMP" "./boot/vmlinuz-$ABI" "${IMAGE_MODULES[@]/#/./lib/modules/$ABI/kernel/}"
install_modules() {
  local m
  for m in "${IMAGE_MODULES[@]}"; do
    install -m 0644 "$TMP/lib/modules/$ABI/kernel/$m" "$OUT/$(basename "$m").tmp"
    mv "$OUT/$(basename "$m").tmp" "$OUT/$(basename "$m")"
  done
}
if [ -n "$BUILT" ]; then
  install_modules
  log "kernel $ABI ready in $OUT (modules added)"
  echo "$OUT"
  exit 0
fi

# 2. From the source tarball (streamed out of the .deb, never stored whole): extract-vmlinux, and the
#    three files gpio-sim needs.
log "unpacking the gpio-sim sources and scripts/extract-vmlinux from linux-source-6.1"
SRC=linux-source-6.1
dpkg-deb --fsys-tarfile "$SOURCE_DEB" | tar -x -O "./usr/src/$SRC.tar.xz" |
  tar -xJ -C "$TMP" "$SRC/scripts/extract-vmlinux" "$SRC/drivers/gpio/gpio-sim.c" \
    "$SRC/drivers/gpio/gpiolib.h" "$SRC/kernel/irq/irq_sim.c"

log "extracting the uncompressed vmlinux"
sh "$TMP/$SRC/scripts/extract-vmlinux" "$TMP/boot/vmlinuz-$ABI" >"$TMP/vmlinux"
readelf -h "$TMP/vmlinux" >/dev/null || die "extract-vmlinux did not produce an ELF image"

# 3. gpio-sim as one out-of-tree module: the driver plus the interrupt simulator it depends on
#    (CONFIG_IRQ_SIM is unset too). The driver's source is renamed so that its object does not clash
#    with the module's name. 6.1 does not export irq_to_desc() to modules, so the simulator's one call
#    through it becomes generic_handle_domain_irq(), which is exported and does the same lookup.
log "building gpio-sim.ko against linux-headers-$ABI"
MOD=$TMP/module
mkdir -p "$MOD"
cp "$TMP/$SRC/drivers/gpio/gpio-sim.c" "$MOD/gpio-sim-main.c"
cp "$TMP/$SRC/drivers/gpio/gpiolib.h" "$MOD/gpiolib.h"
sed 's/handle_simple_irq(irq_to_desc(irqnum));/generic_handle_domain_irq(work_ctx->domain, offset);/' \
  "$TMP/$SRC/kernel/irq/irq_sim.c" >"$MOD/irq_sim.c"
grep -q 'generic_handle_domain_irq(work_ctx->domain, offset);' "$MOD/irq_sim.c" ||
  die "irq_sim.c of $VERSION no longer has the call this script rewrites; look at kernel/irq/irq_sim.c"
cat >"$MOD/Kbuild" <<'EOF'
obj-m := gpio-sim.o
gpio-sim-y := gpio-sim-main.o irq_sim.o
EOF
make -s -C "$KBUILD" M="$MOD" -j"$(nproc)" modules >&2
[ -s "$MOD/gpio-sim.ko" ] || die "the module build produced no gpio-sim.ko"

# Move into the cache last, each file whole, so an interrupted run never leaves a half-built cache.
install -m 0644 "$TMP/vmlinux" "$OUT/vmlinux.tmp" && mv "$OUT/vmlinux.tmp" "$OUT/vmlinux"
install_modules
install -m 0644 "$MOD/gpio-sim.ko" "$OUT/gpio-sim.ko.tmp" && mv "$OUT/gpio-sim.ko.tmp" "$OUT/gpio-sim.ko"
log "kernel $ABI ready in $OUT"
echo "$OUT"
