# The reference rig's paired-results CSV: latencies identical to its own m2m_latency_ms column (to
# 1 us) through import -> store -> re-pairing -> export, and statistics equal to numpy's.
source "$(dirname "$0")/lib.bash"
# Written for this test: 0 to 6 decimals, a borrow across the second, a 1 ns latency step.
cat > run1.csv <<'CSV'
remote_station_s,remote_station_ns,vehicle_s,vehicle_ns,,m2m_latency_ms
1700000100,100000000,1700000100,950123456,,850.123456
1700000103,999999999,1700000104,812000001,,812.000002
1700000107,250000000,1700000108,100400400,,850.4004
1700000110,5,1700000110,700000005,,700
1700000113,123456789,1700000114,100000000,,976.543211
1700000116,500000000,1700000117,433333333,,933.333333
1700000119,900000000,1700000120,899999999,,999.999999
1700000122,1,1700000123,2,,1000.000001
1700000125,300000000,1700000126,1000000,,701
CSV
"$M2MLAT" import --store c.db run1.csv > /dev/null
"$M2MLAT" export c.db --what pairs --format pairs-csv -o pairs.csv
"$M2MLAT" stats c.db --json --bootstrap 0 --percentile 10 > stats.json
"$M2MLAT" stats run1.csv --json --bootstrap 0 > stats_file.json
$PY - run1.csv pairs.csv stats.json stats_file.json <<'PY'
import json, sys
import numpy as np
import pandas as pd
rig = pd.read_csv(sys.argv[1])
ours = pd.read_csv(sys.argv[2])
assert len(ours) == len(rig), (len(ours), len(rig))
# latency_ns is exact; the file's m2m_latency_ms is rounded to at most 6 decimals.
diff_ns = ours["latency_ns"].to_numpy() - np.round(rig["m2m_latency_ms"].to_numpy() * 1e6).astype(np.int64)
assert np.all(np.abs(diff_ns) <= 1000), diff_ns  # within 1 us of the file's own column
ms = rig["m2m_latency_ms"].to_numpy()
exact_ms = ours["latency_ns"].to_numpy() / 1e6
for path in sys.argv[3:]:
    lat = json.load(open(path))["scenarios"][0]["latency"]
    assert lat["n"] == len(ms)
    q = np.percentile(exact_ms, [5, 25, 50, 75, 90, 95, 99])
    for key, want in zip(["p5_ms", "q1_ms", "median_ms", "q3_ms", "p90_ms", "p95_ms", "p99_ms"], q):
        assert abs(lat[key] - want) < 1e-9, (key, lat[key], want)
    assert abs(lat["mean_ms"] - exact_ms.mean()) < 1e-9
    assert abs(lat["sd_ms"] - exact_ms.std(ddof=1)) < 1e-9
    assert abs(lat["iqr_ms"] - (q[3] - q[1])) < 1e-9
    for t in lat["above"]:
        assert t["count"] == int((ours["latency_ns"] > t["threshold_ns"]).sum())
print("rig formats ok")
PY
echo "1 passed, 0 failed"
