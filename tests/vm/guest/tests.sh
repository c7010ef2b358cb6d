# The real-kernel tests, run by the guest's /init (busybox sh, in /tmp, as root).
#
# Every test is a function that returns 0 (pass), 1 (fail) or 77 (skipped: what it needs is missing);
# run_test prints one result line "M2MLAT-VM PASS|FAIL|SKIP <name> <seconds>" and the test's details
# as "M2MLAT-VM INFO <name>: ..." lines, which the host turns into the suite's report.
#
# The stimulus is gpio-sim: writing pull-up / pull-down to sim_gpioK/pull makes an edge on line K.
# m2mlat-vm-driver makes the edges, logs CLOCK_REALTIME just before and after each write, and
# verifies a capture's exported events against that log (see tests/vm/driver.cpp).

DRIVER=/bin/m2mlat-vm-driver
M2MLAT=/bin/m2mlat
LABEL=m2mlat-sim0
NLINES=8
# Pacing of "lockstep-ish" edges (us between writes): an edge made while the previous one's interrupt
# thread is still pending is silently not turned into an event, so exact counts are only asserted
# with a gap far above the 15-25 us the guest needs per edge (and on one guest CPU: see run.sh).
PACE_US=${PACE_US:-1000}

T=""
info() { echo "M2MLAT-VM INFO $T: $*"; }
# uptime in centiseconds, for the per-test time
now_cs() { sed 's/^\([0-9]*\)\.\([0-9]*\) .*/\1\2/' /proc/uptime; }

run_test() {
  T=$1
  local start end rc result
  start=$(now_cs)
  "$2"
  rc=$?
  end=$(now_cs)
  case $rc in
    0) result=PASS ;;
    77) result=SKIP ;;
    *) result=FAIL ;;
  esac
  echo "M2MLAT-VM $result $T $(((end - start) / 100)).$(((end - start) % 100 / 10))"
}

# make_chip NAME LABEL NLINES: a live gpio-sim chip with one bank; line 0 is named "hall". Sets
# CHIP (gpiochipN) and SIM (the folder of its sim_gpioK attributes).
make_chip() {
  local dir=/sys/kernel/config/gpio-sim/$1
  mkdir "$dir" "$dir/bank0" "$dir/bank0/line0" || return 1
  echo "$2" >"$dir/bank0/label"
  echo "$3" >"$dir/bank0/num_lines"
  echo hall >"$dir/bank0/line0/name"
  echo 1 >"$dir/live" || return 1
  CHIP=$(cat "$dir/bank0/chip_name")
  SIM=/sys/devices/platform/$(cat "$dir/dev_name")/$CHIP
}

# running PID: the process exists and has not exited (an exited child stays a zombie, state Z, until
# the shell waits for it, and kill -0 would still find it).
running() { [ -r "/proc/$1/stat" ] && [ "$(cut -d' ' -f3 "/proc/$1/stat" 2>/dev/null)" != Z ]; }

# wait_ready SECONDS CMD...: polls CMD every 0.05 s until it succeeds (0) or SECONDS pass (1). For what
# a helper says once it is watching or listening: under TCG on a slow host, starting a process and
# opening a store take longer than any fixed sleep a test could afford.
wait_ready() {
  local left=$(($1 * 20))
  shift
  until "$@"; do
    [ $left -gt 0 ] || return 1
    sleep 0.05
    left=$((left - 1))
  done
}

# wait_exit PID SECONDS: waits for a background process and returns its exit status; if it outlives
# SECONDS it is killed (TERM, then KILL) and the status is 124, whatever it exited with.
wait_exit() {
  local pid=$1 left=$(($2 * 10))
  while running "$pid" && [ $left -gt 0 ]; do
    sleep 0.1
    left=$((left - 1))
  done
  if running "$pid"; then
    info "pid $pid still running after $2 s: terminating it"
    kill -TERM "$pid"
    sleep 2
    kill -KILL "$pid" 2>/dev/null
    wait "$pid"
    return 124
  fi
  wait "$pid"
}

# show FILE: a file's lines as INFO lines (for failures).
show() { [ -f "$1" ] && while IFS= read -r line; do info "  $1: $line"; done <"$1"; }

have_record() { "$M2MLAT" help 2>/dev/null | awk '$1 == "record" { found = 1 } END { exit !found }'; }
need_record() {
  have_record && return 0
  info "skipped: this m2mlat has no 'record' subcommand yet ('m2mlat help' does not list it)"
  return 77
}

# start_record STORE OUT EDGES ARGS...: m2mlat record in the background on line 0 of the chip as
# channel "hall", for edges EDGES (record's default is falling only); returns once it holds the line
# and has had time to arm edge detection (the line shows as used a moment before the kernel has set
# up its interrupt, and edges in between are not seen). Sets REC.
start_record() {
  local store=$1 out=$2 edges=$3
  shift 3
  "$M2MLAT" record --store "$store" --node guest --channel "hall=$CHIP:0" --edges "$edges" --json "$@" \
    >"$out" 2>"$out.err" &
  REC=$!
  if ! "$DRIVER" wait-used "/dev/$CHIP" 0 20000 >/dev/null; then
    info "record did not request the line within 20 s"
    show "$out.err"
    return 1
  fi
  sleep 0.3
}

# ns_to_us NS: nanoseconds as whole microseconds (0 for an empty value).
ns_to_us() { awk -v n="$1" 'BEGIN { printf "%d", n / 1000 }'; }
# json_field FILE NAME: the first integer value of "NAME" in a JSON file (record's summary).
json_field() { tr ',{}' '\n\n\n' <"$1" | sed -n "s/^ *\"$2\" *: *\([0-9]*\).*/\1/p" | head -n1; }

# export_verify STORE DRIVER_LOG VERIFY_ARGS...: exports the store and verifies it against the log.
export_verify() {
  local store=$1 log=$2
  shift 2
  "$M2MLAT" export "$store" -o "$store.csv" 2>"$store.export.err" || {
    info "m2mlat export failed"
    show "$store.export.err"
    return 1
  }
  "$DRIVER" verify --driver "$log" --events "$store.csv" --channel hall "$@" >"$store.verify"
  local rc=$?
  show "$store.verify"
  return $rc
}

# ---- smoke: the guest, the chip, the driver, the binary (no capture code needed) -----------------

t_boot() {
  info "kernel $(uname -r); $(grep -c ^processor /proc/cpuinfo) CPUs;" \
    "clocksource $(cat /sys/devices/system/clocksource/clocksource0/current_clocksource 2>/dev/null)"
  case $(uname -r) in 6.1.*) ;; *) return 1 ;; esac
  grep -q '^gpio_sim ' /proc/modules || { info "gpio-sim is not loaded"; return 1; }
  make_chip chip0 "$LABEL" "$NLINES" || { info "gpio-sim chip creation failed"; return 1; }
  info "chip0 is /dev/$CHIP, its lines at $SIM"
}

t_chip() {
  [ -c "/dev/$CHIP" ] || { info "/dev/$CHIP is not a character device"; return 1; }
  local got
  got=$("$DRIVER" info "/dev/$CHIP") || return 1
  info "$got"
  [ "$got" = "name=$CHIP label=$LABEL lines=$NLINES" ]
}

