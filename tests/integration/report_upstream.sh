# Comparisons on the reference study's published results, beside the checkout (../shared/data, not
# part of this repository; the test fails without them): the study's figures (medians, IQRs, "5G has a 47 % narrower IQR than
# WiFi", co-referenced has the lower median, shares above 1 s) come out of `m2mlat report`, and its
# significance tests equal SciPy's (Debian's python3-scipy) on the same latencies.
source "$(dirname "$0")/lib.bash"
require_upstream Static_5G.csv
$PY -c "import scipy" || fail "python3-scipy is not installed (make deps installs it)"

"$M2MLAT" report "$UPSTREAM"/{Static_Wifi,Static_5G,Dynamic_Co_Referenced,Dynamic_Autonomous}.csv \
  --compare Static_5G:Static_Wifi --compare Dynamic_Co_Referenced:Dynamic_Autonomous --out out > report.txt
grep -q "Static_5G vs Static_Wifi: IQR 47 % narrower" report.txt || { cat report.txt; fail "no '47 % narrower' sentence"; }
$PY - "$UPSTREAM" out/report.json <<'PY'
import json, sys
import numpy as np
import pandas as pd
from scipy import stats
up, doc = sys.argv[1], json.load(open(sys.argv[2]))
assert doc["groups"] == ["Static", "Dynamic"], doc["groups"]
ns = {}
for s in doc["scenarios"]:
    rig = pd.read_csv(f"{up}/{s['scenario']}.csv")
    lat = (rig.vehicle_s * 10**9 + rig.vehicle_ns) - (rig.remote_station_s * 10**9 + rig.remote_station_ns)
    ns[s["scenario"]] = lat.to_numpy(dtype=np.int64)
    ms = ns[s["scenario"]] / 1e6
    L = s["latency"]
    assert L["n"] == len(ms)
    assert abs(L["median_ms"] - np.median(ms)) < 1e-6, (s["scenario"], L["median_ms"], np.median(ms))
    iqr = np.percentile(ms, 75) - np.percentile(ms, 25)
    assert abs(L["iqr_ms"] - iqr) < 1e-6
    above = {a["threshold_ns"]: a for a in L["above"]}
    assert above[10**9]["count"] == int((ns[s["scenario"]] > 10**9).sum())
    print(f"{s['scenario']}: median {L['median_ms']:.1f} ms, IQR {L['iqr_ms']:.1f} ms, "
          f"above 1 s {100 * above[10**9]['fraction']:.1f} %")
c5g, cdyn = doc["comparisons"]
assert (c5g["subject"], c5g["baseline"]) == ("Static_5G", "Static_Wifi")
assert round((1 - c5g["iqr_ratio"]) * 100) == 47, c5g["iqr_ratio"]
assert cdyn["median_difference_ms"] < 0, cdyn["median_difference_ms"]   # co-referenced has the lower median
for c in doc["comparisons"]:
    a, b = ns[c["subject"]], ns[c["baseline"]]
    mw = stats.mannwhitneyu(a, b, alternative="two-sided", method="asymptotic")
    assert c["mann_whitney"]["u_subject"] == mw.statistic, (c["mann_whitney"], mw)
    assert abs(c["mann_whitney"]["p"] - mw.pvalue) <= 1e-9 * mw.pvalue, (c["mann_whitney"]["p"], mw.pvalue)
    # For these sizes SciPy's default method is the same normal approximation.
    assert abs(stats.mannwhitneyu(a, b).pvalue - mw.pvalue) == 0
    bf = stats.levene(a, b, center="median")
    assert abs(c["brown_forsythe"]["w"] - bf.statistic) <= 1e-9 * bf.statistic, (c["brown_forsythe"], bf)
    assert abs(c["brown_forsythe"]["p"] - bf.pvalue) <= 1e-8 * bf.pvalue, (c["brown_forsythe"], bf)
    for q in ("median_difference_ci_ms", "iqr_ratio_ci", "sd_ratio_ci"):
        lo, hi = c[q]
        point = c[q.replace("_ci", "")]
        assert lo <= point <= hi, (q, lo, point, hi)
    print(f"{c['subject']} vs {c['baseline']}: Mann-Whitney p {c['mann_whitney']['p']:.4g} (SciPy {mw.pvalue:.4g}), "
          f"Brown-Forsythe p {c['brown_forsythe']['p']:.4g} (SciPy {bf.pvalue:.4g})")
PY
grep -q "<svg" out/report.html || fail "no charts in the HTML report"
echo "1 passed, 0 failed"
