# `m2mlat onsettest`: the JSON carries every detector, profile and speed class with the figures the
# text shows; the same seed gives the same figures; a bad detector name or motion count is a usage error.
source "$(dirname "$0")/lib.bash"
"$M2MLAT" onsettest --motions 8 --json > a.json
"$M2MLAT" onsettest --motions 8 --json > b.json
"$M2MLAT" onsettest --motions 8 > text.txt
$PY - <<'PY'
import json
a, b = json.load(open("a.json")), json.load(open("b.json"))
assert a["format"] == "m2mlat-onsettest/1", a["format"]
assert len(a["onset"]) == 12 and len(a["baseline"]) == 6
for x, y in zip(a["onset"], b["onset"]):
    assert x == y, (x, y)  # deterministic per seed (only the throughput is this machine's)
text = open("text.txt").read()
for row in a["onset"]:
    assert row["found"] <= row["motions"] == 8
    if row["detector"] == "flank":
        assert row["found"] == 8, row
        med = row["onset_error"]["median_ns"] / 1e6
        assert f"{med:+.3f}" in text, (med, text)
print("ok")
PY
expect_exit 2 "$M2MLAT" onsettest --detector magic
grep -q "no onset detector 'magic' (known: reference, flank)" err.txt || fail "$(cat err.txt)"
expect_exit 2 "$M2MLAT" onsettest --motions 0
"$M2MLAT" onsettest --motions 4 --detector flank --hand-shape raised-cosine --json > cos.json
$PY -c 'import json; j = json.load(open("cos.json")); assert j["hand_shape"] == "raised-cosine", j["hand_shape"]'
expect_exit 2 "$M2MLAT" onsettest --hand-shape trapezoid
grep -q "unknown hand shape 'trapezoid': minimum-jerk or raised-cosine" err.txt || fail "$(cat err.txt)"