# The driver requests the line itself and waits for each edge's event before making the next one:
# the kernel's own timestamps must fall inside the write windows, with seqno never skipping.
t_driver_lockstep() {
  "$DRIVER" toggle --sim "$SIM/sim_gpio1" --count 1000 --log drv.csv --watch "/dev/$CHIP:1" \
    --events watch.csv >toggle.out || { show toggle.out; return 1; }
  show toggle.out
  "$DRIVER" verify --driver drv.csv --events watch.csv >verify.out
  local rc=$?
  show verify.out
  return $rc
}

t_version() {
  local v
  v=$("$M2MLAT" --version 2>&1) || { info "m2mlat --version failed: $v"; return 1; }
  info "$v"
  case $v in *m2mlat*) ;; *) return 1 ;; esac
  info "subcommands: $("$M2MLAT" help 2>/dev/null | awk '/^  [a-z]/ { printf "%s ", $1 }')"
}

# ---- m2mlat record against the real kernel -------------------------------------------------------

# Thousands of edges, paced: every one stored, timestamps inside the windows, edges alternating as
# made, seqno and line_seqno without a gap.
t_record_lockstep() {
  need_record || return 77
  local n=2000
  start_record lock.db lock.json both --count $n --duration 300s || return 1
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count $n --period-us "$PACE_US" --log lock.drv >lock.toggle
  show lock.toggle
  wait_exit $REC 60 || { info "record exited $?"; show lock.json.err; return 1; }
  export_verify lock.db lock.drv || { show lock.json; return 1; }
  local stored
  stored=$(json_field lock.json events)
  info "record's summary: events=$stored losses=$(json_field lock.json losses)"
  [ "$stored" = $n ]
}

# Only the requested edge type reaches the store.
t_record_edges() {
  need_record || return 77
  local kind rc=0
  for kind in rising falling; do
    start_record "$kind.db" "$kind.json" "$kind" --count 100 --duration 120s || return 1
    "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count 200 --period-us "$PACE_US" --log "$kind.drv" >/dev/null
    wait_exit $REC 60 || { info "record --edges $kind exited $?"; show "$kind.json.err"; return 1; }
    export_verify "$kind.db" "$kind.drv" --edges "$kind" || rc=1
  done
  return $rc
}

# SIGTERM right after the last edge: every edge made before it is stored, and record has ended
# within 1 s of the signal (measured to wait_exit's 0.1 s polling, so up to 1.1 s is allowed).
t_record_shutdown() {
  need_record || return 77
  start_record term.db term.json both || return 1
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count 500 --period-us "$PACE_US" --log term.drv >/dev/null
  local signalled
  signalled=$(now_cs)
  kill -TERM $REC
  wait_exit $REC 30 || { info "record exited $? on SIGTERM"; show term.json.err; return 1; }
  local took=$(($(now_cs) - signalled))
  info "record ended $((took * 10)) ms after SIGTERM"
  [ "$took" -le 110 ] || { info "record took more than 1 s to stop"; return 1; }
  export_verify term.db term.drv || { show term.json; return 1; }
}

# The reader is stopped (SIGSTOP) while more edges arrive than the kernel's buffer holds: the kernel
# drops the oldest and its seqno jumps; the store must show exactly that gap, and record must report
# it as lost. Edges before and after the stall are all stored.
t_record_stall() {
  need_record || return 77
  start_record stall.db stall.json both || return 1
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count 20 --period-us "$PACE_US" --log stall.drv >/dev/null
  sleep 0.5
  kill -STOP $REC
  # 1024 is the largest buffer the kernel gives a line request; 3000 edges overflow any of them.
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count 3000 --period-us 300 --log stall.drv --append >stall.toggle
  show stall.toggle
  kill -CONT $REC
  sleep 1
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count 20 --period-us "$PACE_US" --log stall.drv --append >/dev/null
  sleep 1
  kill -INT $REC
  wait_exit $REC 30 || { info "record exited $? on SIGINT"; show stall.json.err; return 1; }
  export_verify stall.db stall.drv --allow-missing || { show stall.json; return 1; }
  local missing reported
  missing=$(sed -n 's/.* seqno_gap=\([0-9]*\) .*/\1/p' stall.db.verify)
  [ "${missing:-0}" -gt 0 ] || { info "no seqno gap: the stall did not overflow the kernel buffer"; return 1; }
  # record's own count of lost events: the "losses" of its JSON summary's only channel
  reported=$(json_field stall.json losses)
  info "kernel seqno gap: $missing events; record reports losses=${reported:-?}"
  [ "$reported" = "$missing" ]
}

# --refractory 30ms: bursts of three rising edges 2 ms apart, 100 ms between bursts: only the first
# edge of each burst is kept, the others are counted as suppressed. (The margins are wide so that a
# host stalling the guest for a few ms cannot make the outcome ambiguous.)
t_record_refractory() {
  need_record || return 77
  local bursts=20
  start_record refr.db refr.json rising --refractory 30ms || return 1
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count $((bursts * 6)) --period-us 1000 --burst 6 \
    --burst-gap-us 100000 --log refr.drv >/dev/null
  sleep 0.5
  kill -INT $REC
  wait_exit $REC 30 || { info "record exited $?"; show refr.json.err; return 1; }
  export_verify refr.db refr.drv --edges rising --refractory-us 30000 || { show refr.json; return 1; }
  local stored suppressed
  stored=$(json_field refr.json events)
  suppressed=$(json_field refr.json suppressed)
  info "record's summary: events=$stored suppressed=$suppressed"
  # verify judged each edge by its real timing (normally one kept per burst; more if the host stalled
  # the guest inside a burst); record must also count every other rising edge as suppressed.
  [ $((stored + suppressed)) = $((bursts * 3)) ]
}

# A second record on a line the first one holds fails with a message that says the line is taken.
t_record_busy() {
  need_record || return 77
  start_record busy1.db busy1.json both || return 1
  "$M2MLAT" record --store busy2.db --node guest --channel "hall=$CHIP:0" --count 1 --duration 10s \
    >busy2.out 2>busy2.err
  local rc=$?
  kill -INT $REC
  wait_exit $REC 30 >/dev/null
  show busy2.err
  [ $rc -ne 0 ] || { info "the second record exited 0"; return 1; }
  grep -Eqi 'busy|in use' busy2.err || { info "the message does not say the line is busy"; return 1; }
}

# A chip that does not exist: a clear message naming it, a non-zero exit, within seconds.
t_record_missing_chip() {
  need_record || return 77
  "$M2MLAT" record --store missing.db --node guest --channel hall=gpiochip99:0 --count 1 --duration 10s \
    >missing.out 2>missing.err
  local rc=$?
  show missing.err
  [ $rc -ne 0 ] || { info "record exited 0"; return 1; }
  grep -q 'gpiochip99' missing.err || { info "the message does not name the chip"; return 1; }
}

