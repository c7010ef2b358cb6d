# The dashboard in a real browser: two simulated boards record in real time into one store,
# `m2mlat watch --dashboard 127.0.0.1:0` serves the live view, and Debian's headless Chromium
# (driven over the DevTools protocol by cdp_page.py) keeps the page open for some seconds. The page
# must run without any console error, uncaught exception or failed load; its sample count must grow
# while it stays open (the event stream updates it without a reload); and the final numbers of
# `watch` must be those of `m2mlat stats` on the finished store. Screenshots of the collect page, and of
# it with a board lost, are kept in test-artifacts/ beside the executable. Skipped (exit 0 with a note)
# where Chromium is not installed.
HERE=$(cd "$(dirname "$0")" && pwd)  # before lib.bash changes into the temporary folder
source "$HERE/lib.bash"
ARTIFACTS=$(dirname "$M2MLAT")/test-artifacts  # the screenshots of docs/dashboard.md come from here
mkdir -p "$ARTIFACTS"
CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$CHROMIUM" ]; then
  echo "SKIP: no $CHROMIUM (apt-get install chromium)"
  exit 0
fi

recorders=()
watcher=""
sender=""
cleanup() {
  for pid in "${recorders[@]}" $watcher $sender; do kill "$pid" 2>/dev/null || true; done
  for pid in "${recorders[@]}" $watcher $sender; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$WORK"
}
# dashboard_url LOG: waits for the "dashboard URL" line a live view prints on stderr.
dashboard_url() {
  local url=""
  for _ in $(seq 100); do
    url=$(sed -n 's/^dashboard \(http:[^ ]*\)$/\1/p' "$1")
    [ -n "$url" ] && break
    sleep 0.1
  done
  [ -n "$url" ] || { cat "$1" >&2; fail "no 'dashboard URL' line in $1"; }
  echo "$url"
}
trap cleanup EXIT

# Both boards replay the same simulated rig in real time (a manoeuvre every 1.5 to 4 s).
for side in "operator cause" "vehicle effect"; do
  read -r node role <<< "$side"
  "$M2MLAT" record --source sim --sim-paced --sim-preset static_wifi --node "$node" --role "$role" \
    --scenario browser --store store.db --batch 1 --commit-interval 50ms --duration 90s --quiet \
    > "record-$node.txt" 2>&1 &
  recorders+=($!)
done
# watch reads a store that exists (a missing one is an error): the recorders make it first.
for _ in $(seq 200); do [ -s store.db ] && break; sleep 0.05; done
"$M2MLAT" watch store.db --dashboard 127.0.0.1:0 --refresh 200ms --duration 90s > watch.txt 2> watch.err &
watcher=$!

url=$(dashboard_url watch.err)

# The API and the page's files answer with their types; wait for the first pairs.
$PY - "$url" <<'PY' || { tail -n 20 record-*.txt >&2; fail "the live view found no pairs"; }
import json, sys, time, urllib.request
url = sys.argv[1]
for path, kind in [("", "text/html"), ("dashboard.js", "text/javascript"), ("dashboard.css", "text/css"),
                   ("favicon.svg", "image/svg+xml"), ("api/live", "application/json")]:
    with urllib.request.urlopen(url + path, timeout=5) as r:
        assert r.headers["Content-Type"].startswith(kind), (path, r.headers["Content-Type"])
deadline = time.monotonic() + 30
while time.monotonic() < deadline:
    with urllib.request.urlopen(url + "api/live", timeout=5) as r:
        snap = json.load(r)
    if snap["summary"]["samples"] >= 2:
        break
    time.sleep(0.2)
else:
    sys.exit(f"no samples after 30 s: {snap['summary']}")
PY

# One page load, read twice: after 3 s and after 10 s more, without reloading.
read_page='[document.getElementById("samples").textContent, document.getElementById("connection").textContent,
  document.querySelectorAll("#strip circle.point").length, document.querySelectorAll("#histogram rect.bar").length,
  document.getElementById("median").textContent, document.getElementById("scenario").textContent,
  document.getElementById("median-ci").textContent]'
