# Software markers through real processes on loopback: an agent with --mark-port records a simulated
# board; `m2mlat mark` sends marks from the shell (with and without its own stamp), a raw datagram that
# breaks the format is refused and counted by reason in /v1/status and /metrics, a bad name is a usage
# error (exit 2). Each stored mark's time (the kernel's arrival stamp) must lie inside the window the
# sending shell measured around its `m2mlat mark`, and its sender stamp before its arrival; `collect`
# carries the marks into a campaign store exactly once (a second collect adds none), and `export --what
# markers` of both stores gives the same m2mlat-markers/1 lines.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

start_agent operator cause 3 operator.db 127.0.0.1:0 --mark-port 0 --commit-interval 50ms
OPERATOR_PORT=$AGENT_PORT
start_agent vehicle effect 3 vehicle.db 127.0.0.1:0 --commit-interval 50ms  # the effect side, for pairs
VEHICLE_URL="http://127.0.0.1:$AGENT_PORT"
AGENT_PORT=$OPERATOR_PORT
MARK_PORT=$(wait_for_line operator.log 'marks 127\.0\.0\.1:[0-9]+' | sed 's/.*://')
URL="http://127.0.0.1:$AGENT_PORT"

# The first session opens right after the agent starts listening; marks before it are refused.
for ((i = 0; i < 100; i++)); do
  "$PY" - "$URL" <<'PY' && break
import json, sys, urllib.request
sys.exit(0 if json.load(urllib.request.urlopen(sys.argv[1] + "/v1/status", timeout=5))["session"] else 1)
PY
  sleep 0.05
done

: >windows.txt
for key in 101 102 103 104 105; do
  before=$(date +%s%N)
  if [ "$key" = 103 ]; then
    "$M2MLAT" mark operator_cmd --key "$key" --to "127.0.0.1:$MARK_PORT"
  else
    "$M2MLAT" mark operator_cmd --key "$key" --stamp --to "127.0.0.1:$MARK_PORT"
  fi
  after=$(date +%s%N)
  echo "$key $before $after" >>windows.txt
done
"$PY" - "$MARK_PORT" <<'PY'
import socket, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.sendto(b"m2mlat-mark/1 has spaces in=it", ("127.0.0.1", int(sys.argv[1])))
s.sendto(b"GET / HTTP/1.1\r\n", ("127.0.0.1", int(sys.argv[1])))
PY
expect_exit 2 "$M2MLAT" mark "two words" --to "127.0.0.1:$MARK_PORT"
expect_exit 2 "$M2MLAT" mark ok --to "127.0.0.1"

# Wait until the agent has stored the five and refused the two.
"$PY" - "$URL" <<'PY'
import json, sys, time, urllib.request
for _ in range(200):
    marks = json.load(urllib.request.urlopen(sys.argv[1] + "/v1/status", timeout=5))["marks"]
    if marks["stored"] == 5 and sum(marks["rejected"].values()) == 2:
        break
    time.sleep(0.05)
assert marks["stored"] == 5, marks
assert marks["rejected"] == {"field": 1, "format": 1}, marks
assert marks["stamps"] in ("kernel", "receiver"), marks
metrics = urllib.request.urlopen(sys.argv[1] + "/metrics", timeout=5).read().decode()
assert 'm2mlat_marks_stored_total{node="operator"} 5' in metrics, metrics
assert 'm2mlat_marks_rejected_total{node="operator",reason="format"} 1' in metrics, metrics
print("status:", marks)
PY

"$M2MLAT" collect --agent "$URL" --agent "$VEHICLE_URL" --store campaign.db --duration 1s --quiet >collect.out 2>collect.err ||
  { cat collect.err >&2; fail "collect failed"; }
"$M2MLAT" collect --agent "$URL" --agent "$VEHICLE_URL" --store campaign.db --duration 0.5s --quiet >>collect.out 2>>collect.err ||
  { cat collect.err >&2; fail "the second collect failed"; }
"$M2MLAT" export operator.db --what markers -o agent-markers.csv
"$M2MLAT" export campaign.db --what markers -o campaign-markers.csv
cmp agent-markers.csv campaign-markers.csv || { diff agent-markers.csv campaign-markers.csv >&2; fail "the campaign's markers differ"; }

"$PY" - <<'PY'
import csv
lines = open("campaign-markers.csv").read().splitlines()
assert lines[0].startswith("node,name,clock,time_ns,"), lines[0]  # the header first
rows = list(csv.DictReader(lines))
windows = {k: (int(b), int(a)) for k, b, a in (l.split() for l in open("windows.txt"))}
assert [r["key"] for r in rows] == sorted(windows), rows
for r in rows:
    before, after = windows[r["key"]]
    t = int(r["time_ns"])
    assert r["node"] == "operator" and r["name"] == "operator_cmd" and r["clock"] == "realtime", r
    assert before <= t <= after, (r, before, after)
    if r["key"] == "103":
        assert r["sender_ns"] == "" and r["sender_to_capture_ns"] == "", r
    else:
        s = int(r["sender_ns"])
        assert before <= s <= t and int(r["sender_to_capture_ns"]) == t - s, (r, before)
    assert r["origin"].startswith("udp 127.0.0.1:"), r
    print(f'{r["key"]}: arrival {t - before} ns after the shell\'s start, window {after - before} ns, '
          f'source {r["source"]}, sender to arrival {r["sender_to_capture_ns"] or "-"} ns')
PY

# The stored markers reach the stage breakdown with no --markers file (without markers --stages is a
# usage error); every pair in the statistics is counted, complete or not. (The paced agents give few
# pairs in these two seconds, often none: docs/breakdown.md's tests check the stages themselves.)
printf 'to_operator_cmd = first operator:operator_cmd after cause\nrest = effect\n' >stages.txt
"$M2MLAT" stats campaign.db --stages stages.txt --json >breakdown.json || fail "stats --stages on the campaign failed"
"$PY" - <<'PY'
import json
scenarios = json.load(open("breakdown.json"))["scenarios"]
assert scenarios, "no scenario"
for s in scenarios:
    b = s["breakdown"]
    assert b["complete"] + b["incomplete"] == b["events"], b
    assert [x["name"] for x in b["stages"]] == ["to_operator_cmd", "rest"], b
    print(f'breakdown from the stored markers: {b["events"]} events, {b["complete"]} complete')
PY
echo "markers_agent: ok"