# m2mlat doctor on a machine with a GPIO chip: the simulated chip is found and named.
t_doctor() {
  "$M2MLAT" help 2>/dev/null | awk '$1 == "doctor" { found = 1 } END { exit !found }' ||
    { info "skipped: this m2mlat has no 'doctor' subcommand"; return 77; }
  "$M2MLAT" doctor >doctor.out 2>&1
  info "doctor exited $? (non-zero is expected: the guest's clock is not synchronised)"
  show doctor.out
  grep -q "$LABEL" doctor.out || { info "doctor does not name the chip $CHIP ($LABEL)"; return 1; }
}

# ---- the gyroscope (MPU-6050) through Linux's I2C character device ------------------------------
#
# i2c-stub (chip_addr=0x68) gives a register file on a real SMBus adapter, i2c-dev its /dev/i2c-N:
# the chip m2mlat gyro reads. m2mlat-vm-gyro (tests/vm/gyro_driver.cpp) writes the rate registers
# at logged times and judges the recorded trace against them.
GYRO=/bin/m2mlat-vm-gyro
GYRO_DEV=""
GYRO_STEPS=${GYRO_STEPS:-12}    # rate changes made while m2mlat gyro reads
GYRO_GAP_US=${GYRO_GAP_US:-100000}

have_gyro() { "$M2MLAT" help 2>/dev/null | awk '$1 == "gyro" { found = 1 } END { exit !found }'; }

# load_i2c_stub: the stub at 0x68 and i2c-dev; sets GYRO_DEV to its /dev/i2c-N.
load_i2c_stub() {
  [ -n "$GYRO_DEV" ] && return 0
  insmod /lib/modules/i2c-stub.ko chip_addr=0x68 || { info "insmod i2c-stub failed"; return 1; }
  insmod /lib/modules/i2c-dev.ko || { info "insmod i2c-dev failed"; return 1; }
  local d
  for d in /sys/class/i2c-dev/*; do
    grep -q 'stub' "$d/name" 2>/dev/null && GYRO_DEV=/dev/$(basename "$d")
  done
  [ -n "$GYRO_DEV" ] && [ -c "$GYRO_DEV" ] || { info "no /dev/i2c-N for the stub"; return 1; }
  info "i2c-stub at 0x68 on $GYRO_DEV"
}

# Before the stub is loaded there is no bus: a clear error naming the device (exit 66).
t_gyro_no_bus() {
  have_gyro || { info "skipped: this m2mlat has no 'gyro' subcommand"; return 77; }
  "$M2MLAT" gyro --device /dev/i2c-0 --duration 1s --out nobus.csv >nobus.out 2>nobus.err
  local rc=$?
  show nobus.err
  [ $rc -eq 66 ] || { info "exit $rc, expected 66 (no input)"; return 1; }
  grep -q '/dev/i2c-0: no such I2C device' nobus.err || { info "the message does not name the device"; return 1; }
  [ ! -e nobus.csv ] || { info "a trace file was written"; return 1; }
}

# The recorded trace shows every rate change the test made, each where it was made: the last read of
# the old rates began before the write ended, the first read of the new ones ended after it began.
t_gyro_trace() {
  have_gyro || { info "skipped: this m2mlat has no 'gyro' subcommand"; return 77; }
  load_i2c_stub || return 1
  "$GYRO" set "$GYRO_DEV" 0x68 0x75 0x68 || return 1  # WHO_AM_I
  "$GYRO" set "$GYRO_DEV" 0x68 0x6b 0x40 || return 1  # PWR_MGMT_1 as at power-on: asleep
  "$GYRO" steps --device "$GYRO_DEV" --address 0x68 --from 0 --count 1 --gap-us 0 --log gyro.steps || return 1
  "$M2MLAT" gyro --device "$GYRO_DEV" --period 1ms --rt-priority 50 --out gyro.csv --json >gyro.out 2>gyro.err &
  local pid=$! rc=0
  # PWR_MGMT_1 0x01: m2mlat has woken and is configuring the chip; the reads follow at once.
  "$GYRO" wait-reg "$GYRO_DEV" 0x68 0x6b 0x01 5000 || { kill -TERM $pid; wait $pid; show gyro.err; return 1; }
  sleep 0.3
  "$GYRO" steps --device "$GYRO_DEV" --address 0x68 --from 1 --count "$GYRO_STEPS" --gap-us "$GYRO_GAP_US" \
    --log gyro.steps --append || rc=1
  sleep 0.2
  kill -INT $pid
  wait_exit $pid 10 || { info "m2mlat gyro exited $?"; show gyro.err; return 1; }
  info "m2mlat gyro: $(tr -d '\n' <gyro.out | tr -s ' ')"
  grep -q "\"stop_reason\": *\"SIGINT\"" gyro.out || { info "not stopped by SIGINT"; rc=1; }
  grep -q "\"i2c_errors\": *0," gyro.out || { info "I2C errors"; rc=1; }
  "$GYRO" verify --log gyro.steps --trace gyro.csv >gyro.verify 2>&1 || rc=1
  show gyro.verify
  # The resolution: a change is placed within about one period (1 ms) plus a read.
  local window
  window=$(sed -n 's/.*change_window_p50_us=\([0-9]*\).*/\1/p' gyro.verify)
  [ "${window:-99999}" -le 2000 ] || { info "changes placed within ${window:-?} us (median), not 2 ms"; rc=1; }
  [ $rc -eq 0 ] || { show gyro.steps; show gyro.err; }
  return $rc
}

# A chip that is not an MPU-6050, an address where nothing answers: clear errors (exit 74), no file,
# and doctor says so; doctor finds the good chip.
t_gyro_errors() {
  have_gyro || { info "skipped: this m2mlat has no 'gyro' subcommand"; return 77; }
  load_i2c_stub || return 1
  local rc=0 code
  "$GYRO" set "$GYRO_DEV" 0x68 0x75 0x70 || return 1  # an MPU-6500's WHO_AM_I
  "$GYRO" set "$GYRO_DEV" 0x68 0x1b 0x18 || return 1  # GYRO_CONFIG, to see that nothing is written
  "$M2MLAT" gyro --device "$GYRO_DEV" --duration 1s --out wrong.csv >wrong.out 2>wrong.err
  code=$?
  show wrong.err
  [ $code -eq 74 ] || { info "wrong WHO_AM_I: exit $code, expected 74"; rc=1; }
  grep -q "$GYRO_DEV address 0x68: a chip that is not an MPU-6050 (WHO_AM_I 0x70" wrong.err ||
    { info "wrong WHO_AM_I: the message does not say what was read"; rc=1; }
  [ ! -e wrong.csv ] || { info "wrong WHO_AM_I: a trace file was written"; rc=1; }
  "$GYRO" wait-reg "$GYRO_DEV" 0x68 0x1b 0x18 0 || { info "the wrong chip was written to"; rc=1; }
  "$M2MLAT" doctor --gyro-device "$GYRO_DEV" >doctor-gyro.out 2>&1
  grep -q 'FIX.*gyro.*not an MPU-6050' doctor-gyro.out || { info "doctor does not flag the wrong chip"; show doctor-gyro.out; rc=1; }

  "$M2MLAT" gyro --device "$GYRO_DEV" --address 0x69 --duration 1s --out absent.csv >absent.out 2>absent.err
  code=$?
  show absent.err
  [ $code -eq 74 ] || { info "no chip at 0x69: exit $code, expected 74"; rc=1; }
  grep -q "$GYRO_DEV address 0x69: reading register 0x75:.*no chip answered" absent.err ||
    { info "no chip at 0x69: the message does not say so"; rc=1; }
  [ ! -e absent.csv ] || { info "no chip: a trace file was written"; rc=1; }

  "$GYRO" set "$GYRO_DEV" 0x68 0x75 0x68 || return 1
  "$M2MLAT" doctor --gyro-device "$GYRO_DEV" >doctor-gyro.out 2>&1
  grep -q 'ok.*gyro.*MPU-6050 at' doctor-gyro.out || { info "doctor does not find the chip"; show doctor-gyro.out; rc=1; }
  return $rc
}

