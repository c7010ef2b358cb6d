# The command loop of both guests of the two-guest test (busybox sh, run by /init with ROLE and SIM
# set). The host writes one command per line to the guest's /dev/ttyS2 (a TCP chardev on the host);
# each gets exactly one answer line, "ok ..." or "err ...". Everything else goes to the console.
#
#   ping TAG             -> pong ROLE TAG
#   chrony-start         chronyd with the configuration `m2mlat setup chrony` writes for this role
#                        (operator: the reference, serves its own clock at `local stratum 5`;
#                        vehicle: the peer, follows 10.0.0.1, polls every 0.25 s, steps)
#   chrony-wait SECONDS  until chronyc says synchronised and |system time offset| < 100 us three
#                        times in a row (1 s apart) -> ok <chronyc -c tracking line>
#   tracking             -> ok <chronyc -c tracking line>
#   chrony-stop          stops chronyd: from now on the clock runs free (no sync between the guests)
#   shift NS             steps CLOCK_REALTIME by NS (m2mlat-2g-shift-clock) -> ok <its line>
#   agent-start NAME CHRONY_INTERVAL
#                        m2mlat agent recording line 0 as channel "latency" and line 1 as "pulse"
#                        into /tmp/NAME.db, API on port 8470 (with the host's token), reading chronyc
#                        every CHRONY_INTERVAL (0: never)
#   agent-stop           SIGTERM to the agent -> ok <its exit status>
#   log FILE             -> ok <the file's last 20 lines, joined by " | ">
#   poweroff
console() { echo "twoguest[$ROLE]: $*" >/dev/console; }
AGENT=""

tracking() { chronyc -c -n tracking 2>&1 | head -n 1; }

chrony_start() {
  mkdir -p /run/chrony /var/lib/chrony /var/log/chrony
  chmod 750 /run/chrony
  # The configurations `m2mlat setup chrony` writes for the two co-referenced roles, so that this test
  # also shows them synchronising two kernels. Operator: local stratum 5 (as a reference without an
  # upstream server). Vehicle: minpoll/maxpoll -2, a request every 0.25 s (the reference rig polls
  # every 4 s; the test has seconds, not minutes, to converge) and the default makestep 0.005 3: the
  # guest boots with the host's RTC, up to a second off the operator's clock, and is stepped at its
  # first update (at maxslewrate 500 a slew of 49 ms would take 100 s). Both keep
  # rtcsync: once synchronised, chronyd clears the kernel's STA_UNSYNC, so the vehicle's adjtimex
  # samples say synchronised. The operator's never do: chronyd serving its own clock leaves
  # STA_UNSYNC set (m2mlat's uncertainty then uses chrony's samples).
  if [ "$ROLE" = operator ]; then
    m2mlat setup chrony --mode co-referenced --role reference --allow 10.0.0.0/24 --local-stratum 5 \
      --output /etc/chrony.conf >/dev/console 2>&1
  else
    m2mlat setup chrony --mode co-referenced --role peer --reference 10.0.0.1 --minpoll -2 --maxpoll -2 \
      --output /etc/chrony.conf >/dev/console 2>&1
  fi || return 1
  chronyd -u root -f /etc/chrony.conf >/dev/console 2>&1
}

# synced_once: chronyc reports a reference and a system time offset under 100 us.
synced_once() {
  tracking | awk -F, 'NF >= 14 { c = $5 < 0 ? -$5 : $5; ok = $14 != "Not synchronised" && c < 0.0001 }
                      END { exit !ok }'
}

chrony_wait() {
  local left=$1 good=0
  while [ "$left" -gt 0 ]; do
    if synced_once; then good=$((good + 1)); else good=0; fi
    [ $good -ge 3 ] && { echo "ok $(tracking)"; return; }
    sleep 1
    left=$((left - 1))
  done
  echo "err not synchronised: $(tracking)"
}

agent_start() {
  local role=cause
  [ "$ROLE" = vehicle ] && role=effect
  rm -f /tmp/agent.port
  m2mlat agent --store "/tmp/$1.db" --node "$ROLE" --role $role --scenario "$1-idle" \
    --channel latency=m2mlat-2g:0 --channel pulse=m2mlat-2g:1 --edges both \
    --chrony-interval "$2" --listen 0.0.0.0:8470 --token-file /etc/m2mlat-token \
    --port-file /tmp/agent.port >"/tmp/agent-$1.log" 2>&1 &
  AGENT=$!
  local left=200
  while [ ! -s /tmp/agent.port ] && [ $left -gt 0 ] && kill -0 $AGENT 2>/dev/null; do
    sleep 0.1
    left=$((left - 1))
  done
  if [ -s /tmp/agent.port ]; then echo "ok pid $AGENT"; else echo "err agent did not start: $(tail -n 3 "/tmp/agent-$1.log" | tr '\n' ' ')"; fi
}

agent_stop() {
  [ -n "$AGENT" ] || { echo "err no agent"; return; }
  kill -TERM $AGENT
  wait $AGENT
  echo "ok $?"
  AGENT=""
}

stty -F /dev/ttyS2 raw -echo
exec </dev/ttyS2 >/dev/ttyS2
console "ready"
while IFS= read -r line; do
  set -- $line
  cmd=${1:-}
  [ $# -gt 0 ] && shift
  console "command: $cmd $*"
  case $cmd in
    ping) echo "pong $ROLE $*" ;;
    chrony-start) chrony_start && echo ok || echo "err m2mlat setup chrony or chronyd failed (see the console)" ;;
    chrony-wait) chrony_wait "${1:-30}" ;;
    tracking) echo "ok $(tracking)" ;;
    chrony-stop) kill "$(cat /run/chrony/chronyd.pid)" && sleep 0.5 && echo ok || echo "err no chronyd" ;;
    shift) echo "ok $(m2mlat-2g-shift-clock "$1" 2>&1)" ;;
    agent-start) agent_start "$1" "${2:-8s}" ;;
    agent-stop) agent_stop ;;
    log) echo "ok $(tail -n 20 "$1" 2>&1 | tr '\n' '|')" ;;
    poweroff) echo ok; sleep 0.2; poweroff -f ;;
    "") ;;
    *) echo "err unknown command '$cmd'" ;;
  esac
done
console "command channel closed"
poweroff -f
