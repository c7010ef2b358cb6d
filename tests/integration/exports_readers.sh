# The exports as other programs read them, with their plain calls and no options: pandas'
# read_csv(path) and read_json(path, lines=True), and R's read.csv(path) when R is installed (make
# check installs r-base-core; without it the R part is skipped and says so). The campaign has two
# scenarios measured by differently named boards, one of them with the boards' clock samples (so the
# pairs carry max_error_ns, u_ns, U95_ns). Checked: a header first, scenario/session/label on every
# row, every scenario of the store in `export --what pairs` and `pair -o` with its own node names, no
# column that is an attribute of pandas' DataFrame, exact integer ns, latency_ns = effect - cause, and
# m2mlat's own round trip: export -> import -> export gives the same events (plain and --with-meta).
source "$(dirname "$0")/lib.bash"

"$M2MLAT" simulate --scenario static_5g --out-dir 5g --format events-csv > /dev/null
"$M2MLAT" simulate --scenario static_wifi --out-dir wifi --format kernel-log > /dev/null
"$M2MLAT" import --store campaign.db 5g/operator.csv --node operator --role cause --scenario static_5g \
  --label run-1 > /dev/null
"$M2MLAT" import --store campaign.db 5g/vehicle.csv --node vehicle --role effect --scenario static_5g \
  --label run-1 > /dev/null
"$M2MLAT" import --store campaign.db wifi/operator.log --node station --role cause --scenario static_wifi \
  --label "run 2, wifi" > /dev/null
"$M2MLAT" import --store campaign.db wifi/vehicle.log --node car --role effect --scenario static_wifi \
  --label "run 2, wifi" > /dev/null

"$M2MLAT" export campaign.db -o events.csv 2> note.txt
grep -q 'clock samples .* --with-meta' note.txt || fail "no note on the clock samples left out: $(cat note.txt)"
"$M2MLAT" export campaign.db -o events.jsonl --format events-jsonl
"$M2MLAT" export campaign.db --what pairs -o pairs.csv
"$M2MLAT" export campaign.db --what pairs --scenario static_5g --scenario static_wifi -o both.csv
"$M2MLAT" export campaign.db --what pairs -o pairs.jsonl --format pairs-jsonl
"$M2MLAT" pair campaign.db -o pair-o.csv --unmatched unmatched.csv > /dev/null
cmp pairs.csv pair-o.csv || fail "export --what pairs and pair -o differ"
cmp pairs.csv both.csv || fail "--scenario twice did not export both scenarios"
"$M2MLAT" stats campaign.db --json --bootstrap 0 > stats.json

$PY - <<'PY'
import json
import pandas as pd

attributes = set(dir(pd.DataFrame))
def read(path, **how):
    frame = pd.read_json(path, lines=True, **how) if path.endswith(".jsonl") else pd.read_csv(path)
    clash = attributes & set(frame.columns)
    assert not clash, f"{path}: columns that are DataFrame attributes: {clash}"
    return frame

events = read("events.csv")
want = ["scenario", "session", "label", "node", "channel", "edge", "clock", "time_ns", "seqno",
        "line_seqno", "flag_bits"]
assert list(events.columns) == want, list(events.columns)
assert str(events.time_ns.dtype) == "int64", events.dtypes
assert events.scenario.notna().all() and events.session.notna().all() and events.label.notna().all()
by = events.groupby(["scenario", "node"]).size().to_dict()
assert set(by) == {("static_5g", "operator"), ("static_5g", "vehicle"), ("static_wifi", "station"),
                   ("static_wifi", "car")}, by
assert set(events.label) == {"run-1", "run 2, wifi"}, set(events.label)
lines = read("events.jsonl", dtype={"time_ns": "int64"})
lines = lines[lines.node.notna()]  # the clock records' lines hold no event
assert len(lines) == len(events) and (lines.time_ns.values == events.time_ns.values).all()
assert set(lines.scenario) == {"static_5g", "static_wifi"}

pairs = read("pairs.csv")
assert list(pairs.columns[:3]) == ["scenario", "session", "label"], list(pairs.columns)
assert {"max_error_ns", "u_ns", "U95_ns", "pair_flags", "in_statistics", "left_out", "latency_ms"} <= set(pairs.columns), list(pairs.columns)
# What stats used is what a pandas user selects with in_statistics: the same count and median.
assert pairs.in_statistics.dtype == bool, pairs.dtypes
assert (pairs.left_out.isna() == pairs.in_statistics).all()
for s in json.load(open("stats.json"))["scenarios"]:
    kept = pairs[(pairs.scenario == s["scenario"]) & pairs.in_statistics]
    assert len(kept) == s["latency"]["n"], (s["scenario"], len(kept), s["latency"]["n"])
    assert abs(kept.latency_ms.median() - s["latency"]["median_ms"]) < 1e-6, (s["scenario"], kept.latency_ms.median())