# ---- m2mlat pulse against the real kernel --------------------------------------------------------

# m2mlat pulse drives an output line, toggling it on multiples of its period, and stores each
# commanded edge. gpio-sim shows an output line's value in sim_gpioK/value: sampled meanwhile (every
# 100 us), it must change exactly as the stored edges say, each change seen after its command.
t_pulse() {
  "$M2MLAT" help 2>/dev/null | awk '$1 == "pulse" { found = 1 } END { exit !found }' ||
    { info "skipped: this m2mlat has no 'pulse' subcommand"; return 77; }
  local n=20 period_us=50000 rc sampler
  rm -f pulse.ready
  "$DRIVER" sample --file "$SIM/sim_gpio2/value" --changes $n --duration-ms 30000 --log pulse.values \
    --ready pulse.ready >pulse.sample &
  sampler=$!
  wait_ready 10 test -e pulse.ready || { info "the sampler did not start"; kill $sampler; return 1; }
  "$M2MLAT" pulse --chip "$CHIP" --line 2 --period 50ms --count $n --store pulse.db --node guest \
    --json --quiet >pulse.json 2>pulse.err
  rc=$?
  wait $sampler
  show pulse.sample
  [ $rc = 0 ] || { info "pulse exited $rc"; show pulse.err; return 1; }
  info "pulse's summary: edges=$(json_field pulse.json edges)" \
    "mean_late_us=$(ns_to_us "$(json_field pulse.json mean_late_ns)")" \
    "max_late_us=$(ns_to_us "$(json_field pulse.json max_late_ns)")"
  [ "$(json_field pulse.json edges)" = $n ] || { show pulse.json; return 1; }
  "$M2MLAT" export pulse.db -o pulse.csv 2>pulse.export.err || { show pulse.export.err; return 1; }
  "$DRIVER" verify-pulse --values pulse.values --events pulse.csv --period-us $period_us >pulse.verify
  rc=$?
  show pulse.verify
  [ "$(cat "$SIM/sim_gpio2/value")" = 0 ] || { info "pulse left the line high"; rc=1; }
  return $rc
}

# ---- glass-to-glass: m2mlat led, a camera-and-screen twin, m2mlat record, m2mlat stats -----------------

# Single-board mode on one chip: m2mlat led flashes output line 3 (the LED); m2mlat-vm-driver mirror
# watches line 3's value every 100 us and, G2G_DELAY_US after each change it saw, sets line 4's pull to
# match (the camera, the screen and the phototransistor, with a known delay); m2mlat record captures
# line 4 as channel "photo" into the same store. Then stats pairs guest/led (cause) with guest/photo
# (effect), rising edges: every flash paired, the median within the loop's measured delay plus its
# polling error (the read that sees a change comes 0..100 us after it, plus the guest's scheduling).
G2G_DELAY_US=${G2G_DELAY_US:-20000}
t_g2g() {
  "$M2MLAT" help 2>/dev/null | awk '$1 == "led" { found = 1 } END { exit !found }' ||
    { info "skipped: this m2mlat has no 'led' subcommand"; return 77; }
  need_record || return 77
  local n=10 rec mirror rc=0 median p5 p95 pairs lo hi
  "$M2MLAT" record --store g2g.db --node guest --role effect --scenario g2g --channel "photo=$CHIP:4" \
    --edges both --json --quiet >g2g-record.json 2>g2g-record.err &
  rec=$!
  "$DRIVER" wait-used "/dev/$CHIP" 4 20000 >/dev/null || { show g2g-record.err; return 1; }
  sleep 0.3
  rm -f g2g.mirror.ready
  "$DRIVER" mirror --value "$SIM/sim_gpio3/value" --sim "$SIM/sim_gpio4" --delay-us "$G2G_DELAY_US" \
    --changes $((2 * n)) --duration-ms 30000 --log g2g.mirror --ready g2g.mirror.ready >g2g.mirror.out 2>&1 &
  mirror=$!
  wait_ready 10 test -e g2g.mirror.ready || { info "the mirror did not start"; rc=1; }
  "$M2MLAT" led --chip "$CHIP" --line 3 --period 100ms --on-for 40ms --count $n --store g2g.db \
    --events g2g-led.csv --node guest --scenario g2g --json --quiet >g2g-led.json 2>g2g-led.err ||
    { info "led failed"; rc=1; }
  wait $mirror || { info "mirror failed"; rc=1; }
  show g2g.mirror.out
  sleep 0.2
  kill -INT $rec
  wait_exit $rec 10 || { info "record exited $?"; show g2g-record.err; rc=1; }
  info "led: switches=$(json_field g2g-led.json switches)" \
    "ioctl_mean_us=$(ns_to_us "$(json_field g2g-led.json ioctl_mean_ns)")" \
    "ioctl_max_us=$(ns_to_us "$(json_field g2g-led.json ioctl_max_ns)")"
  [ "$(json_field g2g-led.json switches)" = $((2 * n)) ] || { show g2g-led.json; show g2g-led.err; rc=1; }
  [ "$(cat "$SIM/sim_gpio3/value")" = 0 ] || { info "led left the line high"; rc=1; }
  # m2mlat-events/2: scenario, session and label come first, then node and channel.
  [ "$(grep -c ',guest,led,' g2g-led.csv)" = $((2 * n)) ] || { info "the events file has not every switch"; rc=1; }
  "$M2MLAT" stats g2g.db --cause guest/led --effect guest/photo --edge rising --json >g2g-stats.json \
    2>g2g-stats.err || { info "stats failed"; show g2g-stats.err; return 1; }
  pairs=$(sed -n 's/^ *"n": *\([0-9]*\),*$/\1/p' g2g-stats.json | head -n1)
  median=$(sed -n 's/^ *"median_ms": *\([0-9.]*\),*$/\1/p' g2g-stats.json | head -n1)
  p5=$(sed -n 's/^ *"p5_ms": *\([0-9.]*\),*$/\1/p' g2g-stats.json | head -n1)
  p95=$(sed -n 's/^ *"p95_ms": *\([0-9.]*\),*$/\1/p' g2g-stats.json | head -n1)
  info "G2G: $pairs pairs, median $median ms, p5 $p5 ms, p95 $p95 ms (loop delay $((G2G_DELAY_US / 1000)) ms)"
  [ "$pairs" = $n ] || { info "expected $n pairs"; rc=1; }
  # The loop's real delay (its sleeps overshoot under TCG): from the read that saw a change to the write
  # that copied it. G2G adds how long the change waited for that read: 0..0.1 ms, and the guest's
  # scheduling: on the guest's one CPU the read waits while m2mlat led commits the switch it just made
  # (0.5..1 ms seen under TCG). So the median within [lag_low - 0.05 ms, lag_high + 3 ms].
  lo=$(sed -n 's/.*lag_low_p50_us=\([0-9]*\).*/\1/p' g2g.mirror.out)
  hi=$(sed -n 's/.*lag_high_p50_us=\([0-9]*\).*/\1/p' g2g.mirror.out)
  awk -v l="${lo:-0}" -v d="$G2G_DELAY_US" 'BEGIN { exit !(l >= d) }' || { info "the loop's delay is short"; rc=1; }
  awk -v m="${median:-0}" -v l="${lo:-0}" -v h="${hi:-0}" \
    'BEGIN { exit !(m * 1000 >= l - 50 && m * 1000 <= h + 3000) }' ||
    { info "median $median ms is not the loop's delay ($lo..$hi us)"; rc=1; }
  [ $rc -eq 0 ] || { show g2g.mirror; show g2g-led.err; show g2g-stats.json; }
  return $rc
}