"$PY" "$HERE/cdp_page.py" "$CHROMIUM" "$url" "$WORK/profile" "3=$read_page" "10=$read_page" > page.json \
  || fail "chromium could not load $url"
$PY - page.json <<'PY'
import json, re, sys
page = json.load(open(sys.argv[1]))
assert not page["errors"], "console errors: %s" % page["errors"]
first, second = page["values"]
for v in (first, second):
    samples, connection, points, bars, median, scenario, median_ci = v
    assert connection == "live", v            # the event stream is open
    assert points >= 2 and bars >= 1, v        # both charts drawn
    assert re.fullmatch(r"\d+\.\d ms", median), v
    ci = re.fullmatch(r"95 % CI (\d+\.\d) \.\. (\d+\.\d) ms", median_ci)  # the bootstrap's, live
    assert ci and float(ci[1]) <= float(median[:-3]) <= float(ci[2]), v
    assert scenario == "browser: operator/wheel \u2192 vehicle/wheel", v
assert int(second[0]) > int(first[0]), "the sample count did not grow: %s then %s" % (first[0], second[0])
print("dashboard page: %s then %s samples, no console errors" % (first[0], second[0]))
PY

# Stop the boards, then the watcher: its final block is `m2mlat stats` of the finished store.
for pid in "${recorders[@]}"; do kill -TERM "$pid"; wait "$pid" || true; done
recorders=()
kill -TERM "$watcher"
wait "$watcher" || fail "m2mlat watch did not end cleanly on SIGTERM"
watcher=""
"$M2MLAT" stats store.db --json > stats.json
$PY - watch.txt stats.json <<'PY'
import json, re, sys
text = open(sys.argv[1]).read()
last = re.findall(r"samples (\d+)  last [\d.]+ ms  median ([\d.]+) ms  IQR ([\d.]+) ms", text)[-1]
ci = re.findall(r"95 % CI: median ([\d.]+)-([\d.]+) ms, IQR ([\d.]+)-([\d.]+) ms", text)[-1]
s = json.load(open(sys.argv[2]))["scenarios"][0]
assert s["scenario"] == "browser", s["scenario"]
lat = s["latency"]
assert int(last[0]) == lat["n"], (last, lat["n"])
assert last[1] == "%.1f" % lat["median_ms"] and last[2] == "%.1f" % lat["iqr_ms"], (last, lat)
b = lat["bootstrap"]
assert ci == tuple("%.1f" % x for x in b["median_ms"] + b["iqr_ms"]), (ci, b)
print("final block = m2mlat stats: %s samples, median %s ms (95 %% CI %s-%s)" % (last[0], last[1], ci[0], ci[1]))
PY

# The real coordinator with two simulated agents (the live view wired into `m2mlat collect`), with
# the live stage breakdown (`--stages`): the agents take software markers on --mark-port, a stack's
# marks are sent to both (mark_sender.py), and the simulated rig starts now, so the marks' arrival
# stamps and the simulated edges share one time line.
START=$(date +%s)
for side in "operator cause" "vehicle effect"; do
  read -r node role <<< "$side"
  "$M2MLAT" agent --source sim --seed 5 --role "$role" --node "$node" --store "agent-$node.db" \
    --scenario agents --listen 127.0.0.1:0 --sim-set "start=$START" --mark-port 0 > "agent-$node.log" 2>&1 &
  recorders+=($!)
done
ports=()
marks=()
for node in operator vehicle; do
  for _ in $(seq 100); do
    port=$(sed -n 's/^listening 127\.0\.0\.1:\([0-9]*\)$/\1/p' "agent-$node.log")
    mark=$(grep -oE 'marks 127\.0\.0\.1:[0-9]+' "agent-$node.log" | sed 's/.*://' || true)
    [ -n "$port" ] && [ -n "$mark" ] && break
    sleep 0.1
  done
  [ -n "$port" ] && [ -n "$mark" ] || { cat "agent-$node.log" >&2; fail "agent $node did not start"; }
  ports+=("$port")
  marks+=("$mark")
