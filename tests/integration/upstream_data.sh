# Real data from the reference study's published rig, beside the checkout (../shared/data, not part
# of this repository; the test fails without it): statistics equal numpy's on the file's own latencies, and the two sides,
# separated into kernel logs with bounces, dropouts and spurious edges added, pair back to the rows.
source "$(dirname "$0")/lib.bash"
require_upstream Static_5G.csv
for name in Static_Wifi Static_5G Dynamic_Co_Referenced Dynamic_Autonomous; do
  "$M2MLAT" stats "$UPSTREAM/$name.csv" --json --bootstrap 0 > "$name.json"
  $PY - "$UPSTREAM/$name.csv" "$name.json" "$name" <<'PY'
import json, sys
import numpy as np
import pandas as pd
rig = pd.read_csv(sys.argv[1])
lat = json.load(open(sys.argv[2]))["scenarios"][0]["latency"]
ms = rig["m2m_latency_ms"].to_numpy()
assert lat["n"] == len(ms)
for key, p in [("q1_ms", 25), ("median_ms", 50), ("q3_ms", 75), ("p95_ms", 95)]:
    assert abs(lat[key] - np.percentile(ms, p)) < 1e-3, (key, lat[key], np.percentile(ms, p))
assert abs(lat["mean_ms"] - ms.mean()) < 1e-3 and abs(lat["sd_ms"] - ms.std(ddof=1)) < 1e-3
# Separate the two boards' timestamps, damage them, and write them as the rig's kernel logs.
rng = np.random.default_rng(7)
cause = rig.remote_station_s.to_numpy() * 10**9 + rig.remote_station_ns.to_numpy()
effect = rig.vehicle_s.to_numpy() * 10**9 + rig.vehicle_ns.to_numpy()
keep_c = rng.random(len(cause)) > 0.05
keep_e = rng.random(len(effect)) > 0.05
survivors = {(int(c), int(e)) for c, e, kc, ke in zip(cause, effect, keep_c, keep_e) if kc and ke}
def damage(t, keep):
    t = list(t[keep])
    t += [x + int(rng.integers(200_000, 3_000_000)) for x in t if rng.random() < 0.2]      # bounces
    t += [int(x) for x in rng.integers(t[0], t[-1], size=3)]                             # spurious edges
    return sorted(t)
for side, t in [("cause", damage(cause, keep_c)), ("effect", damage(effect, keep_e))]:
    with open(f"{sys.argv[3]}_{side}.log", "w") as f:
        f.writelines(f"[ {i}.000000] GPIO_16_IRQ:{x}\n" for i, x in enumerate(t))
with open(f"{sys.argv[3]}_survivors.json", "w") as f:
    json.dump(sorted(survivors), f)
PY
  "$M2MLAT" pair --cause-file "${name}_cause.log" --effect-file "${name}_effect.log" -o "${name}_pairs.csv" > /dev/null
  $PY - "${name}_pairs.csv" "${name}_survivors.json" "$name" <<'PY'
import json, sys
import pandas as pd
pairs = pd.read_csv(sys.argv[1])
survivors = {tuple(p) for p in json.load(open(sys.argv[2]))}
found = set(zip(pairs.cause_time_ns, pairs.effect_time_ns))
missing = survivors - found
wrong = found - survivors
assert len(missing) <= 0.03 * len(survivors), (sys.argv[3], "missing", len(missing), len(survivors))
assert len(wrong) <= 0.03 * len(found), (sys.argv[3], "wrong", sorted(wrong)[:5])
print(sys.argv[3], len(survivors), "surviving rows,", len(found & survivors), "paired back,", len(wrong), "wrong")
PY
done
echo "1 passed, 0 failed"
