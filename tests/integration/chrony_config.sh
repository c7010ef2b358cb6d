#!/usr/bin/env bash
# Every configuration `m2mlat setup chrony` generates is accepted by Debian 12's chronyd 4.3
# (`chronyd -p -f FILE` parses it and prints it back; a bad directive makes it exit 1), and the
# files it writes (chrony.conf, the CPU drop-in, the backup) are what it announced.
source "$(dirname "$0")/lib.bash"
command -v chronyd >/dev/null || fail "chronyd is not installed"

# chronyd -p itself refuses a bad directive (so the checks below can fail).
printf 'server\n' >bad.conf
if chronyd -p -f bad.conf >/dev/null 2>&1; then fail "chronyd -p accepted a bad file"; fi

check() {
  local name=$1; shift
  "$M2MLAT" setup chrony "$@" >"$name.conf" || fail "setup chrony $*"
  chronyd -p -f "$name.conf" >"$name.parsed" 2>"$name.err" || fail "chronyd -p refuses '$*': $(cat "$name.err")"
}
check reference --mode co-referenced --role reference --allow 10.0.0.0/24 --allow 192.168.7.2
check peer --mode co-referenced --role peer --reference 10.0.0.1
check peer_fast --mode co-referenced --role peer --reference 10.0.0.1 --reference-port 11123 --minpoll -2 --maxpoll 0 --hwtimestamp eth0
check autonomous --mode autonomous
check autonomous_servers --mode autonomous --server ntp1.example.org --server 192.0.2.1 --pool pool.example.org
check gnss_shm --mode gnss-pps
check gnss_sock --mode gnss-pps --nmea /run/chrony.ttyAMA0.sock --pps-device /dev/pps1 --makestep '1.0 -1'

grep -q '^local stratum 1$' reference.parsed && grep -q '^allow 10.0.0.0/24$' reference.parsed &&
  grep -q '^allow 192.168.7.2$' reference.parsed || fail "reference: $(cat reference.parsed)"
grep -q '^server 10.0.0.1 minpoll 2 maxpoll 2 iburst prefer$' peer.parsed || fail "peer: $(cat peer.parsed)"
grep -q '^hwtimestamp eth0$' peer_fast.parsed || fail "peer_fast: $(cat peer_fast.parsed)"
grep -q '^pool 2.debian.pool.ntp.org iburst$' autonomous.parsed || fail "autonomous: $(cat autonomous.parsed)"
grep -q '^refclock PPS /dev/pps0 lock NMEA refid PPS prefer$' gnss_shm.parsed &&
  grep -q '^refclock SHM 0 refid NMEA' gnss_shm.parsed || fail "gnss: $(cat gnss_shm.parsed)"
grep -q '^refclock SOCK /run/chrony.ttyAMA0.sock' gnss_sock.parsed || fail "gnss sock: $(cat gnss_sock.parsed)"
for f in *.parsed; do
  grep -q '^makestep ' "$f" && grep -q '^rtcsync$' "$f" && grep -q '^maxslewrate 500$' "$f" ||
    fail "$f has no makestep/rtcsync/maxslewrate 500"
done

# Missing or bad options are usage errors (exit 2) and write nothing.
expect_exit 2 "$M2MLAT" setup chrony --mode co-referenced --role reference --output x.conf
expect_exit 2 "$M2MLAT" setup chrony --mode co-referenced --role peer --output x.conf
expect_exit 2 "$M2MLAT" setup chrony --mode sideways
expect_exit 2 "$M2MLAT" setup chrony --mode co-referenced --role peer --reference '10.0.0.1 bogus'
expect_exit 2 "$M2MLAT" setup
[ ! -e x.conf ] || fail "a refused setup wrote a file"

# Writing: the config and the drop-in, announced first; a second run backs up the changed file.
"$M2MLAT" setup chrony --mode autonomous --cpu 1 --output etc/chrony.conf --dropin etc/dropin/cpu.conf >w1.txt
grep -q "^writing etc/chrony.conf" w1.txt && grep -q "^writing etc/dropin/cpu.conf" w1.txt || fail "$(cat w1.txt)"
grep -q '^CPUAffinity=1$' etc/dropin/cpu.conf || fail "drop-in: $(cat etc/dropin/cpu.conf)"
chronyd -p -f etc/chrony.conf >/dev/null || fail "the written chrony.conf"
"$M2MLAT" setup chrony --mode autonomous --cpu 1 --output etc/chrony.conf --dropin etc/dropin/cpu.conf >w2.txt
grep -q "etc/chrony.conf: unchanged" w2.txt || fail "$(cat w2.txt)"
cp etc/chrony.conf before.conf
"$M2MLAT" setup chrony --mode gnss-pps --output etc/chrony.conf --dry-run >w3.txt
cmp -s etc/chrony.conf before.conf || fail "--dry-run changed the file"
grep -q "would copy etc/chrony.conf to etc/chrony.conf.m2mlat-backup" w3.txt || fail "$(cat w3.txt)"
"$M2MLAT" setup chrony --mode gnss-pps --output etc/chrony.conf >/dev/null
cmp -s etc/chrony.conf.m2mlat-backup before.conf || fail "no backup of the previous file"
grep -q '^refclock PPS' etc/chrony.conf || fail "not rewritten"
echo "chrony_config: ok"
