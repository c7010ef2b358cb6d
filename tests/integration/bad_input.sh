# Malformed input gives a clear error naming file and line, a data-error exit code, and stores nothing.
# Inputs and options that would take memory without bound are refused quickly and in little memory.
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
# peak_run OUT ERR COMMAND...: runs COMMAND and prints "<exit code> <peak RSS in KiB> <seconds>" of
# that process (the only child of the Python that measures it).
peak_run() {
  $PY - "$@" <<'EOF'
import resource, subprocess, sys, time
out, err, cmd = sys.argv[1], sys.argv[2], sys.argv[3:]
start = time.monotonic()
with open(out, "wb") as o, open(err, "wb") as e:
    rc = subprocess.call(cmd, stdout=o, stderr=e)
took = time.monotonic() - start
print(rc, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss, f"{took:.2f}")
EOF
}
# expect_bounded CODE MAX_KIB COMMAND...: exits CODE within 5 s, its peak RSS below MAX_KIB; stderr in err.txt.
# (256 MiB leaves room for an emulator around m2mlat, tests/packaging/arm64_integration.sh; natively
# each of these peaks at about 11 MiB, and the window of the report took 19.5 GB.)
expect_bounded() {
  local want=$1 max=$2; shift 2
  read -r rc kib secs <<< "$(peak_run out.txt err.txt "$@")"
  [ "$rc" = "$want" ] || { cat err.txt >&2; fail "'$*' exited $rc, expected $want"; }
  [ "$kib" -lt "$max" ] || fail "'$*' peaked at $kib KiB (limit $max KiB)"
  awk -v s="$secs" 'BEGIN { exit !(s < 5) }' || fail "'$*' took $secs s"
  echo "bounded: '$*' exit $rc, peak $kib KiB, $secs s"
}
"$M2MLAT" export s.db -o events.csv
# A 10^9-second window (5*10^7 s took 19.5 GB, more ended in std::bad_alloc): refused at once,
# naming the flag. One day, the limit, pairs in little memory.
expect_bounded 2 262144 "$M2MLAT" stats events.csv --max-latency 1000000000s
grep -q -- "--max-latency 1000000000s: a latency is at most" err.txt || fail "window not refused: $(cat err.txt)"
expect_bounded 0 262144 "$M2MLAT" stats events.csv --max-latency 86400s --bootstrap 0
expect_bounded 2 262144 "$M2MLAT" stats events.csv --bootstrap 1000000000000
grep -q -- "--bootstrap" err.txt || fail "bootstrap bound not named: $(cat err.txt)"
expect_exit 2 "$M2MLAT" record --store batch.db --node a --source sim --batch 10000000
grep -q -- "--batch must be in 1..1000000" err.txt || fail "batch bound: $(cat err.txt)"
[ ! -e batch.db ] || fail "a refused record created its store"
# A device never ends: refused before reading. An endless pipe without newlines: refused at 64 KiB.
expect_bounded 66 262144 "$M2MLAT" stats /dev/zero
grep -q "/dev/zero: is not a regular file or a pipe" err.txt || fail "/dev/zero: $(cat err.txt)"
expect_bounded 65 262144 bash -c "head -c 1000000000 /dev/zero | '$M2MLAT' stats -"
grep -q "<stdin>:1: line is longer than 65536 bytes" err.txt || fail "endless line: $(cat err.txt)"

# Cut mid-write, a member given twice, a line too long: data errors naming file:line, and the store
# keeps what it had.
printf 'GPIO_16_IRQ:1700000000000000000\nGPIO_16_IRQ:1700000001000000000\nGPIO_16_IRQ:17000' > cut.log
expect_exit 65 "$M2MLAT" import --store s.db cut.log --node operator
grep -q "cut.log:3: the last line does not end with a newline" err.txt || fail "cut.log: $(cat err.txt)"
printf '%s\n' '{"format":"m2mlat-events/1","node":"a","channel":"w","time_ns":1}' \
  '{"format":"m2mlat-events/1","node":"a","channel":"w","time_ns":2,"node":"b"}' > dup.jsonl
expect_exit 65 "$M2MLAT" import --store s.db dup.jsonl
grep -q "dup.jsonl:2: member 'node' appears twice" err.txt || fail "dup.jsonl: $(cat err.txt)"
{ echo "node,channel,time_ns"; echo "a,w,1"; printf 'a,w,%070000d\n' 2; } > long.csv
expect_exit 65 "$M2MLAT" import --store s.db long.csv
grep -q "long.csv:3: line is longer than 65536 bytes" err.txt || fail "long.csv: $(cat err.txt)"
"$M2MLAT" export s.db -o after2.csv
cmp -s before.csv after2.csv || fail "the store changed"
# One board's file given as if it were a whole scenario: the error names the file, the missing side and
# what to do, instead of failing later on an empty channel name.
"$M2MLAT" simulate --manoeuvres 5 --out-dir one >/dev/null
expect_exit 65 "$M2MLAT" pair one/operator.csv one/vehicle.csv -o p.csv
grep -q "one/operator.csv: no effect events of vehicle, falling edges; it has operator/wheel (8 falling).*--cause-file and --effect-file" err.txt ||
  fail "one board's file: $(cat err.txt)"
echo "1 passed, 0 failed"
