# The agent's HTTP API with the real binary: status, events, sessions, metrics and the SSE stream on
# an ephemeral loopback port; served events equal the store's export; a token-protected agent (on
# this machine's own non-loopback address if it has one) refuses missing and wrong tokens; malformed
# and oversized requests get their 4xx, the agent keeps running and the stored events do not change;
# TLS with a self-signed certificate; SIGTERM ends the agent cleanly with every session closed.
source "$(dirname "$0")/lib.bash"

# [STORE=FILE] start_agent NAME ARGS...: starts an agent (store NAME.db unless STORE is set), waits for its `listening` line; sets PORT and PID.
start_agent() {
  local name=$1; shift
  "$M2MLAT" agent --store "${STORE:-$name.db}" --node vehicle --role effect --source sim --quiet \
    --sim-set motion.interval_min=150ms --sim-set motion.interval_max=300ms --sim-set motion.min_pause=20ms \
    --commit-interval 20ms --port-file "$name.port" "$@" > "$name.out" 2> "$name.err" &
  PID=$!
  PIDS+=("$PID")
  for _ in $(seq 100); do
    grep -q '^listening ' "$name.out" 2>/dev/null && break
    kill -0 "$PID" 2>/dev/null || { cat "$name.err" >&2; fail "agent $name exited at start"; }
    sleep 0.1
  done
  PORT=$(sed -n 's/^listening .*:\([0-9]*\)$/\1/p' "$name.out")
  [ -n "$PORT" ] || fail "agent $name printed no port"
  [ "$(cat "$name.port")" = "$PORT" ] || fail "--port-file says $(cat "$name.port"), stdout says $PORT"
}
# status_of URL...: the HTTP status of a curl request (extra curl arguments allowed).
status_of() { curl -s -o body.txt -w '%{http_code}' --max-time 10 "$@"; }
# stop_agent PID: SIGTERM, and it must exit 0.
stop_agent() {
  kill -TERM "$1"
  local rc=0
  wait "$1" || rc=$?
  [ "$rc" = 0 ] || fail "agent exited $rc after SIGTERM"
}

# --- Plain agent on loopback ---------------------------------------------------------------------------
start_agent a --listen 127.0.0.1:0 --label run-1 --scenario urban
A=$PID; URL="http://127.0.0.1:$PORT"
for _ in $(seq 100); do
  last=$(curl -s "$URL/v1/status" | $PY -c 'import json,sys; print(json.load(sys.stdin)["last_seq"])')
  [ "$last" -ge 6 ] && break
  sleep 0.1
done
[ "$last" -ge 6 ] || fail "no events committed"
curl -s -D headers.txt "$URL/v1/status" > status.json
grep -qi '^X-M2mlat-Api: 1' headers.txt || fail "no X-M2mlat-Api header"
$PY - status.json <<'PY' || fail "bad status"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["api"] == "m2mlat-agent/1" and s["node"] == "vehicle" and s["role"] == "effect", s
assert len(s["store_id"]) == 32 and s["session"]["label"] == "run-1" and s["session"]["scenario"] == "urban", s
assert s["session"]["end_ns"] is None and s["channels"][0]["name"] == "wheel", s
assert s["now_ns"] >= s["started_ns"] > 1_600_000_000_000_000_000, s
PY
[ "$(status_of "$URL/metrics")" = 200 ] || fail "metrics"
grep -q '^m2mlat_up{node="vehicle"} 1$' body.txt || fail "metrics lack m2mlat_up"
grep -q '^m2mlat_events_total{node="vehicle",channel="wheel"} ' body.txt || fail "metrics lack events"

# SSE: the first events from after=2 arrive with their ids, in order.
curl -s -N --max-time 3 "$URL/v1/events/stream?after=2" > sse.txt || true
$PY - sse.txt <<'PY' || fail "bad SSE stream: $(head -c 400 sse.txt)"
import json, sys
ids = [int(l[4:]) for l in open(sys.argv[1]) if l.startswith("id: ")]
data = [json.loads(l[6:]) for l in open(sys.argv[1]) if l.startswith("data: ")]
assert ids and ids[0] == 3 and ids == sorted(ids) and ids == list(range(3, 3 + len(ids))), ids
assert [d["seq"] for d in data] == ids
PY
curl -s -N --max-time 2 -H 'Last-Event-ID: 4' "$URL/v1/events/stream" > resumed.txt || true
[ "$(grep -m1 '^id: ' resumed.txt)" = "id: 5" ] || fail "Last-Event-ID not honoured: $(head -3 resumed.txt)"

# Sessions: a new one, then a stop; a second stop is a conflict; then one more for the rest of the run.
[ "$(status_of -X POST -H 'Content-Type: application/json' -d '{"label":"run-2","scenario":"rural"}' "$URL/v1/sessions")" = 201 ] \
  || fail "POST /v1/sessions: $(cat body.txt)"
