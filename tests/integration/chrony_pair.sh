#!/usr/bin/env bash
# Two real chronyd 4.3 daemons on this machine, configured by `m2mlat setup chrony`: a reference
# serving its own clock (local stratum 1) on an ephemeral UDP port of 127.0.0.1, and a peer
# following it with a 0.25 s poll. Both run with -x (never touch the system clock), in the
# foreground, with their own pid files and command sockets in the test's temporary folder. Then
# `m2mlat clock` reads the real chronyc output of both and stores samples, and an agent's clock
# monitor stores and serves the peer's. Needs root (chronyd).
source "$(dirname "$0")/lib.bash"
command -v chronyd >/dev/null && command -v chronyc >/dev/null || fail "chronyd/chronyc are not installed"
[ "$(id -u)" = 0 ] || fail "needs root: chronyd binds its command socket and ntp port as root"

PORT=$($PY -c 'import socket; s=socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')

# 1. The generated configurations; --dry-run first (prints, writes nothing), then for real.
"$M2MLAT" setup chrony --mode co-referenced --role reference --allow 127.0.0.1 \
  --driftfile "$WORK/ref.drift" --output "$WORK/ref.conf" --dry-run >dry.txt
[ ! -e "$WORK/ref.conf" ] || fail "--dry-run wrote the file"
grep -q "would write $WORK/ref.conf" dry.txt || fail "--dry-run did not announce the file: $(cat dry.txt)"
"$M2MLAT" setup chrony --mode co-referenced --role reference --allow 127.0.0.1 \
  --driftfile "$WORK/ref.drift" --output "$WORK/ref.conf" >/dev/null
"$M2MLAT" setup chrony --mode co-referenced --role peer --reference 127.0.0.1 --reference-port "$PORT" \
  --minpoll -2 --maxpoll -2 --driftfile "$WORK/peer.drift" --output "$WORK/peer.conf" >/dev/null
for f in ref peer; do chronyd -p -f "$WORK/$f.conf" >/dev/null || fail "chronyd -p refuses $f.conf"; done
grep -q "^server 127.0.0.1 port $PORT minpoll -2 maxpoll -2 iburst" "$WORK/peer.conf" || fail "peer.conf: $(cat "$WORK/peer.conf")"

# 2. The generated files plus what a test on a shared machine needs: own ports, sockets, pid files, logs.
cat "$WORK/ref.conf" - >"$WORK/ref.run.conf" <<CONF
port $PORT
cmdport 0
bindcmdaddress $WORK/ref.sock
pidfile $WORK/ref.pid
logdir $WORK
CONF
cat "$WORK/peer.conf" - >"$WORK/peer.run.conf" <<CONF
port 0
cmdport 0
bindcmdaddress $WORK/peer.sock
pidfile $WORK/peer.pid
logdir $WORK
CONF
chronyd -u root -x -d -f "$WORK/ref.run.conf" >ref.log 2>&1 &
PIDS+=($!)
chronyd -u root -x -d -f "$WORK/peer.run.conf" >peer.log 2>&1 &
PIDS+=($!)

# 3. Wait (at most 40 s) until the peer is synchronised to the reference, reading it through m2mlat.
synced=0
for _ in $(seq 80); do
  if "$M2MLAT" clock --chrony on --ptp off --chronyc-socket "$WORK/peer.sock" --json >peer.json 2>peer.err &&
    $PY -c 'import json,sys; d=json.load(open("peer.json")); c=[s for s in d["samples"] if s["source"]=="chrony"]; sys.exit(0 if c and c[0]["synchronised"] and c[0]["detail"]["stratum"]==2 else 1)'; then
    synced=1
    break
  fi
  sleep 0.5
done
[ "$synced" = 1 ] || { cat ref.log peer.log peer.err peer.json >&2 || true; fail "the peer did not synchronise"; }

$PY - <<'PY' || fail "m2mlat clock's reading of the peer"
import json
d = json.load(open("peer.json"))
assert d["errors"] == {}, d["errors"]
c = [s for s in d["samples"] if s["source"] == "chrony"][0]
t = c["detail"]
assert t["ref_id"] == "7F000001" and t["ref_name"] == "127.0.0.1", t
assert t["stratum"] == 2 and t["leap_status"] == "Normal", t
assert c["offset_ns"] == t["system_offset_ns"]
assert c["max_error_ns"] == abs(t["system_offset_ns"]) + t["root_dispersion_ns"] + t["root_delay_ns"] // 2, c
assert c["est_error_ns"] == max(t["rms_offset_ns"], abs(t["system_offset_ns"])), c
assert t["root_delay_ns"] > 0 and t["ref_time_ns"] > 1_600_000_000 * 10**9, t
src = t["sources"]
assert len(src) == 1 and src[0]["name"] == "127.0.0.1" and src[0]["state"] == "*" and src[0]["mode"] == "^", src
assert src[0]["poll"] == -2 and src[0]["stratum"] == 1, src
k = [s for s in d["samples"] if s["source"] == "adjtimex"]
assert len(k) == 1, d["samples"]
PY