assert ((pairs.effect_time_ns - pairs.cause_time_ns) == pairs.latency_ns).all()
names = pairs.groupby("scenario")[["cause_node", "effect_node"]].agg(set).to_dict("index")
assert names == {"static_5g": {"cause_node": {"operator"}, "effect_node": {"vehicle"}},
                 "static_wifi": {"cause_node": {"station"}, "effect_node": {"car"}}}, names
assert pairs.session.notna().all() and pairs.label.notna().all()
# The 5G scenario has the boards' clock samples, the WiFi one (kernel logs) none.
assert pairs[pairs.scenario == "static_5g"].u_ns.notna().all()
assert pairs[pairs.scenario == "static_wifi"].u_ns.isna().all()
wifi_sessions = set(events[events.scenario == "static_wifi"].session)
assert set(pairs[pairs.scenario == "static_wifi"].session) <= wifi_sessions

jpairs = read("pairs.jsonl")
assert len(jpairs) == len(pairs) and (jpairs.latency_ns.values == pairs.latency_ns.values).all()
assert list(jpairs.scenario) == list(pairs.scenario)
unmatched = read("unmatched.csv")
assert set(unmatched.scenario) <= {"static_5g", "static_wifi"}
json.dump({"events": len(events), "pairs": len(pairs)}, open("counts.json", "w"))
print(f"pandas: {len(events)} events, {len(pairs)} pairs, {len(unmatched)} unmatched")
PY

if command -v Rscript > /dev/null; then
  Rscript -e '
    e <- read.csv("events.csv"); p <- read.csv("pairs.csv")
    stopifnot(identical(names(e)[1:4], c("scenario", "session", "label", "node")))
    stopifnot(all(c("latency_ms", "u_ns", "U95_ns", "pair_flags", "in_statistics") %in% names(p)))
    stopifnot(setequal(unique(p$scenario), c("static_5g", "static_wifi")))
    stopifnot(all(abs(p$latency_ms - p$latency_ns / 1e6) < 1e-6))
    cat(sprintf("R: %d events, %d pairs\n", nrow(e), nrow(p)))' > r.txt
  cat r.txt
  $PY -c "import json,sys; c=json.load(open('counts.json')); sys.exit(open('r.txt').read().strip() != f\"R: {c['events']} events, {c['pairs']} pairs\")" \
    || fail "R read other counts than pandas: $(cat r.txt)"
else
  echo "R: skipped (Rscript is not installed; make deps installs r-base-core)"
fi

# m2mlat's own round trip, per scenario (an import is one scenario): the same events come back, with
# the clock records when --with-meta kept them.
for how in plain meta; do
  flag=(); [ "$how" = meta ] && flag=(--with-meta)
  "$M2MLAT" export campaign.db --scenario static_5g "${flag[@]}" -o "5g-$how.csv" 2> /dev/null
  "$M2MLAT" import --store "back-$how.db" "5g-$how.csv" --scenario static_5g --label run-1 > /dev/null
  "$M2MLAT" export "back-$how.db" "${flag[@]}" -o "again-$how.csv" 2> /dev/null
  cmp "5g-$how.csv" "again-$how.csv" || fail "$how export -> import -> export changed the file"
done
head -1 5g-plain.csv | grep -q '^scenario,session,label,node,' || fail "a plain export starts with: $(head -1 5g-plain.csv)"
head -1 5g-meta.csv | grep -q '^# format: m2mlat-events/2$' || fail "--with-meta starts with: $(head -1 5g-meta.csv)"
grep -q '^# clock: ' 5g-meta.csv || fail "--with-meta wrote no clock record"
"$M2MLAT" stats back-meta.db --json > meta.json
"$M2MLAT" stats back-plain.db --json > plain.json
$PY - <<'PY'
import json
meta, plain = (json.load(open(f)) for f in ("meta.json", "plain.json"))
def has_uncertainty(doc):
    return any((s.get("sample_uncertainty") or {}).get("with_clock") for s in doc["scenarios"])
assert has_uncertainty(meta), "the clock records of --with-meta did not reach the store"
assert not has_uncertainty(plain), "a plain export carried clock records"
PY
echo "exports readers: ok"
