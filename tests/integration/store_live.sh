# Committed, served events survive other processes opening the live store (issue: a raw open and
# close of the store inside the agent dropped its SQLite locks, so `sqlite3 STORE` deleted the -wal
# under it: HTTP 500 "disk I/O error", and after kill -9 the store had lost events it had served).
# A running agent commits and serves while other processes open and close its store 100 times
# (sqlite3, and m2mlat commands that open it read-only or write beside the agent); /v1/status must
# answer 200 every time; then kill -9: every event the API served is in the store, unchanged. The
# agent restarted on that store closes the cut session and records the cut as a 'restart' loss. The
# same for collect's campaign store. Last, a store created on a full disk (a tiny tmpfs) leaves
# nothing behind (skipped, with a message, where mounting is not permitted).
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

# served_page AFTER: appends the events the agent serves after AFTER to served.jsonl; prints the last seq.
served_page() {
  local code
  code=$(curl -s --max-time 5 -o page.jsonl -w '%{http_code}' "$URL/v1/events?after=$1&limit=10000") || true
  [ "$code" = 200 ] || fail "GET /v1/events answered $code: $(head -c 300 page.jsonl)"
  cat page.jsonl >> served.jsonl
  $PY -c 'import json,sys; s=[json.loads(l)["seq"] for l in open("page.jsonl") if l.strip()]; print(s[-1] if s else sys.argv[1])' "$1"
}

start_agent vehicle effect 7 vehicle.db 127.0.0.1:0 --sim-paced --commit-interval 20ms
AGENT=$AGENT_PID
URL="http://127.0.0.1:$AGENT_PORT"
for i in 1 2 3; do printf 'GPIO_16_IRQ:%d000000000\n' "$i"; done > other.log

served=0
: > served.jsonl
: > status-codes.txt
for round in $(seq 100); do
  # Another process opens and closes the live store ...
  [ "$(sqlite3 vehicle.db 'select count(*) >= 0 from events')" = 1 ] || fail "round $round: sqlite3 could not read the store"
  # ... and, every few rounds, an m2mlat command does (read-only, or a writer beside the agent).
  case $((round % 5)) in
    0) "$M2MLAT" export vehicle.db > /dev/null ;;
    1) "$M2MLAT" stats vehicle.db --json > /dev/null 2>&1 || true ;;  # too few pairs is fine: it opened and closed the store
    2) "$M2MLAT" merge "campaign-$round.db" vehicle.db > /dev/null ;;
    3) "$M2MLAT" import --store vehicle.db other.log --node other --scenario beside > /dev/null ;;
  esac
  curl -s -o status.json -w '%{http_code}\n' --max-time 5 "$URL/v1/status" >> status-codes.txt
  served=$(served_page "$served")
done
[ -z "$(grep -v '^200$' status-codes.txt)" ] || fail "/v1/status answered $(sort status-codes.txt | uniq -c | tr '\n' ' ')"
[ "$served" -ge 10 ] || fail "the agent served only $served events"
[ -e vehicle.db-wal ] || fail "the -wal of the running agent is gone"
kill -9 "$AGENT"; wait "$AGENT" 2>/dev/null || true

# Every served event is in the store, unchanged (seq, session, channel, time, kernel counters).
sqlite3 -separator ' ' vehicle.db "select seq, session_id, channel, t_ns, seqno, line_seqno, flags from events where seq <= $served order by seq" > stored.txt
$PY - served.jsonl stored.txt <<'PY' || fail "served events missing from the store after kill -9"
import json, sys
served = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
rows = {int(r.split()[0]): r.split() for r in open(sys.argv[2])}
missing = [e["seq"] for e in served if e["seq"] not in rows]
assert not missing, f"{len(missing)} of {len(served)} served events missing, first {missing[:5]}"
for e in served:
    r = rows[e["seq"]]
    assert [int(r[1]), r[2], int(r[3]), int(r[4]), int(r[5]), int(r[6])] == \
        [e["session"], e["channel"], e["t_ns"], e["seqno"], e["line_seqno"], e["flags"]], (e, r)
assert [e["seq"] for e in served] == sorted(set(e["seq"] for e in served))
print(f"{len(served)} served events all stored")
PY
[ "$(sqlite3 vehicle.db 'pragma integrity_check')" = ok ] || fail "integrity_check after kill -9"

