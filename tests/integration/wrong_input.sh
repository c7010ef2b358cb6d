# A wrong input never becomes a plausible number: the mistakes a new user makes, each refused,
# warned of or leaving the store as it was, never a table of zeros with exit 0.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"

"$M2MLAT" simulate --scenario static_5g --out-dir run --format kernel-log >/dev/null
"$M2MLAT" import --store s.db run/operator.log --node operator --role cause --scenario static_5g >/dev/null
"$M2MLAT" import --store s.db run/vehicle.log --node vehicle --role effect --scenario static_5g >/dev/null
"$M2MLAT" export s.db -o before.csv 2>/dev/null

# A selection that names nothing: an error listing what exists, with the nearest name.
expect_exit 65 "$M2MLAT" pair --cause-file run/operator.log --effect-file run/vehicle.log --cause wrong/gpio16 -o p.csv
grep -q "run/operator.log: no cause events of wrong/gpio16, falling edges; it has operator/gpio16 (" err.txt || fail "cause: $(cat err.txt)"
[ ! -e p.csv ] || fail "a pairs file was written"
expect_exit 65 "$M2MLAT" report s.db --effect vehicle/gpio61 --html r.html
grep -q "no effect events of vehicle/gpio61.*it has .*vehicle/gpio16 .*(did you mean 'vehicle/gpio16'?)" err.txt || fail "effect: $(cat err.txt)"
[ ! -e r.html ] || fail "a report was written"
expect_exit 65 "$M2MLAT" stats s.db --scenario static_5G
grep -q "no scenario 'static_5G'; it has static_5g (did you mean 'static_5g'?)" err.txt || fail "scenario: $(cat err.txt)"
expect_exit 65 "$M2MLAT" stats s.db --edge rising
grep -q "no cause events of operator/gpio16, rising edges; it has operator/gpio16 ([0-9]* falling)" err.txt || fail "edge: $(cat err.txt)"

# Swapped roles: a warning with both directions' figures, in text and JSON; the figures stay as asked.
"$M2MLAT" stats --cause-file run/vehicle.log --effect-file run/operator.log >swapped.txt
grep -q "^warning: run: cause and effect look swapped" swapped.txt || { cat swapped.txt; fail "no warning of swapped roles"; }
"$M2MLAT" stats --cause-file run/vehicle.log --effect-file run/operator.log --json >swapped.json
"$M2MLAT" stats --cause-file run/operator.log --effect-file run/vehicle.log --json >given.json
"$PY" - swapped.json given.json <<'PY'
import json, sys
swapped, given = (json.load(open(p))["scenarios"][0] for p in sys.argv[1:3])
assert [w["code"] for w in swapped["pairing"]["warnings"]] == ["roles_swapped"], swapped["pairing"]
assert "warnings" not in given["pairing"], given["pairing"]
assert swapped["latency"]["median_ms"] > 1.5 * given["latency"]["median_ms"]
PY

# The same file imported twice adds nothing and says so; exit 0.
"$M2MLAT" import --store s.db run/vehicle.log --node vehicle --role effect --scenario static_5g >out.txt
grep -q "its [0-9]* events of vehicle are already in the store: not imported again" out.txt || fail "import: $(cat out.txt)"
"$M2MLAT" export s.db -o after.csv 2>/dev/null
cmp -s before.csv after.csv || fail "importing a file again changed the store"

# All or nothing: a simulation stopped by SIGINT stores nothing (an existing store as it was, a new
# one not made); a merge that fails leaves no campaign store; watch on a missing store is an error.
run_and_interrupt() {  # STORE: a long simulation into STORE, SIGINT after 1 s; its exit code in $got
  "$M2MLAT" simulate --scenario static_wifi --set manoeuvres=0 --set duration=3600000s --store "$1" 2>sim.err &
  local pid=$!
  sleep 1
  kill -INT "$pid"
  got=0
  wait "$pid" || got=$?
}
run_and_interrupt s.db
[ "$got" = 130 ] || { cat sim.err; fail "an interrupted simulate exited $got"; }
grep -q "SIGINT before the run was recorded: nothing of it stored" sim.err || fail "simulate: $(cat sim.err)"
"$M2MLAT" export s.db -o after.csv 2>/dev/null
cmp -s before.csv after.csv || fail "an interrupted simulate changed the store"
run_and_interrupt new.db
[ "$got" = 130 ] && [ ! -e new.db ] || fail "an interrupted simulate left new.db ($got)"
expect_exit 65 "$M2MLAT" simulate --scenario static_5g --store s.db
grep -q "scenario 'static_5g' already has a session of operator" err.txt || fail "simulate again: $(cat err.txt)"
expect_exit 66 "$M2MLAT" merge out.db missing.db
[ ! -e out.db ] || fail "a failed merge left out.db"
expect_exit 66 timeout 5 "$M2MLAT" watch missing.db --duration 1s

# Usage errors name what was not understood and the nearest subcommand or option.
expect_exit 2 "$M2MLAT" stat s.db
grep -q "'stat' is not a subcommand (did you mean 'stats'?)" err.txt || fail "stat: $(cat err.txt)"
expect_exit 2 "$M2MLAT" stats s.db --max-latncy 3s
grep -q "did you mean '--max-latency' for '--max-latncy'?" err.txt || fail "option: $(cat err.txt)"

# mark with no agent listening says its mark is lost.
expect_exit 74 "$M2MLAT" mark planner_out --key 1 --to 127.0.0.1:9
grep -q "nothing listens there" err.txt || fail "mark: $(cat err.txt)"
echo "wrong input: every case refused, warned of, or leaving the store as it was"
