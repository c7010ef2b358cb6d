# Shared by the real-kernel test scripts (sourced, not run): where things live, and small shell functions.
#
# The suite boots Debian's own 6.1 kernel in QEMU and needs three things that must never be committed
# (the kernel image, its sources, and a module built from them); they are fetched from Debian's archive
# at test time and cached OUTSIDE the clone, in $M2MLAT_VM_CACHE, keyed by the kernel's ABI name, so a
# second run downloads and builds nothing.

VM_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
REPO=$(cd "$VM_DIR/../.." && pwd)
CACHE=${M2MLAT_VM_CACHE:-/var/cache/m2mlat-vm}

# Host packages: QEMU, the guest's userland (busybox), the tools to unpack Debian's kernel packages and
# to pack the initramfs, the compiler for the module, the guest's m2mlat and the static driver, and ccache.
VM_HOST_PACKAGES=(qemu-system-x86 busybox-static cpio xz-utils kmod binutils gzip build-essential iproute2
  ccache libsqlite3-dev libfmt-dev libcpp-httplib-dev libpcap-dev libzstd-dev liblz4-dev libpq-dev)

log() { printf '[vm %s] %s\n' "$(date +%H:%M:%S)" "$*" >&2; }
die() { printf '[vm] error: %s\n' "$*" >&2; exit 1; }

# as_root CMD...: runs CMD as root (directly when we are root, else through sudo).
as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi
}

# ensure_packages PKG...: installs, with apt-get, those of the packages that are not installed yet.
ensure_packages() {
  local missing=() p
  for p in "$@"; do
    dpkg-query -W -f='${Status}\n' "$p" 2>/dev/null | grep -q '^install ok installed' || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  log "installing host packages: ${missing[*]}"
  as_root apt-get update -qq
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
}

# apt_download PKG[=VERSION]...: apt-get download into the current folder, quietly. As root, apt
# would drop to its _apt user and warn that it cannot write the cache folder; it downloads as root.
apt_download() {
  if [ "$(id -u)" = 0 ]; then
    apt-get download -q -o APT::Sandbox::User=root "$@" >&2
  else
    apt-get download -q "$@" >&2
  fi
}

# kernel_abi: the ABI name of the kernel Debian's metapackage linux-image-amd64 pulls in today
# (e.g. 6.1.0-56-amd64). M2MLAT_VM_KERNEL pins another one.
kernel_abi() {
  if [ -n "${M2MLAT_VM_KERNEL:-}" ]; then
    echo "$M2MLAT_VM_KERNEL"
    return
  fi
  local abi
  abi=$(apt-cache depends linux-image-amd64 2>/dev/null | sed -n 's/^ *Depends: linux-image-\(6\.1\.[0-9]*-[0-9]*-amd64\)$/\1/p' | head -n1)
  [ -n "$abi" ] || die "cannot tell which 6.1 kernel linux-image-amd64 pulls in (apt-cache depends linux-image-amd64); is this Debian 12 with its archive in sources.list?"
  echo "$abi"
}

# skip_unless_runnable NAME: where NAME cannot run, says so, passes nothing and exits 0:
# M2MLAT_VM_SKIP=1, or a system whose archive has no Debian 6.1 kernel (Ubuntu, say).
skip_unless_runnable() {
  local reason=""
  if [ -n "${M2MLAT_VM_SKIP:-}" ]; then
    reason="M2MLAT_VM_SKIP is set"
  elif [ -z "${M2MLAT_VM_KERNEL:-}" ] && ! apt-cache depends linux-image-amd64 2>/dev/null | grep -q 'Depends: linux-image-6\.1\.'; then
    reason="the apt archive has no Debian 6.1 kernel (linux-image-amd64); it needs Debian 12's"
  fi
  [ -z "$reason" ] && return 0
  echo "SKIP $1: $reason"
  echo "0 passed, 0 failed"
  exit 0
}

# parse_vm_args ARGS...: the arguments of both VM scripts: --m2mlat PATH (sets M2MLAT_BIN), --help
# (prints the calling script's header comment).
parse_vm_args() {
  M2MLAT_BIN=""
  while [ $# -gt 0 ]; do
    case $1 in
      --m2mlat) M2MLAT_BIN=$(realpath "$2"); shift 2 ;;
      -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
      *) die "unknown argument '$1' (see --help)" ;;
    esac
  done
}
