# Malformed input gives a clear error naming file and line, a data-error exit code, and stores nothing.
source "$(dirname "$0")/lib.bash"
cp "$DATA/rig_paired_small.csv" good.csv
"$M2MLAT" import --store s.db good.csv > /dev/null
"$M2MLAT" export s.db -o before.csv
cp "$DATA/rig_paired_small.csv" bad.csv
echo "1700000120,12x,1700000121,0,,1000" >> bad.csv
line=$(wc -l < bad.csv)
# A good file followed by a bad one: nothing of either is stored.
cp "$DATA/rig_paired_small.csv" good2.csv
expect_exit 65 "$M2MLAT" import --store s.db good2.csv bad.csv
grep -q "bad.csv:$line" err.txt || fail "message does not name bad.csv:$line: $(cat err.txt)"
grep -q "remote_station_ns" err.txt || fail "message does not name the field: $(cat err.txt)"
"$M2MLAT" export s.db -o after.csv
cmp -s before.csv after.csv || fail "the store changed"
[ "$("$M2MLAT" stats s.db --json --bootstrap 0 | $PY -c 'import json,sys; print(len(json.load(sys.stdin)["scenarios"]))')" = 1 ] || fail "a session was added"
# Other refusals: missing file, unknown format, a kernel log line that is malformed.
expect_exit 66 "$M2MLAT" import --store s.db no-such-file.csv
expect_exit 2 "$M2MLAT" import --store s.db good.csv --format no-such-format
printf 'GPIO_16_IRQ:1700000000000000000\nGPIO_16_IRQ:17000000000000x0000\n' > k.log
expect_exit 65 "$M2MLAT" import --store s.db k.log --node operator
grep -q "k.log:2" err.txt || fail "kernel log error does not name k.log:2: $(cat err.txt)"
expect_exit 2 "$M2MLAT" stats s.db --max-latency soon
grep -q -- "--max-latency" err.txt || fail "bad option value not named: $(cat err.txt)"
echo "1 passed, 0 failed"
