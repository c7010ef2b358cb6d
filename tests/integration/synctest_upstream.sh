# The reference rig's one-hour synchronisation tests, beside the checkout (../shared/data, not part of
# this repository; the test fails without them): `m2mlat synctest` on its CSV gives the same table as numpy on the file's own
# offsets (count, mean, sd, min, max, signed and by magnitude, percentiles, jitter), ADEV and MTIE
# at tau0 computed independently, and the study's ~0.3 ms mean offset.
source "$(dirname "$0")/lib.bash"
require_upstream Co_Referenced.csv
for name in Co_Referenced Autonomous; do
  "$M2MLAT" synctest "$UPSTREAM/$name.csv" --json --series > "$name.json"
  "$M2MLAT" synctest "$UPSTREAM/$name.csv" --csv "$name.series.csv" --svg "$name.svg" > "$name.txt"
  grep -q "|t_B - t_A|" "$name.txt" || fail "$name: no offset table"
  grep -q "<polyline" "$name.svg" || fail "$name: no plot"
  $PY - "$UPSTREAM/$name.csv" "$name.json" "$name.series.csv" "$name" <<'PY'
import json, sys
import numpy as np
import pandas as pd
rig = pd.read_csv(sys.argv[1])
doc = json.load(open(sys.argv[2]))
series = pd.read_csv(sys.argv[3])
name = sys.argv[4]
o = rig["sync_offset_ns"].to_numpy(dtype=np.int64)
assert doc["format"] == "m2mlat-synctest/1"
assert doc["pulses"] == len(o) == len(doc["series"]) == len(series)
assert (series["offset_ns"].to_numpy() == o).all()
def check(stats, values, what):
    values = values.astype(float)
    assert stats["n"] == len(values), (what, stats["n"])
    for key, want in [("mean_ns", values.mean()), ("sd_ns", values.std(ddof=1)),
                      ("min_ns", values.min()), ("max_ns", values.max())]:
        assert abs(stats[key] - want) <= 1e-6 * max(1.0, abs(want)), (name, what, key, stats[key], want)
    for p in stats["percentiles"]:
        want = np.percentile(values, p["percent"])
        assert abs(p["ns"] - want) <= 1e-6 * max(1.0, abs(want)), (name, what, p, want)
check(doc["offset"], o, "offset")
check(doc["abs_offset"], np.abs(o), "abs_offset")
check(doc["jitter"], np.diff(o), "jitter")
check(doc["abs_jitter"], np.abs(np.diff(o)), "abs_jitter")
# The study's figure: about 0.3 ms mean offset between the boards.
assert abs(doc["abs_offset"]["mean_ns"] / 1e6 - 0.3) < 0.05, doc["abs_offset"]["mean_ns"]
# tau0 = the median spacing of the trigger times; ADEV and MTIE at tau0 and 4 tau0 by numpy.
t = (rig["trigger_time_s"].to_numpy() * 1e9).round().astype(np.int64)
tau0 = int(np.median(np.diff(t)))
assert abs(doc["tau0_ns"] - tau0) <= 1, (doc["tau0_ns"], tau0)
x = (o - o[0]).astype(float)
for point in doc["stability"]:
    n = point["n"]
    if n not in (1, 4): continue
    d = x[2 * n:] - 2 * x[n:-n] + x[:-2 * n]
    adev = np.sqrt((d ** 2).mean() / 2) / (n * tau0)
    assert abs(point["adev"] - adev) <= 1e-9 * adev, (name, n, point["adev"], adev)
    windows = np.lib.stride_tricks.sliding_window_view(x, n + 1)
    mtie = (windows.max(axis=1) - windows.min(axis=1)).max()
    assert abs(point["mtie_ns"] - mtie) < 1e-6, (name, n, point["mtie_ns"], mtie)
print(name, len(o), "offsets: mean |offset| %.4f ms" % (doc["abs_offset"]["mean_ns"] / 1e6))
PY
done
echo "1 passed, 0 failed"