done
"$PY" "$HERE/mark_sender.py" "${marks[0]}" "${marks[1]}" 60 > sender.out &
sender=$!
printf '%s\n' 'to_command = first operator:cmd after cause' 'to_apply = same key vehicle:apply' \
  'actuator = effect' > stages.txt
"$M2MLAT" collect --agent "http://127.0.0.1:${ports[0]}" --agent "http://127.0.0.1:${ports[1]}" \
  --store campaign.db --dashboard 127.0.0.1:0 --stages stages.txt --duration 90s > collect.txt 2> collect.err &
watcher=$!
url=$(dashboard_url collect.err)
# The breakdown panel: shown, its counts, each stage's segment and the labels inside (their boxes),
# the table's rows; nothing of it may stick out of its figure or overlap another label.
read_agents='[document.getElementById("samples").textContent, document.querySelector("#nodes tbody").innerText,
  document.getElementById("agents").hidden, document.documentElement.scrollWidth - document.documentElement.clientWidth,
  document.getElementById("breakdown").hidden, document.getElementById("breakdown-counts").textContent,
  [...document.querySelectorAll("#breakdown-bar rect.segment")].map((r) => [r.dataset.stage, r.getBoundingClientRect().left, r.getBoundingClientRect().right]),
  [...document.querySelectorAll("#breakdown-bar text")].map((t) => { const b = t.getBoundingClientRect(); return [t.textContent, b.left, b.right, b.top, b.bottom]; }),
  [...document.querySelectorAll("#stages tbody tr")].map((r) => r.innerText),
  (() => { const f = document.querySelector("#breakdown figure").getBoundingClientRect(); return [f.left, f.right]; })()]'
"$PY" "$HERE/cdp_page.py" "$CHROMIUM" "$url" "$WORK/profile2" "4=$read_agents" "8=$read_agents" \
  "0=@$ARTIFACTS/dashboard.png" > collect.json || fail "chromium could not load $url"
$PY - collect.json <<'PY'
import json, re, sys
page = json.load(open(sys.argv[1]))
assert not page["errors"], "console errors: %s" % page["errors"]
(n1, rows1, hidden1, over1, *_), (n2, rows2, hidden2, over2, bd_hidden, counts, segments, texts, stage_rows, fig), shot = page["values"]
# The live breakdown's panel.
assert not bd_hidden, "the breakdown panel is hidden"
m = re.fullmatch(r"\((\d+) complete / (\d+) incomplete of (\d+) events\)", counts)
assert m and int(m[1]) + int(m[2]) == int(m[3]) and int(m[1]) >= 1, counts
assert [s[0] for s in segments] == ["to_command", "to_apply", "actuator"], segments
for a, b in zip(segments, segments[1:]):
    assert abs(a[2] - b[1]) < 0.5, ("segments not stacked end to end", a, b)
assert fig[0] <= segments[0][1] and segments[-1][2] <= fig[1], ("the bar leaves its figure", segments, fig)
for name, left, right, top, bottom in texts:
    assert fig[0] <= left and right <= fig[1], ("a label leaves the figure", name, left, right, fig)
    if name.startswith(tuple(s[0] + " " for s in segments)):  # a stage's label: inside its segment
        seg = next(s for s in segments if name.startswith(s[0] + " "))
        assert seg[1] <= left and right <= seg[2], ("a label sticks out of its segment", name, seg)
boxes = [t for t in texts if t[0]]
for i, a in enumerate(boxes):
    for b in boxes[i + 1:]:
        overlap = min(a[2], b[2]) - max(a[1], b[1]) > 0.5 and min(a[4], b[4]) - max(a[3], b[3]) > 0.5
        assert not overlap, ("labels overlap", a, b)
