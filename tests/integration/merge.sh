# Offline merge: two board stores (imported apart, as boards that share no network record them)
# joined into a campaign store give the same statistics and pairs as one store holding both; merging
# again changes nothing; a bad input changes nothing either.
source "$(dirname "$0")/lib.bash"

"$M2MLAT" simulate --scenario static_5g --seed 3 --out-dir sim >/dev/null
"$M2MLAT" import sim/operator.csv --store operator.db --scenario s5g >/dev/null
"$M2MLAT" import sim/vehicle.csv --store vehicle.db --scenario s5g >/dev/null
"$M2MLAT" import sim/operator.csv sim/vehicle.csv --store together.db --scenario s5g >/dev/null

"$M2MLAT" merge campaign.db operator.db vehicle.db --json >merge1.json
"$PY" - <<'PY'
import json
m = json.load(open("merge1.json"))["merged"]
assert [x["nodes"] for x in m] == [["operator"], ["vehicle"]], m
assert all(x["events"] > 50 for x in m), m
PY
"$M2MLAT" stats campaign.db --json >merged.json
"$M2MLAT" stats together.db --json >together.json
cmp merged.json together.json || fail "stats of the merged store differ from those of one store"
"$M2MLAT" export campaign.db --what pairs >pairs1.csv
"$M2MLAT" export together.db --what pairs >pairs2.csv
cmp pairs1.csv pairs2.csv || fail "pairs of the merged store differ"

# Idempotent: again, in the other order, nothing new.
"$M2MLAT" export campaign.db >events1.csv
"$M2MLAT" merge campaign.db vehicle.db operator.db --json >merge2.json
"$PY" -c 'import json; m=json.load(open("merge2.json"))["merged"]; assert all(x["events"] == 0 for x in m), m'
"$M2MLAT" export campaign.db >events2.csv
cmp events1.csv events2.csv || fail "merging twice changed the campaign store"

# Bad input: a missing board, a file that is not a store, the campaign itself -> error, nothing changed.
echo "not a store" >junk.db
expect_exit 66 "$M2MLAT" merge campaign.db missing.db
expect_exit 65 "$M2MLAT" merge campaign.db junk.db
grep -q "junk.db" err.txt || fail "the error does not name the file: $(cat err.txt)"
expect_exit 2 "$M2MLAT" merge campaign.db campaign.db
"$M2MLAT" export campaign.db >events3.csv
cmp events1.csv events3.csv || fail "a refused merge changed the campaign store"
echo "merge: ok"
