# `m2mlat gyro` and `doctor --gyro-device` on a machine without an I2C bus: every way of being
# pointed at no gyroscope gives a clear error with its exit code, and a trace file already there is
# left as it was. (Reading a chip is tested in the real kernel: tests/vm, gyro.*.)
source "$(dirname "$0")/lib.bash"

echo "an earlier trace" > keep.csv

# No such device: exit 66, naming it and how to get one; the earlier file is untouched.
expect_exit 66 "$M2MLAT" gyro --device "$WORK/i2c-none" --duration 1s --out keep.csv
grep -q "$WORK/i2c-none: no such I2C device (load i2c-dev" err.txt || fail "no-device message: $(cat err.txt)"
[ "$(cat keep.csv)" = "an earlier trace" ] || fail "the earlier trace file was changed"

# A file that is not an I2C device: the address cannot be selected (exit 74), and it is named.
touch not-a-bus
expect_exit 74 "$M2MLAT" gyro --device not-a-bus --address 0x69 --duration 1s --out new.csv
grep -q "not-a-bus: cannot select address 0x69" err.txt || fail "not-a-bus message: $(cat err.txt)"
[ ! -e new.csv ] || fail "a trace file was written without a chip"

# Bad flags are usage errors (exit 2) naming the flag.
expect_exit 2 "$M2MLAT" gyro --device not-a-bus --address 0x80 --out new.csv
grep -q -- "--address: '0x80' is not a 7-bit I2C address" err.txt || fail "address message: $(cat err.txt)"
expect_exit 2 "$M2MLAT" gyro --device not-a-bus --period 0ms --out new.csv
grep -q -- "--period" err.txt || fail "period message: $(cat err.txt)"

expect_exit 2 "$M2MLAT" gyro --device not-a-bus --json --out -
grep -q -- "--json and --out -" err.txt || fail "json/stdout message: $(cat err.txt)"

# An output target that cannot be written is refused before the bus is opened.
mkdir adir
expect_exit 74 "$M2MLAT" gyro --device "$WORK/i2c-none" --out adir
grep -q "adir" err.txt || fail "target message: $(cat err.txt)"

# doctor: the configured gyroscope is a finding to fix, with the device named.
expect_exit 1 "$M2MLAT" doctor --gyro-device "$WORK/i2c-none"
grep -q "FIX.*gyro.*$WORK/i2c-none: no such I2C device" out.txt || fail "doctor: $(cat out.txt)"
"$M2MLAT" doctor --json --gyro-device "$WORK/i2c-none" > doctor.json || true
$PY - doctor.json <<'PY'
import json, sys
findings = json.load(open(sys.argv[1]))["findings"]
gyro = [f for f in findings if f["check"] == "gyro"]
assert len(gyro) == 1 and gyro[0]["status"] == "FIX", gyro
assert "docs/hardware.md" in gyro[0]["fix"], gyro
PY
echo "PASS"