# The motion-onset trigger: m2mlat led --on-edge holds line 0 (the "Hall sensor") and flashes line 3
# at each of its falling edges, which the driver makes 100 ms apart; the mirror copies line 3 to
# line 4 as above. Every onset makes one flash, stored beside the onset edges (channel wheel), and
# every flash pairs with its photo edge.
t_g2g_onset() {
  "$M2MLAT" help 2>/dev/null | awk '$1 == "led" { found = 1 } END { exit !found }' ||
    { info "skipped: this m2mlat has no 'led' subcommand"; return 77; }
  need_record || return 77
  local n=8 rec mirror led rc=0 pairs
  "$M2MLAT" record --store onset.db --node guest --role effect --scenario g2g --channel "photo=$CHIP:4" \
    --edges both --json --quiet >onset-record.json 2>onset-record.err &
  rec=$!
  "$DRIVER" wait-used "/dev/$CHIP" 4 20000 >/dev/null || { show onset-record.err; return 1; }
  # Without --quiet: its "m2mlat: led:" line on stderr says it answers edges (store open, session begun).
  "$M2MLAT" led --chip "$CHIP" --line 3 --on-edge "wheel=$CHIP:0" --on-for 30ms --store onset.db \
    --node guest --scenario g2g --json >onset-led.json 2>onset-led.err &
  led=$!
  wait_ready 20 grep -q '^m2mlat: led:' onset-led.err || { show onset-led.err; kill -INT $led $rec; return 1; }
  rm -f onset.mirror.ready
  "$DRIVER" mirror --value "$SIM/sim_gpio3/value" --sim "$SIM/sim_gpio4" --delay-us "$G2G_DELAY_US" \
    --changes $((2 * n)) --duration-ms 30000 --log onset.mirror --ready onset.mirror.ready \
    >onset.mirror.out 2>&1 &
  mirror=$!
  wait_ready 10 test -e onset.mirror.ready || { info "the mirror did not start"; rc=1; }
  # 2n flips of line 0's pull, 100 ms apart, from pull-down: n rising and n falling edges.
  "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count $((2 * n)) --period-us 100000 >onset.toggle || rc=1
  wait $mirror || { info "mirror failed"; rc=1; }
  show onset.mirror.out
  kill -INT $led
  wait_exit $led 10 || { info "led exited $?"; show onset-led.err; rc=1; }
  sleep 0.2
  kill -INT $rec
  wait_exit $rec 10 || { info "record exited $?"; show onset-record.err; rc=1; }
  info "led: switches=$(json_field onset-led.json switches) trigger_edges=$(json_field onset-led.json trigger_edges)"
  [ "$(json_field onset-led.json trigger_edges)" = $n ] || { show onset-led.json; rc=1; }
  [ "$(json_field onset-led.json switches)" = $((2 * n)) ] || { show onset-led.json; rc=1; }
  "$M2MLAT" stats onset.db --cause guest/led --effect guest/photo --edge rising --json >onset-stats.json \
    2>onset-stats.err || { info "stats failed"; show onset-stats.err; return 1; }
  pairs=$(sed -n 's/^ *"n": *\([0-9]*\),*$/\1/p' onset-stats.json | head -n1)
  info "G2G: $pairs pairs, median $(sed -n 's/^ *"median_ms": *\([0-9.]*\),*$/\1/p' onset-stats.json | head -n1) ms"
  [ "$pairs" = $n ] || { info "expected $n pairs"; rc=1; }
  "$M2MLAT" export onset.db -o onset.csv 2>/dev/null || rc=1
  [ "$(grep -c ',guest,wheel,falling,' onset.csv)" = $n ] || { info "the onset edges are not all stored"; rc=1; }
  # The LED's lag behind its trigger (the kernel's stamp of the onset edge -> the LED event): positive,
  # the i-th flash after the i-th onset.
  # (m2mlat-events/2: scenario, session, label, node, channel, edge, clock, time_ns, ...)
  awk -F, '$5 == "wheel" && $6 == "falling" { w[nw++] = $8 } $5 == "led" && $6 == "rising" { l[nl++] = $8 }
    END { if (nw != nl || nw == 0) exit 1
          for (i = 0; i < nw; i++) { d = (l[i] - w[i]) / 1000; if (d <= 0) exit 1; s += d; if (d > m) m = d }
          printf "LED lag behind its trigger edge: mean %d us, max %d us\n", s / nw, m }' onset.csv >onset.lag ||
    { info "an LED flash is not after its trigger edge"; rc=1; }
  show onset.lag
  [ $rc -eq 0 ] || { show onset.mirror; show onset-led.err; show onset.csv; }
  return $rc
}

# ---- the LED at the gyroscope's own motion onset, and the raw trace beside it ----------------------
#
# One vehicle board, one chip, two programs (docs/capture.md): `record --gyro` keeps the stub's raw
# samples in a store while `led --on-gyro` reads the same chip and flashes line 3 at each rotation
# m2mlat-vm-gyro writes (rest, then 30 deg/s about x for 300 ms, GYRO_LED_N times, 400 ms apart).
# Each LED switch-on lies after the write that began its rotation, by at most GYRO_LED_BOUND_US (the
# streaming detector's stated p95 delay on fast motions, docs/onset.md; a rate step is seen within a
# read period or two); the onsets in `export --what gyro`'s trace (the first sample of the new rate)
# lie where the writes put them (within a read period, a read and the guest's stalls of the write).
GYRO_LED_N=${GYRO_LED_N:-3}
GYRO_LED_BOUND_US=${GYRO_LED_BOUND_US:-19000}