# 4. The reference: synchronised to its own clock at stratum 1 (reference id 7F7F0101 = "LOCL").
"$M2MLAT" clock --chrony on --ptp off --chronyc-socket "$WORK/ref.sock" --json >ref.json
$PY - <<'PY' || fail "m2mlat clock's reading of the reference"
import json
d = json.load(open("ref.json"))
c = [s for s in d["samples"] if s["source"] == "chrony"][0]
assert c["synchronised"] and c["detail"]["stratum"] == 1 and c["detail"]["ref_id"] == "7F7F0101", c
assert c["detail"]["sources"] == [], c
PY

# 5. --watch into a store: one session labelled "clock" with adjtimex and chrony samples.
"$M2MLAT" clock --watch --count 3 --interval 200ms --chrony on --ptp off --chronyc-socket "$WORK/peer.sock" \
  --store clock.db --node peer >watch.txt
grep -q "^chrony:  synchronised to 127.0.0.1 (7F000001), stratum 2" watch.txt || fail "watch output: $(cat watch.txt)"
$PY - <<'PY' || fail "the stored clock samples"
import sqlite3
db = sqlite3.connect("clock.db")
sessions = db.execute("SELECT id, label, node, end_ns IS NOT NULL FROM sessions").fetchall()
assert sessions == [(1, "clock", "peer", 1)], sessions
rows = db.execute("SELECT source, COUNT(*) FROM clock_samples GROUP BY source ORDER BY source").fetchall()
assert dict(rows)["chrony"] == 3 and dict(rows)["adjtimex"] >= 3, rows
PY

# 6. An agent's clock monitor: a kmsg-source agent reading the peer's chronyd every 300 ms stores
# chrony and adjtimex samples in its own commits, serves them on /v1/clock-samples, and shows the
# newest in /v1/status.
printf 'GPIO_16_IRQ:1780000000000000000\n' >edges.log
"$M2MLAT" agent --store agent.db --node peer --role effect --source kmsg --kmsg edges.log --channel wheel=k:16 \
  --listen 127.0.0.1:0 --chrony-interval 300ms --kernel-interval 200ms --chronyc-socket "$WORK/peer.sock" \
  --commit-interval 50ms --quiet >agent.out 2>agent.err &
AGENT=$!
PIDS+=($AGENT)
for _ in $(seq 100); do grep -q '^listening ' agent.out && break; sleep 0.1; done
URL="http://$(sed -n 's/^listening //p' agent.out)"
[ "$URL" != "http://" ] || { cat agent.err >&2; fail "the agent did not start"; }
$PY - "$URL" <<'PY' || { cat agent.err >&2; fail "the agent's clock samples"; }
import json, sys, time, urllib.request
url = sys.argv[1]
# Three of each: 1 s at the intervals above, but a loaded machine runs chronyc and commits later,
# so wait for them (a fixed 1.5 s was not always enough); 30 s is a safety net.
deadline = time.monotonic() + 30
while True:
    rows = [json.loads(l) for l in urllib.request.urlopen(url + "/v1/clock-samples?after=0").read().decode().splitlines()]
    chrony = [r for r in rows if r["source"] == "chrony"]
    kernel = [r for r in rows if r["source"] == "adjtimex"]
    if (len(chrony) >= 3 and len(kernel) >= 3) or time.monotonic() > deadline:
        break
    time.sleep(0.1)
assert len(chrony) >= 3 and len(kernel) >= 3, rows
for r in chrony:
    assert r["synchronised"] and r["detail"]["stratum"] == 2 and r["detail"]["ref_name"] == "127.0.0.1", r
    assert 0 < r["max_error_ns"] < 10**9, r
status = json.load(urllib.request.urlopen(url + "/v1/status"))
assert status["clock"] is not None and status["clock"]["source"] in ("chrony", "adjtimex"), status
PY
kill -TERM "$AGENT"
wait "$AGENT" || fail "the agent did not stop cleanly: $(cat agent.err)"
[ ! -s agent.err ] || fail "the agent warned: $(cat agent.err)"

# 7. A chronyd that is not there: `--chrony on` fails with chronyc's message, `auto` just says so.
expect_exit 74 "$M2MLAT" clock --chrony on --ptp off --chronyc-socket "$WORK/none.sock"
grep -q "chronyc" err.txt || fail "no chronyc message: $(cat err.txt)"
expect_exit 0 "$M2MLAT" clock --ptp off --chronyc-socket "$WORK/none.sock"
grep -q "^chrony:  not available" out.txt || fail "auto mode: $(cat out.txt)"
echo "chrony_pair: ok"
