# `m2mlat synctest` on two boards' recordings of one pulse line: two stores (one per board), one
# store holding both, and an events file with both give the same offsets, which equal the ones the
# test put in (numpy), with lost and extra edges left unmatched; CSV, JSON and SVG outputs; errors.
source "$(dirname "$0")/lib.bash"
$PY - <<'PY'
import numpy as np
rng = np.random.default_rng(5)
t0 = 1_780_304_400_000_000_000
period = 250_000_000                      # the line toggles every 250 ms: both edges are paired
n = 2000
a = t0 + np.arange(n, dtype=np.int64) * period
# B's clock: 400 us ahead, wandering slowly, plus 15 us of white noise.
offset = 400_000 + (60_000 * np.sin(np.arange(n) / 300.0)).astype(np.int64) + rng.normal(0, 15_000, n).astype(np.int64)
b = a + offset
keep_a = rng.random(n) > 0.01
keep_b = rng.random(n) > 0.01
both = keep_a & keep_b
np.savetxt("truth.txt", offset[both], fmt="%d")
def write(path, node, times, keep, extra):
    rows = []
    for i, (t, k) in enumerate(zip(times, keep)):
        if k: rows.append((int(t), "rising" if i % 2 == 0 else "falling"))
    for t in extra: rows.append((int(t), "rising"))
    rows.sort()
    with open(path, "w") as f:
        f.write("# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n")
        for k, (t, e) in enumerate(rows):
            f.write(f"{node},pulse,{e},realtime,{t},{k + 1},{k + 1},0\n")
        # and a wheel channel the test must ignore
        f.write(f"{node},wheel,falling,realtime,{int(times[0]) + 7},{len(rows) + 1},1,0\n")
glitches = a[rng.choice(n, 5, replace=False)] + 100_000_000   # 100 ms after some pulses on B
write("a.csv", "board_a", a, keep_a, [])
write("b.csv", "board_b", b, keep_b, glitches)
with open("both.csv", "w") as f:
    lines = open("a.csv").read().splitlines()[2:] + open("b.csv").read().splitlines()[2:]
    lines.sort(key=lambda l: int(l.split(",")[4]))
    f.write("# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n" + "\n".join(lines) + "\n")
PY
"$M2MLAT" import a.csv --store a.db --role observer --scenario sync > /dev/null
"$M2MLAT" import b.csv --store b.db --role observer --scenario sync > /dev/null
"$M2MLAT" import a.csv b.csv --store ab.db --role observer --scenario sync > /dev/null
"$M2MLAT" synctest a.db b.db --json --series > two.json
"$M2MLAT" synctest ab.db --a board_a --b board_b --json --series > one.json
"$M2MLAT" synctest both.csv --a board_a --b board_b --json --series > file.json
"$M2MLAT" synctest a.db b.db --csv series.csv --svg offset.svg > table.txt
grep -q "pulses paired" table.txt || fail "no text summary"
grep -q "<svg" offset.svg || fail "no SVG"
$PY - <<'PY'
import json
import numpy as np
import pandas as pd
truth = np.loadtxt("truth.txt", dtype=np.int64)
docs = [json.load(open(f)) for f in ("two.json", "one.json", "file.json")]
for d in docs:
    got = np.array([s["offset_ns"] for s in d["series"]], dtype=np.int64)
    assert len(got) == len(truth) and (got == truth).all(), (len(got), len(truth))
    assert d["period_ns"] == 250_000_000
    assert d["unmatched_b"] >= 5 and d["unmatched_a"] > 0
    assert abs(d["offset"]["mean_ns"] - truth.mean()) < 1e-6 * abs(truth.mean())
    assert abs(d["offset"]["sd_ns"] - truth.std(ddof=1)) < 1e-6 * truth.std(ddof=1)
    assert d["stability"][0]["tau_s"] == 0.25
for key in ("offset", "abs_offset", "jitter", "stability"):
    assert docs[0][key] == docs[1][key] == docs[2][key], key
csv = pd.read_csv("series.csv")
assert (csv["offset_ns"].to_numpy() == truth).all()
print(len(truth), "pulses: mean offset %.1f us" % (truth.mean() / 1e3))
PY
# Errors: one store with two boards needs no --a/--b only when exactly two nodes have the channel;
# a missing channel and a wrong input count are clear errors.
expect_exit 65 "$M2MLAT" synctest a.db b.db --channel nothing
grep -q "no node has events on channel" err.txt || fail "unclear error for a missing channel"
expect_exit 2 "$M2MLAT" synctest a.db b.db ab.db
expect_exit 66 "$M2MLAT" synctest missing.db
"$M2MLAT" synctest ab.db --json > auto.json   # the two nodes with a pulse channel, in name order
echo "1 passed, 0 failed"