t_gyro_led() {
  have_gyro || { info "skipped: this m2mlat has no 'gyro' subcommand"; return 77; }
  "$M2MLAT" led --help 2>/dev/null | grep -q -- '--on-gyro' || { info "skipped: led has no --on-gyro"; return 77; }
  load_i2c_stub || return 1
  "$GYRO" set "$GYRO_DEV" 0x68 0x75 0x68 || return 1  # WHO_AM_I
  "$GYRO" motion --device "$GYRO_DEV" --address 0x68 --count 0 --rate 0 --rest-ms 0 --move-ms 0 \
    --log /dev/null || return 1  # the rates at rest
  local rec led rc=0
  "$M2MLAT" record --store gyro-led.db --node guest --role effect --channel "spare=$CHIP:5" \
    --gyro "$GYRO_DEV" --gyro-period 1ms --json --quiet >gl-record.json 2>gl-record.err &
  rec=$!
  "$DRIVER" wait-used "/dev/$CHIP" 5 20000 >/dev/null || { show gl-record.err; return 1; }
  "$M2MLAT" led --chip "$CHIP" --line 3 --on-gyro "$GYRO_DEV" --gyro-period 1ms --on-for 50ms \
    --events gl-led.csv --node guest --json --quiet >gl-led.json 2>gl-led.err &
  led=$!
  "$DRIVER" wait-used "/dev/$CHIP" 3 20000 >/dev/null || { show gl-led.err; kill -INT $rec; return 1; }
  sleep 0.5  # the detector learns the rest (100 ms of samples)
  "$GYRO" motion --device "$GYRO_DEV" --address 0x68 --count "$GYRO_LED_N" --rate 3930 --rest-ms 400 \
    --move-ms 300 --log gl.motion || rc=1
  sleep 0.3
  kill -INT $led
  wait_exit $led 10 || { info "led exited $?"; show gl-led.err; rc=1; }
  kill -INT $rec
  wait_exit $rec 10 || { info "record exited $?"; show gl-record.err; rc=1; }
  info "led: onsets=$(json_field gl-led.json onsets) switches=$(json_field gl-led.json switches)"
  [ "$(json_field gl-led.json onsets)" = "$GYRO_LED_N" ] || { info "expected $GYRO_LED_N onsets"; rc=1; }
  [ "$(json_field gl-led.json switches)" = $((2 * GYRO_LED_N)) ] || { show gl-led.json; rc=1; }
  "$M2MLAT" export gyro-led.db --what gyro -o gl-trace.csv 2>gl-export.err || { show gl-export.err; return 1; }
  info "record: $(grep -c '^[0-9]' gl-trace.csv) samples stored"
  # LED switch-on k after onset k's write began, by at most the bound; the trace's first sample of the
  # new rate within [write began - its bound, write ended + 10 ms] (a 1 ms read period, a read, and the
  # guest's stalls under TCG: the first rotation's took 5.4 ms once in four runs on a quiet host, the
  # others 0.2-0.5 ms; most likely code run for the first time, which QEMU translates then).
  awk -v bound="$GYRO_LED_BOUND_US" -v n="$GYRO_LED_N" '
    FILENAME == "gl.motion" { b[$1] = $2; a[$1] = $3; next }
    FILENAME == "gl-led.csv" && /^#/ { next }
    FILENAME == "gl-led.csv" && !lh { lh = 1; for (i = 1; i <= NF; i++) lc[$i] = i; next }
    FILENAME == "gl-led.csv" { if ($lc["channel"] == "led" && $lc["edge"] == "rising") l[nl++] = $lc["time_ns"]; next }
    /^[0-9]/ { split($0, f, ","); if (f[3] != 0 && prev == 0) t[nt++] = f[1] " " f[2]; prev = f[3] }
    END {
      if (nl != n || nt != n) { printf "%d LED switch-ons, %d onsets in the trace, expected %d\n", nl, nt, n; exit 1 }
      for (k = 0; k < n; k++) {
        d = (l[k] - b[k]) / 1000; split(t[k], s, " "); e = (s[1] - b[k]) / 1000
        printf "onset %d: LED on %d us after the write began; trace onset %d us after (bound %d us)\n", k, d, e, s[2] / 1000
        if (d <= 0 || (l[k] - a[k]) / 1000 > bound) bad = 1
        if (s[1] + s[2] < b[k] || s[1] - s[2] > a[k] + 10000000) bad = 1
      }
      exit bad }' FS=' ' gl.motion FS=, gl-led.csv FS=, gl-trace.csv >gl.check || rc=1
  show gl.check
  [ $rc -eq 0 ] || { show gl.motion; show gl-led.err; show gl-record.json; }
  return $rc
}

# ---- packets across a netem link: m2mlat packets live on both ends (tests/integration/packets_netem.sh) --

