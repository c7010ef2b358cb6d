#!/usr/bin/env bash
# The amd64 package on a clean Debian 12: installs into a minimal bookworm root (debootstrap) with its
# Depends resolved by apt inside it, runs, keeps recorded data across an upgrade, a remove and a
# purge, and its systemd unit passes `systemd-analyze verify` there.
#
#   tests/packaging/deb_install.sh PACKAGE.deb NEWER_PACKAGE.deb
#
# NEWER_PACKAGE.deb is the same build packaged with a higher version (cpack -D CPACK_PACKAGE_VERSION=..).
# Needs root (chroot, mounts). Caches, in $M2MLAT_DEBOOTSTRAP_CACHE (default /var/cache/m2mlat-debootstrap):
#   bookworm-minbase.tgz   debootstrap --make-tarball: the packages of the minimal root
#   bookworm-root.tar      the root once debootstrap has finished, with systemd and fresh apt lists (warm
#                          runs unpack this in seconds; delete it to start from the tarball again)
#   archives/              the .debs apt fetched inside the root (the package's Depends)
# The mirror is the one this machine's apt uses for bookworm (or $M2MLAT_DEBIAN_MIRROR).
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 PACKAGE.deb NEWER_PACKAGE.deb" >&2; exit 2; }
DEB=$(realpath "$1")
NEWER=$(realpath "$2")
CACHE=${M2MLAT_DEBOOTSTRAP_CACHE:-/var/cache/m2mlat-debootstrap}
SUITE=bookworm
SECONDS=0
log() { echo "[deb_install ${SECONDS}s] $*"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
[ "$(id -u)" = 0 ] || fail "needs root (debootstrap, chroot)"
command -v debootstrap >/dev/null || fail "debootstrap is missing (apt-get install debootstrap)"

# The mirror apt already uses for the suite: a URI from the sources whose lists apt has fetched.
find_mirror() {
  local uri name
  for uri in $(sed -n -e 's/^deb \(\[[^]]*\] \)\{0,1\}\([a-z]*:\/\/[^ ]*\).*/\2/p' -e 's/^URIs: *//p' \
               /etc/apt/sources.list /etc/apt/sources.list.d/*.list /etc/apt/sources.list.d/*.sources 2>/dev/null); do
    name=${uri#*://}
    name=${name%/}
    if [ -e "/var/lib/apt/lists/${name//\//_}_dists_${SUITE}_InRelease" ]; then
      echo "${uri%/}"
      return
    fi
  done
  echo http://deb.debian.org/debian
}
MIRROR=${M2MLAT_DEBIAN_MIRROR:-$(find_mirror)}

ROOT=$(mktemp -d /var/tmp/m2mlat-deb-root.XXXXXX)
AGENT_PID=
cleanup() {
  [ -z "$AGENT_PID" ] || kill "$AGENT_PID" 2>/dev/null || true
  for m in "$ROOT/var/cache/apt/archives" "$ROOT/dev/pts" "$ROOT/dev" "$ROOT/proc"; do
    mountpoint -q "$m" && umount -l "$m"
  done
  rm -rf --one-file-system "$ROOT"
}
trap cleanup EXIT
in_root() { chroot "$ROOT" "$@"; }

mkdir -p "$CACHE/archives/partial"
if [ -f "$CACHE/$SUITE-root.tar" ]; then
  log "unpacking the cached root"
  tar -C "$ROOT" -xf "$CACHE/$SUITE-root.tar"
else
  if [ ! -f "$CACHE/$SUITE-minbase.tgz" ]; then
    log "debootstrap --make-tarball from $MIRROR"
    scratch=$(mktemp -d /var/tmp/m2mlat-debootstrap.XXXXXX)
    debootstrap --variant=minbase --make-tarball="$CACHE/$SUITE-minbase.tgz.part" "$SUITE" "$scratch" "$MIRROR" \
      >"$CACHE/debootstrap.log" 2>&1 || { tail -n 20 "$CACHE/debootstrap.log" >&2; fail "debootstrap --make-tarball"; }
    rm -rf "$scratch"
    mv "$CACHE/$SUITE-minbase.tgz.part" "$CACHE/$SUITE-minbase.tgz"
  fi
  log "debootstrap --unpack-tarball"
  debootstrap --variant=minbase --unpack-tarball="$CACHE/$SUITE-minbase.tgz" "$SUITE" "$ROOT" "$MIRROR" \
    >"$CACHE/debootstrap.log" 2>&1 || { tail -n 20 "$CACHE/debootstrap.log" >&2; fail "debootstrap"; }
  cp /etc/resolv.conf "$ROOT/etc/resolv.conf"
  in_root apt-get -o APT::Sandbox::User=root update -qq >/dev/null || fail "apt-get update in the root"
  # systemd, as on a board: the unit is verified against it, in the root.
  log "installing systemd into the root"
  DEBIAN_FRONTEND=noninteractive in_root apt-get install -y -qq --no-install-recommends systemd \
    >"$CACHE/root-systemd.log" 2>&1 || { tail -n 20 "$CACHE/root-systemd.log" >&2; fail "installing systemd"; }
  in_root apt-get clean
  tar -C "$ROOT" -cf "$CACHE/$SUITE-root.tar.part" . && mv "$CACHE/$SUITE-root.tar.part" "$CACHE/$SUITE-root.tar"
fi
# The root's "/": mktemp made it 0700 (and the cached tar keeps that), which only root could enter.
chmod 755 "$ROOT"
cp /etc/resolv.conf "$ROOT/etc/resolv.conf"
mount -t proc proc "$ROOT/proc"
mount --bind /dev "$ROOT/dev"
mount --bind "$CACHE/archives" "$ROOT/var/cache/apt/archives"
cp "$DEB" "$NEWER" "$ROOT/tmp/"
PKG=/tmp/$(basename "$DEB")
NEWPKG=/tmp/$(basename "$NEWER")
export DEBIAN_FRONTEND=noninteractive
apt_in_root() {
  in_root apt-get -o Dpkg::Use-Pty=0 -o APT::Keep-Downloaded-Packages=true -y -qq "$@" >"$ROOT/tmp/apt.log" 2>&1 ||
    { tail -n 30 "$ROOT/tmp/apt.log" >&2; fail "apt-get $* in the root"; }
}

log "installing $(basename "$DEB") with its Depends"
apt_in_root install --no-install-recommends "$PKG"
[ "$(in_root m2mlat --version)" = "m2mlat $(dpkg-deb -f "$DEB" Version | sed 's/-[^-]*$//')" ] ||
  fail "m2mlat --version in the root: $(in_root m2mlat --version)"
in_root getent passwd m2mlat >/dev/null || fail "no user m2mlat"
grep -qw gpio <<<"$(in_root id -nG m2mlat)" || fail "m2mlat is not in the group gpio"
[ "$(in_root stat -c '%U:%G %a' /var/lib/m2mlat)" = "m2mlat:m2mlat 750" ] ||
  fail "/var/lib/m2mlat is $(in_root stat -c '%U:%G %a' /var/lib/m2mlat)"
for f in /usr/lib/systemd/system/m2mlat-agent@.service /usr/lib/udev/rules.d/60-m2mlat-gpio.rules \
         /usr/libexec/m2mlat/irq-affinity /etc/m2mlat/agent.toml.example /usr/share/man/man1/m2mlat.1.gz \
         /usr/share/man/man1/m2mlat-record.1.gz /usr/share/bash-completion/completions/m2mlat; do
  [ -e "$ROOT$f" ] || fail "$f is not installed"
done

log "smoke run: m2mlat demo; the example configuration with the simulated source"
in_root m2mlat demo >"$ROOT/tmp/demo.txt" 2>&1 || { cat "$ROOT/tmp/demo.txt" >&2; fail "m2mlat demo in the root"; }
in_root sh -c 'cd /tmp && m2mlat record --config /etc/m2mlat/agent.toml.example --source sim --count 5 --store example.db --quiet' \
  >/dev/null || fail "the example configuration does not load"

log "the unit's command as the user m2mlat (simulated source), stopped by SIGTERM"
# chroot and sh exec, so $! is the agent itself (not through in_root: a function in the background
# is a subshell, and SIGTERM would end that instead).
chroot "$ROOT" chroot --userspec=m2mlat:m2mlat / sh -c 'cd /var/lib/m2mlat && exec m2mlat agent \
  --config /etc/m2mlat/agent.toml.example --store /var/lib/m2mlat/smoke.db --listen 127.0.0.1:0 --source sim' \
  >"$ROOT/tmp/agent.out" 2>"$ROOT/tmp/agent.err" &
AGENT_PID=$!
for _ in $(seq 100); do grep -q '^listening ' "$ROOT/tmp/agent.out" && break; sleep 0.2; done
grep -q '^listening 127.0.0.1:' "$ROOT/tmp/agent.out" || { cat "$ROOT/tmp/agent.err" >&2; fail "the agent did not start"; }
sleep 1
kill -TERM "$AGENT_PID"
wait "$AGENT_PID" || { cat "$ROOT/tmp/agent.err" >&2; fail "the agent did not stop cleanly on SIGTERM"; }
AGENT_PID=
[ "$(in_root stat -c %U /var/lib/m2mlat/smoke.db)" = m2mlat ] || fail "the agent's store is not the user m2mlat's"
rm -f "$ROOT"/var/lib/m2mlat/smoke.db*

log "systemd-analyze verify on an instance of the unit, in the root"
# --man=no: the root has no man-db; deb_contents.sh checks the pages.
verify_out=$(in_root systemd-analyze verify --man=no /usr/lib/systemd/system/m2mlat-agent@vehicle.service 2>&1) ||
  { echo "$verify_out" >&2; fail "systemd-analyze verify"; }
[ -z "$verify_out" ] || { echo "$verify_out" >&2; fail "systemd-analyze verify warns about the unit"; }

log "recording data as the agent's user into /var/lib/m2mlat"
in_root chroot --userspec=m2mlat:m2mlat / sh -c \
  'cd /var/lib/m2mlat && m2mlat simulate --seed 5 --store vehicle.db >/dev/null && m2mlat export vehicle.db -o -' \
  >"$ROOT/tmp/before.csv" || fail "recording as m2mlat"
[ "$(wc -l <"$ROOT/tmp/before.csv")" -gt 10 ] || fail "the recorded store is empty"
echo "# edited by the administrator" >>"$ROOT/etc/m2mlat/agent.toml.example"
echo 'node = "vehicle"' >"$ROOT/etc/m2mlat/vehicle.toml"
same_data() {  # same_data WHEN
  [ -f "$ROOT/var/lib/m2mlat/vehicle.db" ] || fail "$1: /var/lib/m2mlat/vehicle.db is gone"
  [ "$(in_root stat -c %U /var/lib/m2mlat/vehicle.db)" = m2mlat ] || fail "$1: the store changed owner"
  [ -f "$ROOT/etc/m2mlat/vehicle.toml" ] || fail "$1: /etc/m2mlat/vehicle.toml is gone"
  # Read with the host's own sqlite3 when the package (and its m2mlat) is gone.
  if [ -x "$ROOT/usr/bin/m2mlat" ]; then
    in_root m2mlat export /var/lib/m2mlat/vehicle.db -o - >"$ROOT/tmp/after.csv"
    cmp -s "$ROOT/tmp/before.csv" "$ROOT/tmp/after.csv" || fail "$1: the store's events changed"
  else
    # The export's rows: all but its header (m2mlat-events/2: scenario, session and label first).
    [ "$(sqlite3 "$ROOT/var/lib/m2mlat/vehicle.db" 'SELECT count(*) FROM events')" -eq \
      "$(grep -cvE '^(#|scenario,session,label,node,)' "$ROOT/tmp/before.csv")" ] || fail "$1: the store's events changed"
  fi
}

log "upgrading to $(basename "$NEWER")"
apt_in_root install --no-install-recommends "$NEWPKG"
[ "$(in_root dpkg-query -W -f='${Version}' m2mlat)" = "$(dpkg-deb -f "$NEWER" Version)" ] || fail "not upgraded"
same_data "after the upgrade"
grep -q 'edited by the administrator' "$ROOT/etc/m2mlat/agent.toml.example" ||
  fail "the upgrade replaced the edited conffile"

log "removing"
apt_in_root remove m2mlat
[ ! -e "$ROOT/usr/bin/m2mlat" ] || fail "/usr/bin/m2mlat is still there after remove"
same_data "after remove"
[ -f "$ROOT/etc/m2mlat/agent.toml.example" ] || fail "remove deleted the conffile (only purge may)"

log "purging"
apt_in_root purge m2mlat
same_data "after purge"
[ ! -e "$ROOT/etc/m2mlat/agent.toml.example" ] || fail "purge left the conffile"

log "reinstalling over the kept data"
apt_in_root install --no-install-recommends "$PKG"
same_data "after reinstalling"
log "passed"
