# A gyroscope's raw trace in the store: an m2mlat-gyro/1 file imported as a session's trace comes
# back out of `export --what gyro` byte for byte (also after a merge into a campaign store, and
# merging again adds nothing); a truncated file or an ambiguous export is refused and changes
# nothing stored.
source "$(dirname "$0")/lib.bash"

# 10,000 samples 125 us apart (three blocks in the store), values using the whole 16-bit range.
"$PY" - <<'PY'
t0 = 1764086400000000000
with open("trace.csv", "w") as f:
    f.write("# format: m2mlat-gyro/1\n# clock: realtime\n# counts_per_deg_s: 131\n")
    f.write("# source: mpu6050 /dev/i2c-1 address 0x68, period 125000 ns, divider 0\n")
    f.write("time_ns,bound_ns,x,y,z\n")
    for i in range(10000):
        f.write(f"{t0 + i * 125000 + (i * 7919) % 997},{80000 + i % 50},{(i * 37) % 65536 - 32768},"
                f"{-(i % 300)},{32767 - i % 3}\n")
PY

"$M2MLAT" import trace.csv --store vehicle.db --node vehicle --channel wheel_gyro --json >import.json
"$PY" -c '
import json; s = json.load(open("import.json"))["files"][0]
assert s["format"] == "m2mlat-gyro/1" and s["sessions"][0]["samples"] == 10000, s'
"$M2MLAT" export vehicle.db --what gyro -o back.csv
cmp trace.csv back.csv || fail "the exported trace differs from the imported file"

# Merged into a campaign store with an operator's trace: both come back exactly, once.
sed 's/^# source: .*/# source: the operator station/' trace.csv >operator.csv
"$M2MLAT" import operator.csv --store operator.db --node operator >/dev/null
"$M2MLAT" merge campaign.db vehicle.db operator.db --json >merge1.json
"$M2MLAT" merge campaign.db vehicle.db operator.db --json >merge2.json
"$PY" - <<'PY'
import json
m1 = json.load(open("merge1.json"))["merged"]
m2 = json.load(open("merge2.json"))["merged"]
assert [x["rate_blocks"] for x in m1] == [3, 3], m1
assert [x["rate_blocks"] for x in m2] == [0, 0], m2
PY
"$M2MLAT" export campaign.db --what gyro --node vehicle -o merged_vehicle.csv
cmp trace.csv merged_vehicle.csv || fail "the vehicle's trace changed in the merge"
"$M2MLAT" export campaign.db --what gyro --node operator --channel gyro -o merged_operator.csv
cmp operator.csv merged_operator.csv || fail "the operator's trace changed in the merge"

# Two traces match: the export asks which, naming both.
expect_exit 2 "$M2MLAT" export campaign.db --what gyro -o any.csv
grep -q "node 'vehicle' channel 'wheel_gyro'" err.txt || fail "ambiguity message: $(cat err.txt)"
[ ! -e any.csv ] || fail "an ambiguous export wrote a file"
expect_exit 66 "$M2MLAT" export campaign.db --what gyro --node nobody -o none.csv

# A file cut mid-line: refused naming the file, the store unchanged.
head -c 5000 trace.csv >cut.csv
"$M2MLAT" export campaign.db --what gyro --node vehicle -o before.csv
expect_exit 65 "$M2MLAT" import cut.csv --store campaign.db --node late
grep -q "cut.csv" err.txt || fail "the truncated file is not named: $(cat err.txt)"
"$M2MLAT" export campaign.db --what gyro --node vehicle -o after.csv
cmp before.csv after.csv || fail "a refused import changed the store"
expect_exit 66 "$M2MLAT" export campaign.db --what gyro --node late -o late.csv

# record --gyro: a missing chip or a bad keep flag fails before the store is made.
expect_exit 66 "$M2MLAT" record --source sim --node vehicle --store rec.db --gyro "$WORK/i2c-none" --duration 1s
grep -q "i2c-none" err.txt || fail "the missing gyroscope is not named: $(cat err.txt)"
expect_exit 2 "$M2MLAT" record --source sim --node vehicle --store rec.db --gyro "$WORK/i2c-none" \
  --gyro-keep window:soon --duration 1s
grep -q -- "--gyro-keep" err.txt || fail "the bad keep flag is not named: $(cat err.txt)"
[ ! -e rec.db ] || fail "a failed record made a store"
echo "gyro_store: ok"
