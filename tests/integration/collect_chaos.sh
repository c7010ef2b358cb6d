# Exactly once through crashes: two simulated agents and the coordinator as real processes; for
# several rounds the coordinator, an agent, or both are killed with SIGKILL at a random moment and
# restarted (the agent on the same port and store). At the end every event each agent committed
# is in the campaign store exactly once, and nothing else is.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/lib.bash"
source "$HERE/collect_lib.bash"
ROUNDS=${COLLECT_CHAOS_ROUNDS:-5}

start_agent operator cause 11 operator.db 127.0.0.1:0 --sim-paced
OP=$AGENT_PORT OP_PID=$AGENT_PID
start_agent vehicle effect 11 vehicle.db 127.0.0.1:0 --sim-paced
VE=$AGENT_PORT VE_PID=$AGENT_PID
AGENTS=(--agent "http://127.0.0.1:$OP" --agent "http://127.0.0.1:$VE")

start_collect() {
  "$M2MLAT" collect "${AGENTS[@]}" --store campaign.db --quiet >>collect.out 2>>collect.err &
  COLLECT_PID=$!
}
restart_agent() {  # NAME ROLE PORT
  start_agent "$1" "$2" 11 "$1.db" "127.0.0.1:$3" --sim-paced
}
pause() { sleep "$($PY -c 'import random; print(round(random.uniform(0.2, 1.2), 2))')"; }

start_collect
for ((round = 1; round <= ROUNDS; round++)); do
  pause
  case $((RANDOM % 4)) in
    0) victim="coordinator"; kill -9 "$COLLECT_PID"; wait "$COLLECT_PID" 2>/dev/null || true; start_collect ;;
    1) victim="operator"; kill -9 "$OP_PID"; wait "$OP_PID" 2>/dev/null || true
       restart_agent operator cause "$OP"; OP_PID=$AGENT_PID ;;
    2) victim="vehicle"; kill -9 "$VE_PID"; wait "$VE_PID" 2>/dev/null || true
       restart_agent vehicle effect "$VE"; VE_PID=$AGENT_PID ;;
    3) victim="coordinator and vehicle"; kill -9 "$COLLECT_PID" "$VE_PID"
       wait "$COLLECT_PID" "$VE_PID" 2>/dev/null || true
       restart_agent vehicle effect "$VE"; VE_PID=$AGENT_PID; start_collect ;;
  esac
  echo "round $round: killed the $victim"
done
pause
# The end: stop the agents' sessions (they then store nothing more) and take the rest.
kill -TERM "$COLLECT_PID"; wait "$COLLECT_PID" || fail "collect did not end cleanly on SIGTERM"
COLLECT_PID=
"$M2MLAT" collect "${AGENTS[@]}" --store campaign.db --stop-session --duration 1s --quiet >final.out 2>final.err ||
  { cat final.err >&2; fail "the final collect failed"; }

expect_exactly_once campaign.db operator.db operator
expect_exactly_once campaign.db vehicle.db vehicle
echo "ok: $ROUNDS rounds; operator $(wc -l <agent-operator.txt) and vehicle $(wc -l <agent-vehicle.txt) events, each stored once"
