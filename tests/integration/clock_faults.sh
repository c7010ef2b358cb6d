# Kernel logs with clock faults that m2mlat's simulator does not make (tests/integration/clock_faults.py):
# one line of another clock (first, middle, last line; either board), a printk stamp far off, a board
# that stamped edges before its first synchronisation (1970 or a fake-hwclock time), genuine steps of
# +-5 ms .. +-1 h, and all of them together. Each faulted pair of logs, read as files and through a
# store, must pair as the clean logs do: the same pairs, latencies within the step's measured size,
# the same flags (a corrected step's aside), the faulted lines' events left out and counted, nothing else.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"

"$M2MLAT" simulate --scenario static_5g --manoeuvres 150 --seed 7 --out-dir clean --format kernel-log >/dev/null
"$M2MLAT" pair --cause-file clean/operator.log --effect-file clean/vehicle.log -o clean.csv >/dev/null

# same CLEAN_DIR CLEAN_CSV FAULTED_DIR PAIRS_CSV STATS_JSON: the pairs of PAIRS_CSV are the clean
# ones (rules above).
same() {
  "$PY" - "$@" <<'PYEOF'
import csv, json, sys
clean_dir, clean_csv, faulted_dir, pairs_csv, stats_json = sys.argv[1:6]
faults = json.load(open(f"{faulted_dir}/faults.json"))
def stamps(path):
    return [int(l.rsplit(":", 1)[1]) for l in open(path) if "GPIO_" in l]
lost = {side: {stamps(f"{clean_dir}/{side}.log")[i] for i in faults["left_out"][side]}
        for side in ("operator", "vehicle")}
def pairs(path):
    return [(int(r["cause_time_ns"]), int(r["effect_time_ns"]), int(r["latency_ns"]), int(r["pair_flags"]) & ~256)
            for r in csv.DictReader(l for l in open(path) if not l.startswith("#"))]
want = [p for p in pairs(clean_csv) if p[0] not in lost["operator"] and p[1] not in lost["vehicle"]]
got = pairs(pairs_csv)
# A step's size is measured from the printk stamps: corrected stamps lie within 0.5 ms of the clean.
near = lambda a, b: abs(a[0] - b[0]) < 500_000 and abs(a[1] - b[1]) < 500_000 and abs(a[2] - b[2]) < 500_000
# A step back's first event is stamped where the old and new readings overlap: flagged "after clock
# step" (512) and left out of the statistics, never wrong. At most one such pair a step.
unplaced = [q for q in got if q[3] & 512]
if len(unplaced) > faults["steps"]:
    sys.exit(f"{faulted_dir}: {len(unplaced)} pairs flagged after a clock step: {unplaced[:3]}")
got = [q for q in got if not q[3] & 512]
want = [p for p in want if not any(abs(p[0] - q[0]) < 500_000 or abs(p[1] - q[1]) < 500_000 for q in unplaced)]
missing = [p for p in want if not any(near(p, q) for q in got)]
extra = [q for q in got if not any(near(p, q) for p in want)]
# The neighbours of a lost event may pair differently (its partner is now alone): at most 2 a loss.
allowed = 2 * sum(len(v) for v in faults["left_out"].values())
if len(missing) + len(extra) > allowed:
    sys.exit(f"{faulted_dir}: {len(missing)} clean pairs missing, {len(extra)} pairs not in the clean log "
             f"(allowed {allowed}): {missing[:3]} {extra[:3]}")
moved = [q for q in got if any(near(p, q) and p[3] != q[3] for p in want)]
if len(moved) > allowed:
    sys.exit(f"{faulted_dir}: {len(moved)} pairs with other flags: {moved[:3]}")
s = json.load(open(stats_json))["scenarios"][0]
left = s["pairing"].get("unknown_clock", {"cause": {"outlier": 0, "before_sync": 0}, "effect": {"outlier": 0, "before_sync": 0}})
counted = {"operator": sum(left["cause"].values()), "vehicle": sum(left["effect"].values())}
expected = {side: len(faults["left_out"][side]) + faults["prefix"][side] for side in counted}
if counted != expected:
    sys.exit(f"{faulted_dir}: left out {counted}, expected {expected}")
print(f"{faulted_dir}: {len(got)} pairs, left out {counted}")
PYEOF
}

