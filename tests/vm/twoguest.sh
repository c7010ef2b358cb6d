#!/usr/bin/env bash
# The two-guest test: two QEMU guests, two kernels and two independent clocks on one machine, as two
# boards of a rig. Each guest runs m2mlat agent on a gpio-sim chip (line 0 "latency", line 1 "pulse");
# the operator guest serves its clock with chronyd (`local stratum 5`), the vehicle guest follows it
# over the guests' own network; m2mlat collect on the HOST pulls both agents into campaign stores.
# The host, the one clock the guests share, triggers the edges in physical time (twoguest/trigger.cpp):
# the operator's latency edge, the vehicle's one DELAY later, and a pulse on both at once. Then:
#   coref   chrony co-referenced: pairs ~ DELAY, synctest offset ~ 0, every pair with a finite,
#           plausible uncertainty from both guests' clock samples (chrony and adjtimex);
#   auto    chronyd stopped on both, the vehicle's clock stepped OFFSET ahead (clock_adjtime
#           ADJ_SETOFFSET): the vehicle's agent records the step and the analysis corrects it, so
#           pairs ~ DELAY (each flagged corrected), while the synctest, on the raw clocks, ~ OFFSET.
# Prints one line per check and "N passed, N failed" last; exit 0 only if none failed.
#
#   tests/vm/twoguest.sh [--m2mlat BINARY]
#
# Environment (besides run.sh's M2MLAT_VM_CACHE, M2MLAT_VM_BUILD, M2MLAT_VM_KERNEL, M2MLAT_VM_SKIP):
#   M2MLAT_2G_DELAY_US    the true latency (default 50000 us)
#   M2MLAT_2G_OFFSET_NS   the vehicle's clock offset in the autonomous phase (default 5000000 ns)
#   M2MLAT_2G_CYCLES      stimulus cycles per phase, 500 ms each (default 40)
#   M2MLAT_2G_MEAN_TOL_US largest |error| of the median latency and the median pulse offset (default 1500 us)
#   M2MLAT_2G_TOL_US      at least half the latencies and pulse offsets within this (default 2000 us)
#   M2MLAT_2G_MAX_US      every latency and pulse offset within this (default 150000 us: a pair or
#                         pulse matched with the wrong cycle is 500 ms off)
#   M2MLAT_2G_TIMEOUT     seconds for the whole guest part (default 300)
#   M2MLAT_2G_KEEP        non-empty: keep the work folder (stores, logs) and print its path
set -euo pipefail
source "$(dirname "$0")/lib.sh"

parse_vm_args "$@"  # sets M2MLAT_BIN
BUILD=${M2MLAT_VM_BUILD:-$REPO/build-vm}
DELAY_US=${M2MLAT_2G_DELAY_US:-50000}
OFFSET_NS=${M2MLAT_2G_OFFSET_NS:-5000000}
CYCLES=${M2MLAT_2G_CYCLES:-40}
PERIOD_MS=500
# Tolerances (us), from the delivery jitter of the trigger bytes measured on a loaded 2-core host
# (docs/testing.md): most within a millisecond or two, a tail to tens of ms when the host is busy.
TOL_US=${M2MLAT_2G_TOL_US:-2000}
MEAN_TOL_US=${M2MLAT_2G_MEAN_TOL_US:-1500}
MAX_US=${M2MLAT_2G_MAX_US:-150000}
TIMEOUT=${M2MLAT_2G_TIMEOUT:-300}
SECONDS=0

skip_unless_runnable "two-guest test"

# chrony: the guests run the host's chronyd and chronyc (Debian 12's 4.3) with the host's libraries.
# python3 judges the results (twoguest/judge.py, standard library only); ss (iproute2) finds free ports.
ensure_packages "${VM_HOST_PACKAGES[@]}" chrony python3 iproute2
KERNEL_DIR=$(bash "$VM_DIR/kernel.sh")
mkdir -p "$BUILD"
if [ -z "$M2MLAT_BIN" ]; then
  # As run.sh: the guest's m2mlat from its own build folder (Release, -O2, through ccache).
  export CCACHE_DIR=$CACHE/ccache CCACHE_BASEDIR=$REPO CCACHE_NOHASHDIR=true
  [ -f "$BUILD/build.ninja" ] ||
    cmake -S "$REPO" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O2 -DNDEBUG" \
      -DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DM2MLAT_TESTS=OFF -DM2MLAT_BENCH=OFF >"$BUILD/build-2g.log" 2>&1 ||
    { tail -n 40 "$BUILD/build-2g.log" >&2; die "configuring the guest's build failed"; }
  log "building the guest's m2mlat (log: $BUILD/build-2g.log)"
  cmake --build "$BUILD" --target m2mlat_exe >"$BUILD/build-2g.log" 2>&1 ||
    { tail -n 40 "$BUILD/build-2g.log" >&2; die "building the guest's m2mlat failed"; }
  M2MLAT_BIN=$BUILD/m2mlat
