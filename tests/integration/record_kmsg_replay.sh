# `record --source kmsg` replaying an old kernel log: the edges (stamped in 2026-05) are stored, and
# the summary says the edge -> durable commit latency does not apply to them instead of giving their
# age as a latency; --json counts them as replayed with no latency samples.
source "$(dirname "$0")/lib.bash"

for i in 0 1 2 3; do printf 'GPIO_16_IRQ:%d\n' $((1780000000000000000 + i * 500000000)); done > old.log
"$M2MLAT" record --store replay.db --node vehicle --source kmsg --kmsg old.log --channel wheel=k:16 \
  --no-clock-monitor --duration 1s --quiet > out.txt
grep -q '^  wheel  *4 ' out.txt || { cat out.txt >&2; fail "the 4 replayed edges were not stored"; }
grep -q 'edge -> durable commit: n/a for 4 replayed events (stamped before the recording began)' out.txt \
  || { cat out.txt >&2; fail "no n/a line for the replayed edges"; }
if grep -q 'edge -> durable commit: p50' out.txt; then cat out.txt >&2; fail "a latency was given for replayed edges"; fi

"$M2MLAT" record --store replay2.db --node vehicle --source kmsg --kmsg old.log --channel wheel=k:16 \
  --no-clock-monitor --duration 1s --quiet --json > out.json
$PY - out.json <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
assert j["events"] == 4, j
assert j["commit_latency_replayed"] == 4 and j["commit_latency_ns"]["events"] == 0, j
PY
echo "1 passed, 0 failed"
