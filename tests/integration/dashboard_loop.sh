# The full loop on the live dashboard, in a real browser: a store holding a simulated full-loop run
# (both boards' gyroscope traces, the LED's writes and the photo edges), `m2mlat watch --dashboard`,
# and Debian's headless Chromium (cdp_page.py) reading the page: the full-loop panel is shown, with
# M2M, G2G and E2E (n, median, P95, last) equal to `m2mlat stats` on the store (the run lies inside
# the live view's 1 min window), without any console error. Skipped (exit 0 with a note) where
# Chromium is not installed.
HERE=$(cd "$(dirname "$0")" && pwd)  # before lib.bash changes into the temporary folder
source "$HERE/lib.bash"
CHROMIUM=${CHROMIUM:-/usr/bin/chromium}
if [ ! -x "$CHROMIUM" ]; then
  echo "SKIP: no $CHROMIUM (apt-get install chromium)"
  exit 0
fi

"$M2MLAT" simulate --scenario full_loop --seed 3 --manoeuvres 12 --store store.db > /dev/null
"$M2MLAT" stats store.db --bootstrap 0 --json > stats.json
"$M2MLAT" watch store.db --dashboard 127.0.0.1:0 --refresh 200ms --duration 60s > watch.txt 2> watch.err &
PIDS+=($!)
url=""
for _ in $(seq 100); do
  url=$(sed -n 's/^dashboard \(http:[^ ]*\)$/\1/p' watch.err)
  [ -n "$url" ] && break
  sleep 0.1
done
[ -n "$url" ] || { cat watch.err >&2; fail "no 'dashboard URL' line"; }

read_page='[document.getElementById("full-loop").hidden, document.getElementById("loop-window").textContent,
  ["m2m", "g2g", "e2e"].map((q) => ["n", "median", "p95", "last"].map((c) => document.getElementById(q + "-" + c).textContent)),
  document.getElementById("loop-incomplete").textContent, document.getElementById("scenario").textContent]'
"$PY" "$HERE/cdp_page.py" "$CHROMIUM" "$url" "$WORK/profile" "3=$read_page" > page.json \
  || fail "chromium could not load $url"
$PY - page.json stats.json <<'PY'
import json, sys
page = json.load(open(sys.argv[1]))
assert not page["errors"], "console errors: %s" % page["errors"]
hidden, window, cells, incomplete, scenario = page["values"][0]
assert not hidden, "the full-loop panel is hidden"
assert window == "(12 chains over the last 60 s, flank onsets)", window
assert incomplete == "incomplete chains: none", incomplete
assert scenario == "full_loop: station/gyro \u2192 vehicle/gyro", scenario
loop = json.load(open(sys.argv[2]))["full_loop"][0]["quantities"]
for q, (n, median, p95, last) in zip(("m2m", "g2g", "e2e"), cells):
    s = loop[q]["summary"]
    assert n == str(s["n"]) == "12", (q, n, s["n"])
    assert median == "%.1f ms" % s["median_ms"], (q, median, s["median_ms"])
    assert p95 == "%.1f ms" % s["p95_ms"], (q, p95, s["p95_ms"])
    assert last.endswith(" ms") and float(last[:-3]) > 0, (q, last)
print("dashboard full-loop panel = m2mlat stats:", cells)
PY