$PY -c 'import json,sys; s=json.load(open("body.txt"))["session"]; assert s["id"]==2 and s["label"]=="run-2" and s["end_ns"] is None, s' \
  || fail "new session: $(cat body.txt)"
sleep 0.5
[ "$(status_of -X POST "$URL/v1/sessions/current/stop")" = 200 ] || fail "stop: $(cat body.txt)"
$PY -c 'import json; s=json.load(open("body.txt"))["session"]; assert s["id"]==2 and s["end_ns"] is not None, s' || fail "stopped session"
[ "$(status_of -X POST "$URL/v1/sessions/current/stop")" = 409 ] || fail "a second stop is not 409"
sleep 0.5
[ "$(status_of "$URL/v1/status")" = 200 ] || fail "status"
$PY -c 'import json; s=json.load(open("body.txt")); assert s["session"] is None, s' || fail "a session is open after stop"
[ "$(status_of -X POST -d '{"label":"run-3"}' "$URL/v1/sessions")" = 201 ] || fail "POST /v1/sessions without a JSON type"
[ "$(status_of "$URL/v1/sessions")" = 200 ] || fail "GET /v1/sessions"
$PY -c 'import json; s=json.load(open("body.txt"))["sessions"]; assert [x["id"] for x in s]==[1,2,3] and s[0]["end_ns"] and s[1]["end_ns"] and not s[2]["end_ns"], s' \
  || fail "sessions: $(cat body.txt)"

# Malformed and oversized requests: the right 4xx each, and the agent keeps serving.
curl -s "$URL/v1/events?limit=10000" > before.ndjson
expect_status() {
  local want=$1; shift
  local got
  got=$(status_of "$@")
  [ "$got" = "$want" ] || fail "$* -> $got, expected $want: $(cat body.txt)"
  $PY -c "import json; e=json.load(open('body.txt'))['error']; assert e['status']==$want and e['message']" \
    || fail "$* -> error body $(cat body.txt)"
}
expect_status 400 "$URL/v1/events?after=abc"
expect_status 400 "$URL/v1/events?after=-1"
expect_status 400 "$URL/v1/events?limit=99999999999999999999999"
expect_status 400 "$URL/v1/events?limit=10001"
expect_status 400 "$URL/v1/clock-samples?after=1.5"
expect_status 400 -X POST -d '{"label":' "$URL/v1/sessions"
expect_status 404 "$URL/v1/nothing"
expect_status 404 "$URL/../../etc/passwd"
expect_status 405 -X DELETE "$URL/v1/events"
grep -qi '^Allow: GET, HEAD' <(curl -s -D - -o /dev/null -X PUT "$URL/v1/status") || fail "no Allow header on 405"
headers=()
for i in $(seq 100); do headers+=(-H "X-Filler-$i: $i"); done
expect_status 431 "${headers[@]}" "$URL/v1/status"
head -c 1048576 /dev/zero | tr '\0' 'x' > big.bin
expect_status 413 -X POST -H 'Content-Type: application/json' --data-binary @big.bin "$URL/v1/sessions"
# Garbage bytes and a truncated request straight on the socket: an answer or a closed connection,
# never a crash.
for payload in 'GARBAGE\x00\xff\xfe\r\n\r\n' 'GET /v1/status HTTP/1.1\r\nHost: x\r\nContent-Length: 99999999999\r\n\r\n' \
  'GET /v1/status HTTP/1.1\r\nContent-Length: 5\r\n\r\nGET /v1/events HTTP/1.1\r\n\r\n' \
  'POST /v1/sessions HTTP/1.1\r\nContent-Length: 123456789012345678901234567890\r\n\r\n{}' \
  'GET /v1/events?after=%00%ff HTTP/1.1\r\n\r\n' "GET /$(head -c 9000 /dev/zero | tr '\0' a) HTTP/1.1\r\n\r\n"; do
  exec 3<>"/dev/tcp/127.0.0.1/$PORT"
  printf '%b' "$payload" >&3 || true  # the agent may answer and close before all is written
  timeout 2 cat <&3 > raw.txt || true  # the first response line is all we need
  exec 3<&- 3>&-
  if [ -s raw.txt ]; then head -1 raw.txt | grep -q '^HTTP/1.1 4' || fail "garbage got: $(head -1 raw.txt)"; fi
done
kill -0 "$A" || fail "the agent died"
[ "$(status_of "$URL/v1/status")" = 200 ] || fail "the agent stopped serving"
# No request above changed what was stored: the first events are still the same, byte for byte.
n=$(wc -l < before.ndjson)
# (Not `curl | head`: with pipefail, curl's write error once head has closed the pipe ends the test.)
curl -s "$URL/v1/events?limit=10000" > all.ndjson
head -n "$n" all.ndjson > after.ndjson
cmp -s before.ndjson after.ndjson || fail "the stored events changed"