assert [r.split("\t")[0].strip() for r in stage_rows] == ["to_command", "to_apply", "actuator"], stage_rows
assert all(re.search(r"\d+\.\d{3} ms", r) for r in stage_rows), stage_rows
print("breakdown panel: %s, %d segments, %d labels" % (counts, len(segments), len(texts)))
assert over2 <= 0, "the page is %s px wider than the window (it scrolls sideways)" % over2
assert shot > 10000, "no screenshot: %s bytes" % shot
assert not hidden2, "the agents' table is hidden"
rows = [r.split("\t") for r in rows2.strip().split("\n")]
assert [r[:3] for r in rows] == [["operator", "cause", "ok"], ["vehicle", "effect", "ok"]], rows
# the clock columns (offset, max error, sync) from the simulated boards' own clock samples
for r in rows:
    assert re.fullmatch(r"[+-]\d+\.\d{3} ms", r[7]) and re.fullmatch(r"\d+\.\d{3} ms", r[8]), r
    assert r[9] in ("yes", "NO"), r
n1 = int(n1) if n1.isdigit() else 0
assert int(n2) > n1, "the sample count did not grow: %s then %s" % (n1, n2)
print("collect dashboard: %s then %s samples, agents %s" % (n1, n2, [r[:3] + r[7:10] for r in rows]))
PY

# A board lost in the car: the vehicle's agent is killed while the page is open. The top of the page
# must turn red at once, naming the board, and the badge must stop saying a plain "live". The page is
# read 2 s after loading (both boards ok), then every 0.25 s after the kill for up to 4 s.
read_top='[!document.getElementById("alert").hidden, document.getElementById("alert").textContent,
  getComputedStyle(document.getElementById("alert")).backgroundColor, document.getElementById("alert").getBoundingClientRect().top,
  document.getElementById("connection").textContent, document.getElementById("connection").className,
  [...document.querySelectorAll("#strip .axis-label, #histogram .axis-label")].map((t) => t.textContent)]'
steps=("2=$read_top" "0=!kill -KILL ${recorders[1]}")
for _ in $(seq 16); do steps+=("0.25=$read_top"); done
steps+=("0=@$ARTIFACTS/dashboard_board_down.png")
"$PY" "$HERE/cdp_page.py" "$CHROMIUM" "$url" "$WORK/profile3" "${steps[@]}" > lost.json \
  || fail "chromium could not load $url"
wait "${recorders[1]}" 2>/dev/null || true
$PY - lost.json <<'PY'
import json, sys
page = json.load(open(sys.argv[1]))
assert not page["errors"], "console errors: %s" % page["errors"]
before, killed, *after, shot = page["values"]
assert shot > 10000, "no screenshot: %s bytes" % shot
assert killed == 0, "kill failed: %s" % killed
shown, text, colour, top, badge, badge_class, labels = before
assert not shown and badge == "live" and badge_class == "badge badge-ok", before
# the axes carry their units
assert labels == ["time (s before the newest pair)", "latency (ms)", "latency (ms)", "pairs"], labels
first = next((i for i, v in enumerate(after) if v[0]), None)
assert first is not None, "no red banner within 4 s of the kill: %s" % after[-1]
shown, text, colour, top, badge, badge_class, _ = after[first]
assert text.startswith("vehicle UNREACHABLE") or text.startswith("vehicle STALE"), text
assert "operator" not in text, text              # only the lost board is named
assert colour == "rgb(179, 38, 30)", colour      # --bad, light scheme
assert top == 0, top                             # at the very top of the page
assert badge == "live \u00b7 1 board down" and badge_class == "badge badge-error", (badge, badge_class)
print("board lost: red banner %.2f s after the kill: %r; badge %r" % ((first + 1) * 0.25, text, badge))
PY
kill -TERM "$watcher"
wait "$watcher" || fail "m2mlat collect did not end cleanly on SIGTERM"
watcher=""
echo "1 passed, 0 failed"