# The integration test's setup in this kernel, which has sch_netem (the build hosts' kernels do not):
# three network namespaces (sender, router, receiver) joined by veth pairs, `tc qdisc ... netem
# delay` on the router's link to the receiver (a capture on an interface sees its outgoing packets
# after that interface's queueing discipline, so the delay must not sit on the sender's own), 100
# length-prefixed JSON commands over TCP and 100 datagrams over UDP at 100 Hz (m2mlat-vm-traffic),
# `m2mlat packets --interface` capturing live on both ends. Each command's one-way time from the
# two captures must be within 0.1 ms of what the two ends' clocks say (the kernel's socket
# timestamps: sent, received), and the median within 1 ms of netem's delay. ip and tc are the
# host's iproute2 (busybox's tc has no netem).
TRAFFIC=/bin/m2mlat-vm-traffic
NETEM_DELAY_MS=${NETEM_DELAY_MS:-20}
t_packets_netem() {
  local ip=/usr/sbin/ip tc=/usr/sbin/tc snd=m2s rtr=m2r rcv=m2v side pids="" rc=0 m
  "$M2MLAT" help 2>/dev/null | awk '$1 == "packets" { f = 1 } END { exit !f }' ||
    { info "skipped: this m2mlat has no 'packets' subcommand"; return 77; }
  for m in veth sch_netem; do
    grep -q "^$m " /proc/modules || insmod "/lib/modules/$m.ko" || { info "insmod $m failed"; return 1; }
  done
  $ip netns add $snd && $ip netns add $rtr && $ip netns add $rcv || { info "ip netns add failed"; return 1; }
  $ip link add s0 netns $snd type veth peer name r0 netns $rtr &&
    $ip link add r1 netns $rtr type veth peer name v0 netns $rcv &&
    $ip -n $snd addr add 10.201.1.1/24 dev s0 && $ip -n $rtr addr add 10.201.1.2/24 dev r0 &&
    $ip -n $rtr addr add 10.201.2.1/24 dev r1 && $ip -n $rcv addr add 10.201.2.2/24 dev v0 &&
    for side in "$snd s0" "$rtr r0" "$rtr r1" "$rcv v0" "$snd lo" "$rtr lo" "$rcv lo"; do
      set -- $side
      $ip -n "$1" link set "$2" up || return 1
    done &&
    $ip -n $snd route add default via 10.201.1.2 && $ip -n $rcv route add default via 10.201.2.1 &&
    $ip netns exec $rtr sh -c 'echo 1 >/proc/sys/net/ipv4/ip_forward' ||
    { info "setting up the namespaces failed"; return 1; }
  $ip netns exec $rtr $tc qdisc add dev r1 root netem delay "${NETEM_DELAY_MS}ms" 2>tc.err ||
    { info "tc qdisc add ... netem failed"; show tc.err; return 1; }
  info "netem: $($ip netns exec $rtr $tc qdisc show dev r1)"

  local filter="(tcp port 7000 or udp port 7001) and host 10.201.1.1"
  for side in "$snd s0 snd" "$rcv v0 rcv"; do
    set -- $side
    $ip netns exec "$1" "$M2MLAT" packets --interface "$2" --filter "$filter" --key json:id --sender-ms stamp \
      --node "$3" --write "$3.pcap" --csv -o "$3.live.csv" 2>"$3.err" &
    pids="$pids $!"
  done
  for side in snd rcv; do
    wait_ready 10 grep -q "capturing on" "$side.err" 2>/dev/null  # judged on the next line
    grep -q "capturing on .* (timestamps: host)" "$side.err" || { info "$side capture did not start"; show "$side.err"; rc=1; }
  done
  [ $rc = 0 ] || { kill $pids; return 1; }
  $ip netns exec $rcv "$TRAFFIC" recv 10.201.2.2 7000 7001 >recv.log 2>recv.err &
  local receiver=$!
  wait_ready 10 grep -q ready recv.err 2>/dev/null  # a receiver that never got ready fails the sender
  $ip netns exec $snd "$TRAFFIC" send 10.201.2.2 7000 7001 100 >send.log 2>send.err ||
    { info "the sender failed"; show send.err; rc=1; }
  wait_exit $receiver 20 || { info "the receiver failed"; show recv.err; rc=1; }
  sleep 0.2  # the captures see the last packets
  kill -TERM $pids
  for m in $pids; do wait_exit "$m" 20 || { info "a capture failed"; show snd.err; show rcv.err; rc=1; }; done
  [ $rc = 0 ] || return 1

  # The files written while capturing, matched by key, against the two ends' socket timestamps.
  # The sender's kernel stamps each packet twice, on entering the device's queueing (sched) and in
  # the driver (snd); the capture tap lies between the two, so the sender's clock says "sent within
  # [sched, snd]" (under TCG that window is up to ~0.15 ms wide: the emulated CPU runs the stack
  # slowly). The receiver's kernel stamps a datagram at the very instant the capture sees it (the
  # same skb timestamp), but a TCP segment, which carries the sender's monotonic departure time, at
  # its local delivery, after the tap (under TCG up to ~2 ms later): for TCP the receiver's clock
  # says "received no later than". Per command: the capture's send time within 0.1 ms of the
  # sender's window, its receive time within 0.1 ms of the receiver's stamp (UDP) or not more than
  # 0.1 ms after it (TCP); so its one-way time within 0.1 ms of what the two clocks allow.
  "$M2MLAT" packets snd.pcap --peer rcv.pcap --filter "$filter" --key json:id --sender-ms stamp --csv -o oneway.csv \
    2>oneway.err || { info "m2mlat packets on the two files failed"; show oneway.err; return 1; }
  # awk holds numbers as doubles, exact to 2^53 only: CLOCK_REALTIME in ns (about 1.8e18) is
  # subtracted on its last 13 digits (10^4 s), with the wrap of that window undone. Each behind a
  # "1": busybox awk reads a number with a leading 0 as octal, so in the first 1000 s of every 10^4
  # ("0552...") the digits were misread and the test failed.
  awk -v expected=$((NETEM_DELAY_MS * 1000000)) '
    function diff(a, b,  d) {
      d = ("1" substr(a, length(a) - 12)) - ("1" substr(b, length(b) - 12))
      return d < -5e12 ? d + 1e13 : d > 5e12 ? d - 1e13 : d
    }
    function note(p, name, x) {
      if (!((p, name) in lo) || x < lo[p, name]) lo[p, name] = x
      if (!((p, name) in hi) || x > hi[p, name]) hi[p, name] = x
    }
    FILENAME == "send.log" { snd[$1] = $2; sched[$1] = $3; nsent++; next }
    FILENAME == "recv.log" { received[$1] = $2; next }
    /^#/ { next }
    !header { header = 1; for (i = 1; i <= NF; i++) col[$i] = i; next }
    {
      key = $col["key"]; ow = $col["one_way_ns"]; p = substr(key, 1, 1) == "t" ? "TCP" : "UDP"
      if (!(key in snd) || !(key in received)) { print "unknown key " key; bad = 1; next }
      # the capture send time against the window [sched, snd]: negative before it, positive after
      early = diff(sched[key], $col["sent_ns"]); late = diff($col["sent_ns"], snd[key])
      out = early > 0 ? -early : late > 0 ? late : 0
      # the capture receive time minus the receiver stamp
      dr = diff($col["received_ns"], received[key])
      note(p, "window", diff(snd[key], sched[key])); note(p, "out", out); note(p, "dr", dr)
      if (out < -100000 || out > 100000) { printf "%s: sent %d ns outside the window [sched, snd]\n", key, out; bad = 1 }
      if (dr > 100000 || (p == "UDP" && dr < -100000)) {
        printf "%s: received %d ns from the receiver stamp\n", key, dr; bad = 1
      }
      if ($col["sender_to_sent_ns"] > s2s_max) s2s_max = $col["sender_to_sent_ns"]
      v[++n] = ow
    }
    END {
      if (n != 200 || nsent != 200) { printf "%d commands matched, %d sent, expected 200\n", n, nsent; bad = 1 }
      # insertion sort of 200 values: the median as statistics.median takes it
      for (i = 2; i <= n; i++) { x = v[i]; for (j = i - 1; j > 0 && v[j] > x; j--) v[j + 1] = v[j]; v[j + 1] = x }
      median = n % 2 ? v[(n + 1) / 2] : (v[n / 2] + v[n / 2 + 1]) / 2
      d = median - expected; if (d < 0) d = -d
      if (d > 1000000) { printf "median one-way %d ns, netem delay %d ns\n", median, expected; bad = 1 }
      printf "%d commands, one-way median %.3f ms (netem %d ms), min %.3f ms, max %.3f ms\n",
        n, median / 1e6, expected / 1e6, v[1] / 1e6, v[n] / 1e6
      for (p = 0; p < 2; p++) {
        k = p ? "UDP" : "TCP"
        printf "%s: capture send time outside the sender window [sched, snd] %.1f..%.1f us", k, lo[k, "out"] / 1e3, hi[k, "out"] / 1e3
        printf " (window %.1f..%.1f us wide);", lo[k, "window"] / 1e3, hi[k, "window"] / 1e3
        printf " capture receive time minus receiver stamp %.1f..%.1f us\n", lo[k, "dr"] / 1e3, hi[k, "dr"] / 1e3
      }
      printf "sender stamp (whole ms) to capture at most %.3f ms\n", s2s_max / 1e6
      exit bad
    }' FS=' ' send.log recv.log FS=',' oneway.csv >judge.txt
  rc=$?
  show judge.txt
  m=$(grep -c ',packet,' snd.live.csv)
  [ "$m" = 200 ] || { info "the sender's live markers: $m, expected 200"; rc=1; }
  for m in $snd $rtr $rcv; do $ip netns del $m; done
  return $rc
}

# ---- performance: m2mlat record against Debian's gpiomon on the same streams of edges ---------------