fi
# The guest programs are static (no libraries to carry); the trigger runs on the host.
WARN=(-std=c++20 -O2 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Wold-style-cast -Werror)
for prog in stimulus shift_clock trigger; do
  bin=$BUILD/m2mlat-2g-${prog//_/-}
  if [ ! -x "$bin" ] || [ "$VM_DIR/twoguest/$prog.cpp" -nt "$bin" ]; then
    static=-static
    [ $prog = trigger ] && static=
    g++ "${WARN[@]}" $static -o "$bin" "$VM_DIR/twoguest/$prog.cpp"
  fi
done

WORK=$(mktemp -d)
QEMU_PIDS=()
COLLECT_PID=""
WATCHDOG=""
cleanup() {
  local p
  [ -z "$WATCHDOG" ] || kill "$WATCHDOG" 2>/dev/null || true
  [ -z "$COLLECT_PID" ] || kill "$COLLECT_PID" 2>/dev/null || true
  for p in "${QEMU_PIDS[@]}"; do kill "$p" 2>/dev/null || true; done
  wait 2>/dev/null || true
  if [ -n "${M2MLAT_2G_KEEP:-}" ]; then echo "work folder kept: $WORK"; else rm -rf "$WORK"; fi
}
trap cleanup EXIT

# ---- the initramfs (one for both guests; the role comes from the kernel command line) --------------
ROOT=$WORK/root
mkdir -p "$ROOT"/{bin,dev,proc,sys,tmp,run,etc,usr/bin,usr/sbin,var/lib,lib/modules}
cp /bin/busybox "$ROOT/bin/busybox"
readelf -l "$ROOT/bin/busybox" | grep -q 'Requesting program interpreter' && die "/bin/busybox is not static (install busybox-static)"
# install_libraries BINARY: the shared libraries BINARY loads and the dynamic loader, each at its own path.
install_libraries() {
  ldd "$1" | awk '$2 == "=>" && $3 ~ /^\// { print $3 } $1 ~ /^\/.*ld-linux/ { print $1 }' |
    while read -r lib; do
      [ -e "$ROOT/$lib" ] || install -D -m 0755 "$(readlink -f "$lib")" "$ROOT/$lib"
    done
}
strip -o "$ROOT/bin/m2mlat" "$M2MLAT_BIN"
install_libraries "$M2MLAT_BIN"
cp /usr/sbin/chronyd "$ROOT/usr/sbin/chronyd"
cp /usr/bin/chronyc "$ROOT/usr/bin/chronyc"
install_libraries /usr/sbin/chronyd
install_libraries /usr/bin/chronyc
cp "$BUILD/m2mlat-2g-stimulus" "$BUILD/m2mlat-2g-shift-clock" "$ROOT/bin/"
cp "$KERNEL_DIR/configfs.ko" "$KERNEL_DIR/gpio-sim.ko" "$KERNEL_DIR/e1000.ko" "$ROOT/lib/modules/"
install -m 0755 "$VM_DIR/twoguest/init" "$ROOT/init"
cp "$VM_DIR/twoguest/serve.sh" "$ROOT/serve.sh"
# chronyd looks its user up (-u root) in /etc/passwd.
echo 'root:x:0:0:root:/root:/bin/sh' >"$ROOT/etc/passwd"
echo 'root:x:0:' >"$ROOT/etc/group"
# The agents listen on the user network's address, not loopback, so they need a bearer token.
TOKEN_FILE=$WORK/token
(umask 077; od -An -N16 -tx1 /dev/urandom | tr -d ' \n' >"$TOKEN_FILE")  # a secret: the agent and collect refuse a token others can read
install -m 0600 "$TOKEN_FILE" "$ROOT/etc/m2mlat-token"
(cd "$ROOT" && find . -print0 | cpio --null -o -H newc --quiet) >"$WORK/initramfs.cpio"

# ---- ports: seven free TCP ports on the host's loopback --------------------------------------------
free_ports() {
  local used picked=() p
  used=$(ss -Htan | awk '{ n = split($4, a, ":"); print a[n] }' | sort -u)
  while [ ${#picked[@]} -lt "$1" ]; do
    p=$((20000 + RANDOM % 40000))
    grep -qx "$p" <<<"$used" || [[ " ${picked[*]} " == *" $p "* ]] || picked+=("$p")
  done
  echo "${picked[@]}"
}
read -r LAN_PORT STIM_OP STIM_VEH CTL_OP CTL_VEH API_OP API_VEH <<<"$(free_ports 7)"

# ---- the guests -------------------------------------------------------------------------------------
# qemu_guest ROLE N LAN_NETDEV STIM_PORT CTL_PORT API_PORT: ttyS0 the console (a file), ttyS1 the
# stimulus and ttyS2 the commands (TCP chardevs the host connects to; nodelay: a trigger is one byte),
# NIC 1 the guests' own link (a QEMU socket netdev), NIC 2 QEMU's user network, with only the agent's
# port forwarded from the host's loopback (restrict=on: the guest reaches nothing else).
# preempt=full: Debian's kernel preempts voluntarily by default, and the stimulus program (SCHED_FIFO)
# should not wait behind the agent's kernel work, which TCG stretches tenfold or more.
qemu_guest() {
  local role=$1 n=$2
  "${QEMU_PRIO[@]}" qemu-system-x86_64 -accel tcg,thread=multi -cpu max -smp 1 -m 384 -nodefaults -display none \
    -no-reboot -kernel "$KERNEL_DIR/vmlinux" -initrd "$WORK/initramfs.cpio" \
    -append "console=ttyS0 quiet panic=-1 preempt=full m2mlat_role=$role" \
    -serial "file:$WORK/$role-console.log" \
    -chardev "socket,id=stim,host=127.0.0.1,port=$4,server=on,wait=off,nodelay=on" -serial chardev:stim \
    -chardev "socket,id=ctl,host=127.0.0.1,port=$5,server=on,wait=off" -serial chardev:ctl \
    -netdev "socket,id=lan,$3" -device "e1000,netdev=lan,mac=52:54:00:12:00:0$n,romfile=" \
    -netdev "user,id=up,restrict=on,hostfwd=tcp:127.0.0.1:$6-:8470" \
    -device "e1000,netdev=up,mac=52:54:00:12:01:0$n,romfile=" </dev/null >"$WORK/$role-qemu.log" 2>&1 &
  QEMU_PIDS+=($!)
}
# Priorities, where we may set them (root): the guests' delivery of a trigger byte is the test's noise,
# and on a host busy with other work a QEMU thread waits milliseconds for a CPU. nice -10 for QEMU (its
# threads sleep while the guests idle), SCHED_FIFO for the trigger (it sleeps between its sends).
QEMU_PRIO=() TRIGGER_PRIO=()
if [ "$(id -u)" = 0 ]; then
  QEMU_PRIO=(nice -n -10)
  TRIGGER_PRIO=(chrt -f 20)
fi
port_listening() { ss -Htln "sport = :$1" | grep -q .; }
wait_for() {  # wait_for SECONDS COMMAND...: polls COMMAND every 0.2 s
  local left=$(($1 * 5))
  shift
  until "$@"; do
    left=$((left - 1))
    [ $left -gt 0 ] || return 1
    sleep 0.2
  done
}
log "booting the operator and vehicle guests (TCG, 1 CPU each); work folder $WORK"
GUEST_START=$SECONDS
qemu_guest operator 1 "listen=127.0.0.1:$LAN_PORT" "$STIM_OP" "$CTL_OP" "$API_OP"
wait_for 20 port_listening "$LAN_PORT" || die "the operator's QEMU did not start: $(cat "$WORK/operator-qemu.log")"
qemu_guest vehicle 2 "connect=127.0.0.1:$LAN_PORT" "$STIM_VEH" "$CTL_VEH" "$API_VEH"

# ---- the command channels ---------------------------------------------------------------------------
declare -A CTL
REPLY_LINE=""
guest_ready() { grep -q "twoguest\[$1\]: ready" "$WORK/$1-console.log" 2>/dev/null; }
ctl_open() {  # ctl_open ROLE PORT: connect, then a ping with a fresh tag, skipping any older line
  local fd tag line
  wait_for 60 guest_ready "$1" || die "the $1 guest did not boot; console: $(tail -n 20 "$WORK/$1-console.log")"
  exec {fd}<>"/dev/tcp/127.0.0.1/$2"
  CTL[$1]=$fd
  tag=$RANDOM$RANDOM
  printf 'ping %s\n' "$tag" >&"$fd"
  while IFS= read -r -t 20 line <&"$fd"; do
    [ "${line%$'\r'}" = "pong $1 $tag" ] && return 0
  done
  die "the $1 guest does not answer on its command channel"
}
ctl() {  # ctl ROLE COMMAND [ARGS]: one command, one answer (REPLY_LINE); fails unless it is "ok ..."
  local fd=${CTL[$1]} role=$1
  shift
  printf '%s\n' "$*" >&"$fd"
  IFS= read -r -t 90 REPLY_LINE <&"$fd" || REPLY_LINE="err no answer to '$*'"
  REPLY_LINE=${REPLY_LINE%$'\r'}
  [[ $REPLY_LINE == ok* ]] || { log "$role: $* -> $REPLY_LINE"; return 1; }
}
guests_gone() { ! kill -0 "${QEMU_PIDS[@]}" 2>/dev/null; }
ctl_open operator "$CTL_OP"
ctl_open vehicle "$CTL_VEH"
log "both guests up after $((SECONDS - GUEST_START)) s"

# ---- HTTP to the agents (bash's /dev/tcp: no client needed) -----------------------------------------
http_get() {  # http_get PORT PATH: the body... and headers; enough for a grep
  local h
  exec {h}<>"/dev/tcp/127.0.0.1/$1" || return 1
  printf 'GET %s HTTP/1.0\r\nHost: guest\r\nAuthorization: Bearer %s\r\n\r\n' "$2" "$(cat "$TOKEN_FILE")" >&"$h"
  timeout 5 cat <&"$h" || true
  exec {h}>&-
}
session_is() { http_get "$1" /v1/status | grep -q "\"scenario\":\"$2\""; }

# ---- one measurement phase ----------------------------------------------------------------------------
# phase NAME CHRONY_INTERVAL [BEFORE_TRIGGER_FUNCTION]: new agents (fresh stores) reading chronyc
# every CHRONY_INTERVAL, collect into $WORK/NAME.db with a session of scenario NAME on both, the
# stimulus, then everything committed reaches the campaign.
phase() {
  local name=$1
  ctl operator agent-start "$name" "$2" && ctl vehicle agent-start "$name" "$2" || return 1
  "$M2MLAT_BIN" collect --agent "http://127.0.0.1:$API_OP" --agent "http://127.0.0.1:$API_VEH" \
    --store "$WORK/$name.db" --token-file "$TOKEN_FILE" --start-session --label "$name" --scenario "$name" \
    --stop-session >"$WORK/$name-collect.out" 2>"$WORK/$name-collect.err" &
  COLLECT_PID=$!
  wait_for 30 session_is "$API_OP" "$name" && wait_for 30 session_is "$API_VEH" "$name" ||
    { log "the agents did not begin the $name session: $(tail -n 5 "$WORK/$name-collect.err")"; return 1; }
  if [ $# -gt 2 ]; then "$3" || return 1; fi
  log "$name: $CYCLES stimulus cycles of $PERIOD_MS ms"
  "${TRIGGER_PRIO[@]}" "$BUILD/m2mlat-2g-trigger" "$STIM_OP" "$STIM_VEH" "$DELAY_US" "$PERIOD_MS" "$CYCLES" "$WORK/$name-trigger.csv" \
    >"$WORK/$name-trigger.out" || { log "trigger failed: $(cat "$WORK/$name-trigger.out")"; return 1; }
  # The last edges: committed within the agents' commit interval (100 ms), pulled within a second.
  sleep 2
  ctl operator tracking && echo "operator ${REPLY_LINE#ok }" >"$WORK/$name-tracking.txt"
  ctl vehicle tracking && echo "vehicle ${REPLY_LINE#ok }" >>"$WORK/$name-tracking.txt"
  kill -TERM "$COLLECT_PID"
  wait "$COLLECT_PID" || { log "collect exited $?: $(tail -n 5 "$WORK/$name-collect.err")"; return 1; }
  COLLECT_PID=""
  ctl operator agent-stop && ctl vehicle agent-stop
}

# The autonomous phase: chronyd is stopped on both guests before its agents start (from then on the
# clocks run free, the vehicle's at the frequency chronyd left in its kernel, off by tens of ppm: a
# drift of tens of us per second), and the vehicle's clock is stepped by OFFSET_NS as soon as its
# session has begun, the first edge right after: the agent's step detector allows 500 ppm of the time
# between two clock readings as slewing, so the readings around the step must be close together.
shift_vehicle() {
  ctl vehicle shift "$OFFSET_NS" || return 1
  echo "${REPLY_LINE#ok }" >"$WORK/shift.txt"
}

run_guests() {
  ctl operator chrony-start && ctl vehicle chrony-start || return 1
  local t=$SECONDS
  ctl vehicle chrony-wait 60 || return 1
  echo "synchronised_after_s=$((SECONDS - t)) ${REPLY_LINE#ok }" >"$WORK/chrony-wait.txt"
  # chronyc every 2 s (the agent's default is 8 s): a 20 s phase gets about ten chrony samples.
  phase coref 2s || return 1
  ctl vehicle tracking && echo "vehicle ${REPLY_LINE#ok }" >"$WORK/before-stop-tracking.txt"
  ctl vehicle chrony-stop && ctl operator chrony-stop || return 1
  # The agents do not ask chronyd in this phase (a chronyc that cannot reach its daemon spends guest
  # time on every attempt), so its sessions hold no daemon's samples.
  phase auto 0 shift_vehicle || return 1
  ctl vehicle log /tmp/agent-auto.log >/dev/null && echo "${REPLY_LINE#ok }" >"$WORK/vehicle-agent-auto.log"
}
# A watchdog: guests that hang are ended after TIMEOUT seconds (each command's answer is also
# awaited at most 90 s). It sleeps a second at a time, so that ending it leaves no sleep behind
# holding the output open.
watchdog() {
  local left=$TIMEOUT
  while [ "$left" -gt 0 ]; do sleep 1; left=$((left - 1)); done
  log "timeout after $TIMEOUT s: stopping the guests"
  kill "${QEMU_PIDS[@]}" 2>/dev/null
}
watchdog </dev/null &
WATCHDOG=$!
GUEST_RC=0
run_guests || GUEST_RC=1
ctl operator poweroff || true
ctl vehicle poweroff || true
wait_for 10 guests_gone || kill "${QEMU_PIDS[@]}" 2>/dev/null || true
kill "$WATCHDOG" 2>/dev/null || true
WATCHDOG=""
GUEST_TIME=$((SECONDS - GUEST_START))

# ---- the analysis, with m2mlat's own commands on the campaign stores, and the judge ------------------
PAIRING=(--edge both --min-latency 0ms --max-latency 150ms --burst-gap 50ms --refractory 5ms)
analyse() {  # analyse PHASE (synctest is not told the offset to expect: it must find it)
  local db=$WORK/$1.db
  "$M2MLAT_BIN" pair "$db" --scenario "$1" --cause operator/latency --effect vehicle/latency "${PAIRING[@]}" \
    -o "$WORK/$1-pairs.csv" >"$WORK/$1-pair.txt" 2>&1 &&
    "$M2MLAT_BIN" export "$db" --what pairs --scenario "$1" --format pairs-jsonl \
      --cause operator/latency --effect vehicle/latency "${PAIRING[@]}" -o "$WORK/$1-pairs.jsonl" &&
    "$M2MLAT_BIN" stats "$db" --scenario "$1" --cause operator/latency --effect vehicle/latency "${PAIRING[@]}" \
      --bootstrap 0 --json >"$WORK/$1-stats.json" &&
    "$M2MLAT_BIN" synctest "$db" --a operator --b vehicle --channel pulse --period "${PERIOD_MS}ms" \
      --json --series >"$WORK/$1-synctest.json"
}
ANALYSIS_RC=0
if [ $GUEST_RC -eq 0 ]; then
  analyse coref && analyse auto || ANALYSIS_RC=$?
else
  for role in operator vehicle; do
    echo "$role console, last lines:"
    tail -n 15 "$WORK/$role-console.log" | sed 's/^/      /'
  done
fi
set +e
python3 "$VM_DIR/twoguest/judge.py" --work "$WORK" --delay-us "$DELAY_US" --offset-ns "$OFFSET_NS" \
  --cycles "$CYCLES" --period-ms "$PERIOD_MS" --tol-us "$TOL_US" --mean-tol-us "$MEAN_TOL_US" --max-us "$MAX_US" --guest-rc "$GUEST_RC" \
  --analysis-rc "$ANALYSIS_RC"
JUDGE_RC=$?
set -e
echo "guests $GUEST_TIME s, total $SECONDS s"
exit $JUDGE_RC
