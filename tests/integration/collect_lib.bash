# Shared by the collect_*.sh integration tests (sourced after lib.bash): start sim agents as real
# processes on ephemeral loopback ports, find their ports, and compare stores by their events.

AGENT_PIDS=()
COLLECT_PID=
cleanup_processes() {
  local pid
  for pid in "${AGENT_PIDS[@]}" $COLLECT_PID; do
    kill -CONT "$pid" 2>/dev/null || true
    kill -KILL "$pid" 2>/dev/null || true
  done
  wait 2>/dev/null || true
}
trap 'cleanup_processes; [ -n "${KEEP_WORK:-}" ] && echo "kept $WORK" >&2 || rm -rf "$WORK"' EXIT

# wait_for_line FILE REGEX [SECONDS]: waits until FILE has a line matching REGEX; prints the match.
wait_for_line() {
  local file=$1 re=$2 limit=${3:-15} i
  for ((i = 0; i < limit * 20; i++)); do
    if grep -qE "$re" "$file" 2>/dev/null; then grep -oE "$re" "$file" | head -n1; return 0; fi
    sleep 0.05
  done
  cat "$file" >&2 || true
  fail "no line matching '$re' in $file after ${limit}s"
}

# start_agent NAME ROLE SEED STORE LISTEN [args...]: starts `m2mlat agent` with the sim source in
# the background; sets AGENT_PID and AGENT_PORT (from its "listening 127.0.0.1:PORT" line).
start_agent() {
  local name=$1 role=$2 seed=$3 store=$4 listen=$5
  shift 5
  : >"$name.log"
  # Nine magnets: a few events a second, paced like a real wheel.
  "$M2MLAT" agent --source sim --seed "$seed" --role "$role" --node "$name" --store "$store" \
    --listen "$listen" --sim-set magnets_deg=0,20,40,60,80,100,120,140,160 "$@" >>"$name.log" 2>&1 &
  AGENT_PID=$!
  AGENT_PIDS+=("$AGENT_PID")
  AGENT_PORT=$(wait_for_line "$name.log" 'listening 127\.0\.0\.1:[0-9]+' | sed 's/.*://')
}

# events_of STORE [NODE]: the store's events (node, channel, edge, clock, time, seqno, line_seqno,
# flag_bits), sorted, one per line; without the scenario, session and label columns (each store
# numbers its sessions in its own order).
events_of() {
  local store=$1 node=${2:-}
  if [ -n "$node" ]; then
    "$M2MLAT" export "$store" --node "$node" 2> >(grep -v '^note: ' >&2) | tail -n +2 | cut -d, -f4- | sort
  else
    "$M2MLAT" export "$store" 2> >(grep -v '^note: ' >&2) | tail -n +2 | cut -d, -f4- | sort
  fi
}

# expect_exactly_once CAMPAIGN AGENT_STORE NODE: every event of AGENT_STORE is in CAMPAIGN once,
# and CAMPAIGN has no other event of NODE: the two sorted lists are equal, duplicates included (a
# restarted simulated agent replays its run, so equal events may occur in the agent's own store;
# the campaign must then have them exactly as often).
expect_exactly_once() {
  local campaign=$1 agent=$2 node=$3
  events_of "$agent" >"agent-$node.txt"
  events_of "$campaign" "$node" >"campaign-$node.txt"
  [ -s "agent-$node.txt" ] || fail "$node: the agent stored no events"
  if ! cmp -s "agent-$node.txt" "campaign-$node.txt"; then
    diff "agent-$node.txt" "campaign-$node.txt" | head -n 10 >&2
    fail "$node: the campaign's events differ from the agent's ($(wc -l <"agent-$node.txt") vs $(wc -l <"campaign-$node.txt"))"
  fi
}

# start_pair SEED: the operator (cause) and the vehicle (effect) as paced sim agents of one seed, on
# operator.db and vehicle.db; sets OP and VE (their ports) and VE_PID.
start_pair() {
  start_agent operator cause "$1" operator.db 127.0.0.1:0 --sim-paced
  OP=$AGENT_PORT
  start_agent vehicle effect "$1" vehicle.db 127.0.0.1:0 --sim-paced
  VE=$AGENT_PORT
  VE_PID=$AGENT_PID
}