# faulted CLEAN_DIR N FAULTS: writes fN from CLEAN_DIR with FAULTS and checks it, as files and
# through a store.
faulted() {
  local clean=$1 dir=f$2 faults=$3
  mkdir "$dir"
  "$PY" "$HERE/clock_faults.py" "$clean" "$dir" "$faults" "$2"
  "$M2MLAT" pair --cause-file "$dir/operator.log" --effect-file "$dir/vehicle.log" -o "$dir.csv" >/dev/null
  "$M2MLAT" stats --cause-file "$dir/operator.log" --effect-file "$dir/vehicle.log" --json >"$dir.json"
  same "$clean" "$clean.csv" "$dir" "$dir.csv" "$dir.json" || fail "files faulted with $faults"
  # The same through a store: the left-out lines are stored with the events and left out again.
  "$M2MLAT" import --store "$dir.db" "$dir/operator.log" --node operator --role cause --scenario s 2>/dev/null >/dev/null
  "$M2MLAT" import --store "$dir.db" "$dir/vehicle.log" --node vehicle --role effect --scenario s 2>"$dir.err" >/dev/null
  "$M2MLAT" pair "$dir.db" -o "$dir-store.csv" >/dev/null
  "$M2MLAT" stats "$dir.db" --json >"$dir-store.json"
  same "$clean" "$clean.csv" "$dir" "$dir-store.csv" "$dir-store.json" || fail "store of logs faulted with $faults"
}

n=0
for faults in outlier:vehicle:middle outlier:operator:first outlier:vehicle:last outlier:operator:1 \
              printk:operator:40 printk:vehicle:last boot:vehicle:1:epoch boot:operator:6:fakehw \
              boot:vehicle:3:epoch step:vehicle:5000000:70 step:vehicle:-5000000:70 step:operator:40000000:50 \
              step:vehicle:-40000000:120 step:vehicle:1000000000:60 step:operator:-1000000000:60 \
              step:vehicle:3600000000000:80 step:vehicle:-3600000000000:80 \
              step:vehicle:2000000:70 step:operator:-2000000:100 \
              "outlier:vehicle:20,outlier:vehicle:21,outlier:operator:90" \
              "boot:vehicle:4:fakehw,outlier:vehicle:30,step:vehicle:-40000000:90,outlier:operator:60" \
              "boot:operator:2:epoch,step:operator:3600000000000:40,step:vehicle:5000000:100,printk:vehicle:110,outlier:operator:last"; do
  n=$((n + 1))
  faulted clean $n "$faults"
done

# A published run of the reference rig (../shared/data, beside the checkout): its rows as the two
# boards' kernel logs with printk stamps (the board's offset from boot, a delay of 20-200 us), faulted.
require_upstream Static_5G.csv
mkdir rig
"$PY" - "$UPSTREAM/Static_5G.csv" rig <<'PYEOF'
import csv, random, sys
rows = list(csv.DictReader(open(sys.argv[1])))
rng = random.Random(3)
for side, s, ns, boot in (("operator", "remote_station_s", "remote_station_ns", 1_762_870_000),
                          ("vehicle", "vehicle_s", "vehicle_ns", 1_762_869_500)):
    with open(f"{sys.argv[2]}/{side}.log", "w") as f:
        for r in rows:
            t = int(r[s]) * 10**9 + int(r[ns])
            us = (t - boot * 10**9 + rng.randrange(20_000, 200_000)) // 1000
            f.write(f"[{us // 1_000_000:5d}.{us % 1_000_000:06d}] GPIO_16_IRQ:{t}\n")
PYEOF
"$M2MLAT" pair --cause-file rig/operator.log --effect-file rig/vehicle.log -o rig.csv >/dev/null
[ "$(grep -c ',0,true,$' rig.csv)" -ge 55 ] || fail "the published run's logs pair as $(grep -c ',0,true,$' rig.csv) clean pairs"
for faults in outlier:vehicle:middle outlier:operator:first "boot:vehicle:2:fakehw,step:vehicle:40000000:30" \
              step:vehicle:1000000:30 step:operator:-1000000:20 "step:operator:1000000:15,step:vehicle:-1000000:40" \
              "boot:operator:2:epoch,outlier:vehicle:12,step:vehicle:-1000000:30,step:operator:40000000:45" \
              "outlier:operator:10,step:operator:-40000000:25,outlier:vehicle:40,boot:operator:3:epoch"; do
  n=$((n + 1))
  faulted rig $n "$faults"
done

# What stats says of the left-out events, and import's warning naming the file.
"$M2MLAT" stats --cause-file f1/operator.log --effect-file f1/vehicle.log >f1.txt
grep -q "0 cause and 1 effect events left out, their stamps on no known clock (1 outliers" f1.txt || { cat f1.txt; fail "no note of the outlier"; }
grep -q "f1/vehicle.log: 1 GPIO lines are stamped on no known clock (1 outliers" f1.err || { cat f1.err; fail "import said nothing"; }
echo "clock faults: $n faulted pairs of logs pair as the clean ones"
