# `--matcher model` (docs/matcher.md, "Pairing as inference") through the real executable: the
# fitted model and its expected wrong pairs in stats' text and JSON, the flag of an improbable pair
# in the pairs file, and continuous steering (a pass every 0.56 s, latency 0.8 s, 2 % of the effect
# edges lost) paired right where the rules shift every pair after a loss by a period.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"

"$M2MLAT" simulate --scenario static_5g --manoeuvres 80 --seed 4 --out-dir sim >/dev/null
"$M2MLAT" stats --cause-file sim/operator.csv --effect-file sim/vehicle.csv --matcher model >stats.txt
grep -Eq "^sim: model: latency [0-9.]+ ms .* pairs at p >= 0.99, [0-9.]+ of them expected wrong$" stats.txt ||
  { cat stats.txt >&2; fail "stats --matcher model: no model line"; }
"$M2MLAT" stats --cause-file sim/operator.csv --effect-file sim/vehicle.csv --matcher model --json >stats.json
"$PY" - stats.json <<'PYEOF' || fail "stats --matcher model --json: no model"
import json, sys
m = json.load(open(sys.argv[1]))["scenarios"][0]["pairing"]["model"]
assert 0.7 < m["latency_s"] < 1.2 and m["kept"] > 60 and 0 <= m["expected_wrong"] < 5, m
PYEOF
# Without --matcher model there is no model.
"$M2MLAT" stats --cause-file sim/operator.csv --effect-file sim/vehicle.csv --json >rules.json
"$PY" -c 'import json,sys; sys.exit("model" in json.load(open(sys.argv[1]))["scenarios"][0]["pairing"])' rules.json ||
  fail "the rules' JSON has a model"
expect_exit 2 "$M2MLAT" stats --cause-file sim/operator.csv --effect-file sim/vehicle.csv --matcher nearest
expect_exit 2 "$M2MLAT" stats --cause-file sim/operator.csv --effect-file sim/vehicle.csv --matcher model --min-probability 0.2

# Continuous steering as two kernel logs (stamps only), with the truth beside them.
"$PY" - <<'PYEOF'
import random
rng = random.Random(5)
t, lat, truth = 1_780_000_000.0, 0.8, []
with open("operator.log", "w") as op, open("vehicle.log", "w") as ve:
    for k in range(400):
        t += 0.56 * (0.9 + 0.2 * rng.random())
        lat = 0.8 + 0.9 * (lat - 0.8) + rng.gauss(0, 0.01)
        c = int(t * 1e9)
        e = int((t + lat) * 1e9)
        op.write(f"GPIO_16_IRQ:{c}\n")
        if rng.random() >= 0.02:
            ve.write(f"GPIO_16_IRQ:{e}\n")
            truth.append(f"{c},{e}")
open("truth.txt", "w").write("\n".join(truth) + "\n")
PYEOF
sort -t, -k2 -n -o vehicle.log vehicle.log
for matcher in model rules; do
  "$M2MLAT" pair --cause-file operator.log --effect-file vehicle.log --matcher "$matcher" -o "$matcher.csv" >/dev/null
done
"$PY" - model.csv rules.csv truth.txt <<'PYEOF' || fail "continuous steering"
import csv, sys
truth = {tuple(map(int, l.split(","))) for l in open(sys.argv[3]) if l.strip()}
def score(path):
    rows = list(csv.DictReader(l for l in open(path) if not l.startswith("#")))
    kept = [r for r in rows if int(r["pair_flags"]) & 31 == 0]
    wrong = [r for r in kept if (int(r["cause_time_ns"]), int(r["effect_time_ns"])) not in truth]
    return len(kept), len(wrong)
model, rules = score(sys.argv[1]), score(sys.argv[2])
print(f"continuous steering: model keeps {model[0]} pairs, {model[1]} wrong; the rules {rules[0]}, {rules[1]} wrong; {len(truth)} true")
assert model[1] == 0 and model[0] >= 0.95 * len(truth), model
PYEOF
# Each pair's posterior probability in the pairs file: the improbable ones are those below 0.99, and
# the sum of 1 - p over the others is the expected count of wrong pairs kept that stats prints.
"$M2MLAT" stats --cause-file operator.log --effect-file vehicle.log --matcher model --json --bootstrap 0 > model.json
"$PY" - model.csv rules.csv model.json <<'PYEOF' || fail "the pairs' probabilities"
import csv, json, sys
rows = list(csv.DictReader(open(sys.argv[1])))
p = [float(r["probability"]) for r in rows]
assert all(0 <= x <= 1 for x in p), min(p)
assert [x < 0.99 for x in p] == [r["left_out"] == "improbable" for r in rows]
expected = sum(1 - x for x in p if x >= 0.99)
printed = json.load(open(sys.argv[3]))["scenarios"][0]["pairing"]["model"]["expected_wrong"]
assert abs(expected - printed) < 1e-3 * max(1, printed), (expected, printed)
assert "probability" not in next(csv.DictReader(open(sys.argv[2]))), "the rules have no probabilities"
PYEOF
echo "ok: --matcher model"