# The restarted agent closes the session the kill cut and records the cut.
open_before=$(sqlite3 vehicle.db "select id from sessions where node = 'vehicle' and end_ns is null")
[ -n "$open_before" ] || fail "kill -9 left no open session to close"
start_agent vehicle effect 7 vehicle.db 127.0.0.1:0 --sim-paced --commit-interval 20ms
AGENT=$AGENT_PID
kill -TERM "$AGENT"; wait "$AGENT" || fail "the restarted agent did not end cleanly"
[ "$(sqlite3 vehicle.db "select count(*) from sessions where node = 'vehicle' and end_ns is null")" = 0 ] ||
  fail "a session is still open after the restart"
[ "$(sqlite3 vehicle.db "select count(*) from losses where session_id = $open_before and kind = 'restart'")" = 1 ] ||
  fail "no restart loss for the cut session $open_before"
# Its end: the last time it committed anything (an event or a clock sample), never before its start
# (the simulated rig's edges carry the rig's own times).
last_t=$(sqlite3 vehicle.db "select max(start_ns, (select max(t_ns) from events where session_id = $open_before),
  (select coalesce(max(t_ns), 0) from clock_samples where session_id = $open_before)) from sessions where id = $open_before")
[ "$(sqlite3 vehicle.db "select end_ns from sessions where id = $open_before")" = "$last_t" ] ||
  fail "the cut session does not end at the last it committed"

# collect's campaign store: the coordinator commits while other processes open and close it.
start_agent operator cause 7 operator.db 127.0.0.1:0 --sim-paced --commit-interval 20ms
OP=$AGENT_PID; OP_URL="http://127.0.0.1:$AGENT_PORT"
"$M2MLAT" collect --agent "$OP_URL" --store campaign.db --quiet > collect.out 2> collect.err &
COLLECT_PID=$!
for _ in $(seq 100); do [ -e campaign.db ] && break; sleep 0.05; done
for round in $(seq 100); do
  sqlite3 campaign.db 'select count(*) from events' > /dev/null || fail "round $round: sqlite3 could not read the campaign store"
  [ $((round % 10)) = 0 ] && "$M2MLAT" export campaign.db > /dev/null
  kill -0 "$COLLECT_PID" 2>/dev/null || { cat collect.err >&2; fail "collect exited in round $round"; }
done
[ -e campaign.db-wal ] || fail "the -wal of the running coordinator is gone"
! grep -qi 'disk I/O\|error' collect.err || { cat collect.err >&2; fail "collect reported errors"; }
kill -9 "$COLLECT_PID"; wait "$COLLECT_PID" 2>/dev/null || true; COLLECT_PID=
kill -TERM "$OP"; wait "$OP" || true
# Everything the coordinator's cursor says it took is there: a second run adds exactly the rest.
"$M2MLAT" collect --agent "$OP_URL" --store campaign.db --duration 1s --quiet > /dev/null 2>&1 || true
[ "$(sqlite3 campaign.db 'pragma integrity_check')" = ok ] || fail "campaign integrity_check"
held=$(sqlite3 campaign.db 'select event_seq from origins')
[ "$(sqlite3 campaign.db 'select count(*) from events')" = "$held" ] ||
  fail "the campaign store holds $(sqlite3 campaign.db 'select count(*) from events') events, its cursor says $held"

# A store created on a full disk leaves nothing behind.
mkdir full
if mount -t tmpfs -o size=12k m2mlat-full full 2>/dev/null; then
  trap 'umount full 2>/dev/null || true; cleanup_processes; rm -rf "$WORK"' EXIT
  head -c 4096 /dev/zero > full/filler || true
  expect_exit 74 "$M2MLAT" record --source sim --node vehicle --store full/new.db --count 10 --quiet
  grep -q 'full/new.db: cannot create the store' err.txt || { cat err.txt >&2; fail "no clear error on a full disk"; }
  [ -z "$(ls -A full | grep -v '^filler$')" ] || fail "a full disk left $(ls -A full)"
  umount full
  echo "full disk: refused, nothing left"
else
  echo "SKIP (full disk part): mounting a tmpfs is not permitted here"
fi
echo "ok: $served served events survived 100 foreign opens and kill -9; restart recorded; campaign store kept"
