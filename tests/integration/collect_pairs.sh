# Two simulated agents (same seed: operator = cause, vehicle = effect) and `m2mlat collect` as real
# processes: collect begins a session on both, follows them, stops the sessions and takes the rest.
# The campaign store must then hold exactly each agent's events, and its pairs must equal those
# computed from the two agent stores themselves.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

start_pair 7

"$M2MLAT" collect --agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE" --store campaign.db \
  --start-session --label run-1 --scenario pairs --stop-session --duration 6s --json >collect.json 2>collect.err ||
  { cat collect.err >&2; fail "collect failed"; }
grep -qE 'collect: (GET|POST) ' collect.err && { cat collect.err >&2; fail "collect reported errors"; }

# After --stop-session the agents store nothing more: their stores are final.
expect_exactly_once campaign.db operator.db operator
expect_exactly_once campaign.db vehicle.db vehicle

"$M2MLAT" pair --scenario pairs -o campaign-pairs.csv campaign.db >/dev/null
if "$M2MLAT" help 2>/dev/null | grep -qE '^ *merge '; then
  "$M2MLAT" merge merged.db operator.db vehicle.db >/dev/null
  "$M2MLAT" pair --scenario pairs -o reference-pairs.csv merged.db >/dev/null
else  # several stores given together are read as one campaign
  "$M2MLAT" pair --scenario pairs -o reference-pairs.csv operator.db vehicle.db >/dev/null
fi
pairs=$(grep -vc '^#' campaign-pairs.csv || true)
[ "$pairs" -gt 1 ] || fail "no pairs in the campaign store"
# The session column is each store's own id (the campaign and the merge number sessions in their order).
cmp -s <(cut -d, -f1,3- campaign-pairs.csv) <(cut -d, -f1,3- reference-pairs.csv) ||
  { diff campaign-pairs.csv reference-pairs.csv | head >&2; fail "the campaign's pairs differ from the agents'"; }
# What the agents recorded before collect began its session is in their first session, whose scenario
# (none given) is "unnamed", never an empty name.
$PY -c 'import sqlite3,sys
names = {r[0] for r in sqlite3.connect(sys.argv[1]).execute("select distinct scenario from sessions")}
sys.exit(0 if names == {"unnamed", "pairs"} else f"scenarios: {names}")' campaign.db
"$M2MLAT" stats campaign.db --scenario pairs >campaign-stats.txt
n=$($PY -c 'import json,sys; d=json.load(open("collect.json")); print(sum(a["events"] for a in d["agents"]))')
[ "$n" -gt 0 ] || fail "collect stored no events"
echo "ok: $n events collected, $((pairs - 1)) pairs, equal to the agents' own"