# capture_run NAME TOOL PACE_US N: runs TOOL (record | gpiomon) under the driver's rusage while N edges
# are made P us apart (0: as fast as the guest can), then stops it with SIGINT. Leaves NAME.rusage,
# NAME.out (gpiomon's lines, or record's JSON summary) and NAME.db (record's store).
capture_run() {
  local name=$1 tool=$2 pace=$3 n=$4 pid
  if [ "$tool" = record ]; then
    "$DRIVER" rusage "$name.rusage" -- "$M2MLAT" record --store "$name.db" --node guest \
      --channel "hall=$CHIP:0" --edges both --json --quiet >"$name.out" 2>"$name.err" &
  else
    "$DRIVER" rusage "$name.rusage" -- gpiomon "$CHIP" 0 >"$name.out" 2>"$name.err" &
  fi
  pid=$!
  "$DRIVER" wait-used "/dev/$CHIP" 0 20000 >/dev/null || { show "$name.err"; return 1; }
  sleep 0.3
  [ "$n" = 0 ] || "$DRIVER" toggle --sim "$SIM/sim_gpio0" --count "$n" --period-us "$pace" >"$name.toggle"
  sleep 1
  kill -INT $pid
  wait_exit $pid 30 || { info "$tool exited $?"; show "$name.err"; return 1; }
}

# rss_kb NAME: the peak resident memory of the run (VmHWM), KiB.
rss_kb() { sed 's/.*maxrss_kb=\([0-9]*\).*/\1/' "$1.rusage"; }
# user_sys NAME: "user U sys S" (us) of the run.
user_sys() { sed 's/user_us=\([0-9]*\) sys_us=\([0-9]*\) .*/user \1 sys \2/' "$1.rusage"; }
# cpu_us NAME: user + system CPU time of the run, in us.
cpu_us() { sed 's/user_us=\([0-9]*\) sys_us=\([0-9]*\) .*/\1 \2/' "$1.rusage" | awk '{ print $1 + $2 }'; }
# per_event CPU_US EVENTS [FIXED_US]: CPU time per event, us with two decimals; with FIXED_US also
# " (N net)", the same without the fixed cost of a run without edges.
per_event() {
  awk -v c="$1" -v e="$2" -v f="${3:-}" 'BEGIN {
    printf "%.2f", (e > 0 ? c / e : 0)
    if (f != "") printf " (%.2f net)", (e > 0 ? (c - f) / e : 0) }'
}

# One stream paced at 100 us (10k edges/s), one as fast as the guest can make them. Reported: events
# captured, losses (record's from seqno; gpiomon, on the v1 uAPI, has no seqno and cannot see its
# losses, so "missing" = edges made - events captured), CPU time per captured event, peak resident
# memory, and record's edge -> durable commit latency: record measures it itself, for every stored
# event, from the kernel's timestamp to the return of the commit that made it durable (both on
# CLOCK_REALTIME; p50 and p99 within 3 %). Asserted: every edge of the paced stream is either stored
# by record or counted by it as lost, and record's peak resident memory is under 24 MiB. (It was 20:
# a run without edges took 19.3 MiB, most of it the pages of the larger executable and its
# libraries, and the streams peaked at 19.4-20.2 MiB, failing now and then by 1 %. Since libpq is
# loaded only by the archive, 14.8 MiB and 14.9-15.5 MiB. The reader's queue, at most 16 chunks of
# 1024 events, and SQLite's page cache, at most 2 MB, fit in the rest.)
t_perf_gpiomon() {
  need_record || return 77
  command -v gpiomon >/dev/null || { info "skipped: gpiomon is not in this guest"; return 77; }
  local n=10000 pace rc=0 events losses cpu rss rec_fixed mon_fixed
  # The fixed cost of a run (start-up, store creation, shutdown; for m2mlat under TCG a sizeable
  # share of 10,000 events), from a run without edges.
  capture_run perf-rec-idle record 0 0 || return 1
  capture_run perf-mon-idle gpiomon 0 0 || return 1
  rec_fixed=$(cpu_us perf-rec-idle)
  mon_fixed=$(cpu_us perf-mon-idle)
  info "a run without edges: m2mlat record CPU $rec_fixed us, peak RSS $(rss_kb perf-rec-idle) KiB;" \
    "gpiomon CPU $mon_fixed us"
  for pace in 100 0; do
    capture_run "perf-rec-$pace" record $pace $n || return 1
    capture_run "perf-mon-$pace" gpiomon $pace $n || return 1
    events=$(json_field "perf-rec-$pace.out" events)
    losses=$(json_field "perf-rec-$pace.out" losses)
    cpu=$(cpu_us "perf-rec-$pace")
    info "stream period ${pace} us, $n edges ($(sed 's/.*elapsed_us=\([0-9]*\).*/\1/' "perf-rec-$pace.toggle") us):"
    rss=$(rss_kb "perf-rec-$pace")
    info "  m2mlat record: $events events, $losses lost (seqno), $((n - events - losses)) missing otherwise," \
      "CPU $cpu us ($(user_sys "perf-rec-$pace")), $(per_event "$cpu" "$events" "$rec_fixed") us/event," \
      "peak RSS $rss KiB"
    info "    edge -> durable commit: p50 $(ns_to_us "$(json_field "perf-rec-$pace.out" p50)") us," \
      "p99 $(ns_to_us "$(json_field "perf-rec-$pace.out" p99)") us," \
      "max $(ns_to_us "$(json_field "perf-rec-$pace.out" max)") us"
    if [ "${rss:-0}" -ge 24576 ]; then
      info "  record's peak resident memory $rss KiB is not under 24 MiB"
      rc=1
    fi
    if [ "$pace" != 0 ] && [ $((events + losses)) -ne $n ]; then
      info "  record accounted for $((events + losses)) of $n paced edges"
      rc=1
    fi
    events=$(grep -c . "perf-mon-$pace.out")
    cpu=$(cpu_us "perf-mon-$pace")
    info "  gpiomon:       $events events, $((n - events)) missing (it cannot tell)," \
      "CPU $cpu us ($(user_sys "perf-mon-$pace")), $(per_event "$cpu" "$events" "$mon_fixed") us/event," \
      "peak RSS $(rss_kb "perf-mon-$pace") KiB"
  done
  return $rc
}

run_test smoke.boot t_boot
run_test smoke.chip t_chip
run_test smoke.driver-lockstep t_driver_lockstep
run_test smoke.version t_version
run_test record.lockstep t_record_lockstep
run_test record.edge-types t_record_edges
run_test record.shutdown t_record_shutdown
run_test record.stall t_record_stall
run_test record.refractory t_record_refractory
run_test record.busy-line t_record_busy
run_test record.missing-chip t_record_missing_chip
run_test cli.doctor t_doctor
run_test pulse.output t_pulse
run_test g2g.led-photo t_g2g
run_test g2g.onset-trigger t_g2g_onset
run_test gyro.no-bus t_gyro_no_bus
run_test gyro.trace t_gyro_trace
run_test gyro.errors t_gyro_errors
run_test gyro.led-onset t_gyro_led
run_test packets.netem t_packets_netem
run_test perf.record-vs-gpiomon t_perf_gpiomon
