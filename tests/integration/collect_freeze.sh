# A frozen agent: SIGSTOP the vehicle's agent for longer than the coordinator's timeouts. The
# coordinator must say it is stale and then unreachable, keep pulling the operator, and after
# SIGCONT say it is ok again and catch up, every event once.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"

start_pair 5

"$M2MLAT" collect --agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE" --store campaign.db \
  --stale-after 1.5s --read-timeout 2.5s --refresh 100ms >collect.out 2>collect.err &
COLLECT_PID=$!
wait_for_line collect.err "127\.0\.0\.1:$VE \(vehicle\) is ok" >/dev/null
kill -STOP "$VE_PID"
wait_for_line collect.err "127\.0\.0\.1:$VE \(vehicle\) is stale" 5 >/dev/null
wait_for_line collect.err "127\.0\.0\.1:$VE \(vehicle\) is unreachable" 10 >/dev/null
grep -qE "127\.0\.0\.1:$OP \(operator\) is (stale|unreachable)" collect.err &&
  { cat collect.err >&2; fail "the operator was reported unhealthy too"; }
kill -CONT "$VE_PID"
# Back: ok again (the second "is ok" line of the vehicle).
for ((i = 0; i < 200; i++)); do
  [ "$(grep -cE "127\.0\.0\.1:$VE \(vehicle\) is ok" collect.err)" -ge 2 ] && break
  sleep 0.05
done
[ "$(grep -cE "127\.0\.0\.1:$VE \(vehicle\) is ok" collect.err)" -ge 2 ] || { cat collect.err >&2; fail "the vehicle did not come back"; }
kill -TERM "$COLLECT_PID"; wait "$COLLECT_PID" || fail "collect did not end cleanly"
COLLECT_PID=
"$M2MLAT" collect --agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE" --store campaign.db \
  --stop-session --duration 1s --quiet >final.out 2>final.err || { cat final.err >&2; fail "the final collect failed"; }
expect_exactly_once campaign.db operator.db operator
expect_exactly_once campaign.db vehicle.db vehicle
echo "ok: stale and unreachable while stopped, caught up after SIGCONT"
