# The same events through every path give the same counts and statistics: the demo's own analysis,
# the simulated store, its events-csv files (stats --cause-file), those files imported into a store,
# the store pushed to an archive (a PostgreSQL server started here; that part is skipped without
# Debian's postgresql), and the same run's falling edges written as kernel logs, which hold one edge a
# pass, so that the others match them with --min-pulse off. Compared: every member of "pairing" and the latency's n,
# median and IQR (docs/statistics.md, "What the counts count").
PG=$(realpath "$(dirname "$0")/../support/pg_server.bash")  # before lib.bash changes the folder
source "$(dirname "$0")/lib.bash"

sim=(--scenario static_5g --seed 7 --set sensor.both_edges=true --set sensor.spurious_per_minute=3)
"$M2MLAT" simulate "${sim[@]}" --store sim.db > /dev/null
"$M2MLAT" simulate "${sim[@]}" --out-dir ev --format events-csv > /dev/null
# The same run's falling edges as kernel logs (the reference rig's format: one edge a pass, no rising).
mkdir kl
$PY - <<'PY'
import csv
for side in ("operator", "vehicle"):
    rows = csv.DictReader(line for line in open(f"ev/{side}.csv") if not line.startswith("#"))
    with open(f"kl/{side}.log", "w") as out:
        for r in rows:
            if r["edge"] == "falling":
                out.write(f"GPIO_16_IRQ:{r['time_ns']}\n")
PY
"$M2MLAT" demo --scenario static_5g --seed 7 --set sensor.spurious_per_minute=3 --store demo.db --json > demo.json
"$M2MLAT" import --store imp.db ev/operator.csv --node operator --role cause --scenario static_5g > /dev/null
"$M2MLAT" import --store imp.db ev/vehicle.csv --node vehicle --role effect --scenario static_5g > /dev/null

for pulse in auto off; do
  "$M2MLAT" stats sim.db --json --bootstrap 0 --min-pulse $pulse > "store-$pulse.json"
  "$M2MLAT" stats demo.db --json --bootstrap 0 --min-pulse $pulse > "demo-store-$pulse.json"
  "$M2MLAT" stats imp.db --json --bootstrap 0 --min-pulse $pulse > "import-$pulse.json"
  "$M2MLAT" stats --scenario static_5g --cause-file ev/operator.csv --effect-file ev/vehicle.csv --json \
    --bootstrap 0 --min-pulse $pulse > "files-$pulse.json"
done
"$M2MLAT" stats --scenario static_5g --cause-file kl/operator.log --effect-file kl/vehicle.log --json \
  --bootstrap 0 > kernel-log.json 2> /dev/null

rc=0
URL=$(bash "$PG" start "$WORK") || rc=$?
if [ "$rc" = 0 ]; then
  trap 'bash "$PG" stop "$WORK"; cleanup' EXIT
  "$M2MLAT" archive push sim.db "$URL" --label paths > /dev/null
  "$M2MLAT" stats "$URL" --label paths --json --bootstrap 0 > archive-auto.json
else
  echo "archive: skipped (no PostgreSQL server: $rc)"
fi

$PY - <<'PY'
import json, os
def counts(path, with_ids=True):
    s = json.load(open(path))["scenarios"]
    assert len(s) == 1, (path, len(s))
    s = s[0]
    p = dict(s["pairing"])
    latency = s["latency"]
    return {"pairing": p, "n": latency["n"], "median_ms": latency["median_ms"], "iqr_ms": latency["iqr_ms"]}

demo = counts("demo.json")
assert demo["pairing"]["glitches"]["cause"] + demo["pairing"]["glitches"]["effect"] > 0, demo  # interference dropped
paths = {"demo's own": demo}
for name in ["store-auto", "demo-store-auto", "import-auto", "files-auto", "archive-auto"]:
    if os.path.exists(f"{name}.json"):
        paths[name] = counts(f"{name}.json")
off = {name: counts(f"{name}.json") for name in ["store-off", "demo-store-off", "import-off", "files-off", "kernel-log"]}
for group in (paths, off):
    first_name, first = next(iter(group.items()))
    for name, got in group.items():
        assert got == first, f"{name} counts differ from {first_name}:\n{got}\n{first}"
assert "glitches" not in off["kernel-log"]["pairing"], off["kernel-log"]  # one edge a pass: no filter ran
print(f"counts: {len(paths)} paths agree with the filter (n {demo['n']}), {len(off)} without it (n {off['kernel-log']['n']})")
PY
