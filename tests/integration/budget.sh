# `m2mlat budget`: the reference study's inputs (0.3 ms sync, 5 us cyclictest, 1 deg at 100 deg/s)
# give its 10-15 ms, each term as worst case and u; the steering rate measured on a simulated three-magnet wheel turned at a fixed
# speed; E_sync from a synctest result and from a store's live clock bounds; errors.
source "$(dirname "$0")/lib.bash"
"$M2MLAT" budget --sync 0.3ms --kernel-a 5us --kernel-b 4us --misalignment 1 --rate 100 --json > study.json
"$M2MLAT" budget --sync 0.3ms --kernel-a 5us --misalignment 1 --rate 100 > study.txt
grep -q "total (sum)" study.txt || fail "no total in the table"
grep -q "^U95 " study.txt || fail "no U95 in the table"
# A wheel with magnets 30 degrees apart turned at 200 deg/s: 1 deg is 5 ms.
"$M2MLAT" simulate --store wheel.db --manoeuvres 20 --set magnets_deg=0,30,60 \
  --set motion.speed_min_deg_s=200 --set motion.speed_max_deg_s=200.000001 > /dev/null
"$M2MLAT" budget --sync-store wheel.db --kernel-a 5us --rate-store wheel.db --rate-channel operator/wheel \
  --magnet-angle 30 --json > measured.json
# A synctest result as the sync term.
$PY - <<'PY'
t0 = 1_780_304_400_000_000_000
with open("pulse.csv", "w") as f:
    f.write("# format: m2mlat-events/1\nnode,channel,edge,clock,time_ns,seqno,line_seqno,flags\n")
    rows = []
    for i in range(200):
        rows.append((t0 + i * 500_000_000, "a"))
        rows.append((t0 + i * 500_000_000 + (250_000 if i % 2 else -350_000), "b"))
    for k, (t, n) in enumerate(sorted(rows)):
        f.write(f"{n},pulse,falling,realtime,{t},{k + 1},{k + 1},0\n")
PY
"$M2MLAT" synctest pulse.csv --a a --b b --json > sync.json
"$M2MLAT" budget --synctest sync.json --kernel-a 5us --rate 100 --json > from_sync.json
"$M2MLAT" budget --synctest sync.json --sync-stat max_abs --kernel-a 5us --rate 100 --json > from_sync_max.json
$PY - <<'PY'
import json
study = json.load(open("study.json"))
terms = {t["name"]: t["ns"] for t in study["terms"]}
assert terms == {"sync": 300_000, "kernel": 5_000, "circuit": 2_000, "calibration": 10_000_000}, terms
assert study["total_ns"] == sum(terms.values())
assert 10.0 <= study["total_ms"] <= 15.0, study["total_ms"]
# One story: u is the root sum of squares of the terms' u, U95 = 2 u; the calibration's 10 ms bound
# (uniform) is 5.77 ms of u, and U95 (11.6 ms) lies between the bound's typical part and the sum.
u = [t["u_ns"] for t in study["terms"]]
assert abs(study["u_ns"] - sum(x * x for x in u) ** 0.5) < 1e-3 and study["U95_ns"] == 2 * study["u_ns"], study
assert abs(study["u_ms"] - 10 / 3 ** 0.5) < 0.01, study["u_ms"]
m = {t["name"]: t for t in json.load(open("measured.json"))["terms"]}
assert abs(m["calibration"]["ns"] - 5_000_000) < 50_000, m["calibration"]
# The simulator's clock samples: both boards' median bounds, a few to some tens of ms.
assert 1_000_000 < m["sync"]["ns"] < 100_000_000, m["sync"]
s = {t["name"]: t["ns"] for t in json.load(open("from_sync.json"))["terms"]}
assert s["sync"] == 300_000, s   # mean of |+250 us| and |-350 us|
s = {t["name"]: t["ns"] for t in json.load(open("from_sync_max.json"))["terms"]}
assert s["sync"] == 350_000, s
print("study inputs: %.3f ms; measured wheel: calibration %.3f ms" % (study["total_ms"], m["calibration"]["ns"] / 1e6))
PY
# The same calibration term in every sample's u and bound: stats --misalignment --rate.
"$M2MLAT" stats wheel.db --json --bootstrap 0 > plain.json
"$M2MLAT" stats wheel.db --json --bootstrap 0 --misalignment 1 --rate 100 > calibrated.json
$PY - <<'PY'
import json
plain, cal = (json.load(open(p))["scenarios"][0]["sample_uncertainty"] for p in ("plain.json", "calibrated.json"))
# u adds 10 / sqrt(3) ms in quadrature, the bound 10 ms.
assert abs(cal["median_u_ms"] ** 2 - plain["median_u_ms"] ** 2 - 100 / 3) < 0.05, (plain, cal)
assert abs(cal["median_max_err_ms"] - plain["median_max_err_ms"] - 10) < 1e-3, (plain, cal)
assert abs(cal["median_U95_ms"] - 2 * cal["median_u_ms"]) < 1e-3, cal
PY
expect_exit 2 "$M2MLAT" stats wheel.db --misalignment 1                          # no rate
expect_exit 2 "$M2MLAT" stats wheel.db --misalignment 1 --rate 100 --calibration-u 1ms
expect_exit 2 "$M2MLAT" budget --kernel-a 5us --rate 100                       # no sync term
expect_exit 2 "$M2MLAT" budget --sync 1ms --synctest sync.json --rate 100        # two sync terms
expect_exit 2 "$M2MLAT" budget --sync 1ms                                        # no rate
expect_exit 65 "$M2MLAT" budget --synctest study.json --rate 100                 # not a synctest result
grep -q "study.json" err.txt || fail "the error does not name the file"
echo "1 passed, 0 failed"