# Served events equal the store's export (after a clean stop, every committed event is in both).
stop_agent "$A"
"$M2MLAT" export a.db --format events-jsonl -o export.jsonl
STORE=a.db start_agent a2 --listen 127.0.0.1:0
A2=$PID
curl -s "http://127.0.0.1:$PORT/v1/events?limit=10000" > served.ndjson
curl -s "http://127.0.0.1:$PORT/v1/sessions" > sessions.json
stop_agent "$A2"
$PY - served.ndjson export.jsonl sessions.json <<'PY' || fail "served events differ from the export"
import json, sys
served = [json.loads(l) for l in open(sys.argv[1])]
exported = [j for j in map(json.loads, open(sys.argv[2])) if "clock_sample" not in j]  # events only
sessions = json.load(open(sys.argv[3]))["sessions"]
assert all(s["end_ns"] is not None for s in sessions[:3]), sessions  # SIGTERM closed the open session
key = lambda e: (e["channel"], e["edge"], e["clock"], e["t_ns"] if "t_ns" in e else e["time_ns"], e["seqno"], e["line_seqno"], e.get("flag_bits", e.get("flags")))  # served: flags; exported: flag_bits
# The export was made before the restart: it holds exactly the first run's events (sessions 1-3).
first_run = [e for e in served if e["session"] <= 3]
assert len(first_run) > 5 and len(first_run) == len(exported), (len(first_run), len(exported))
assert [e["seq"] for e in served] == sorted(e["seq"] for e in served)
assert sorted(map(key, first_run)) == sorted(map(key, exported))
PY

# --- Token-protected agent ------------------------------------------------------------------------------
HOST=$(ip -4 -o addr show scope global 2>/dev/null | awk '{split($4, a, "/"); print a[1]; exit}' || true)
openssl rand -hex 24 > token.txt && chmod 600 token.txt
TOKEN=$(cat token.txt)
if [ -n "$HOST" ]; then
  # Off loopback without a token: refused before anything is recorded.
  expect_exit 2 env -u M2MLAT_TOKEN "$M2MLAT" agent --store refused.db --node vehicle --source sim --listen "$HOST:0" --quiet
  grep -q 'token' err.txt || fail "the refusal does not mention the token: $(cat err.txt)"
  [ ! -e refused.db ] || fail "a refused agent created its store"
  start_agent t --listen "$HOST:0" --token-file token.txt
else
  start_agent t --listen 127.0.0.1:0 --token-file token.txt
  HOST=127.0.0.1
fi
T=$PID; TURL="http://$HOST:$PORT"
[ "$(status_of "$TURL/v1/status")" = 401 ] || fail "no token accepted"
grep -qi '^WWW-Authenticate: Bearer' <(curl -s -D - -o /dev/null "$TURL/v1/status") || fail "no WWW-Authenticate"
[ "$(status_of -H "Authorization: Bearer ${TOKEN}x" "$TURL/v1/status")" = 401 ] || fail "wrong token accepted"
[ "$(status_of -H "Authorization: Basic $TOKEN" "$TURL/v1/events")" = 401 ] || fail "Basic accepted"
[ "$(status_of -X POST -d '{}' "$TURL/v1/sessions")" = 401 ] || fail "POST without a token accepted"
[ "$(status_of -H "Authorization: Bearer $TOKEN" "$TURL/v1/status")" = 200 ] || fail "right token refused"
[ "$(status_of -H "Authorization: Bearer $TOKEN" "$TURL/v1/events?limit=1")" = 200 ] || fail "right token refused (events)"
M2MLAT_TOKEN=$TOKEN
stop_agent "$T"
# The environment works as well as the file.
M2MLAT_TOKEN=$TOKEN start_agent e --listen 127.0.0.1:0
[ "$(status_of "http://127.0.0.1:$PORT/v1/status")" = 401 ] || fail "M2MLAT_TOKEN not enforced"
[ "$(status_of -H "Authorization: Bearer $TOKEN" "http://127.0.0.1:$PORT/v1/status")" = 200 ] || fail "M2MLAT_TOKEN refused"
stop_agent "$PID"

# --- TLS with a self-signed certificate -----------------------------------------------------------------
openssl req -x509 -newkey rsa:2048 -nodes -keyout key.pem -out cert.pem -days 1 -subj /CN=localhost \
  -addext subjectAltName=IP:127.0.0.1 2> /dev/null
chmod 600 key.pem
start_agent s --listen 127.0.0.1:0 --tls-cert cert.pem --tls-key key.pem
[ "$(status_of --cacert cert.pem "https://127.0.0.1:$PORT/v1/status")" = 200 ] || fail "TLS status"
[ "$(status_of --cacert cert.pem "https://127.0.0.1:$PORT/v1/events?after=x")" = 400 ] || fail "TLS 400"
curl -s --max-time 3 "http://127.0.0.1:$PORT/v1/status" > /dev/null && fail "plain HTTP answered on the TLS port"
stop_agent "$PID"
expect_exit 2 "$M2MLAT" agent --store x.db --node v --source sim --listen 127.0.0.1:0 --tls-cert cert.pem --quiet
echo "agent_api: ok"
