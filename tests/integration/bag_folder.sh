# `m2mlat bag` on a rosbag2 bag as ros2 bag record leaves it, a folder: rosbag2's own test bag of five
# MCAP files (../shared/data/real/mcap, beside the checkout; the test fails without it) gives every
# topic the message count rosbag2 wrote in its metadata.yaml; a sqlite3 bag (.db3) is refused with
# what to do, and a folder without MCAP files names what a bag holds.
source "$(dirname "$0")/lib.bash"
REAL=$(realpath -m "$(dirname "$(realpath "$0")")/../../../shared/data/real/mcap")
PREFIX=rosbag2_py_test_resources_mcap_wbag
[ -f "$REAL/${PREFIX}_metadata.yaml" ] || fail "no reference data: $REAL (../shared/data beside the checkout)"
mkdir wbag
ln -s "$REAL/${PREFIX}_metadata.yaml" wbag/metadata.yaml
for k in 0 1 2 3 4; do ln -s "$REAL/${PREFIX}_wbag_$k.mcap" "wbag/wbag_$k.mcap"; done
# rosbag2's counts per topic, read from its metadata.yaml.
$PY - wbag/metadata.yaml >expected.txt <<'PY'
import re, sys
text = open(sys.argv[1]).read()
for count, name in re.findall(r"- message_count: (\d+)\n\s+topic_metadata:\n\s+name: (\S+)", text):
    print(name, count)
PY
[ "$(wc -l <expected.txt)" -ge 2 ] || fail "metadata.yaml: no topics read"
topics=()
while read -r name count; do topics+=(--topic "$name"); done <expected.txt
"$M2MLAT" bag wbag/ "${topics[@]}" -o markers.csv 2>counts.txt
while read -r name count; do
  grep -q "^m2mlat: wbag/: $name (std_msgs/msg/String): $count messages$" counts.txt ||
    fail "topic $name: rosbag2 says $count: $(cat counts.txt)"
done <expected.txt
total=$(awk '{ s += $2 } END { print s }' expected.txt)
[ "$(grep -vc '^#\|^node,' markers.csv)" = "$total" ] || fail "markers.csv: not $total rows"
grep -q "^wbag,FFF," markers.csv || fail "node: not the folder's name: $(sed -n 3p markers.csv)"
# A sqlite3 bag; a folder of something else.
mkdir sqlbag other
touch sqlbag/sqlbag_0.db3 other/notes.txt
expect_exit 65 "$M2MLAT" bag sqlbag --topic /x
grep -q "sqlite3 storage (.db3).*ros2 bag convert" err.txt || fail "db3: $(cat err.txt)"
expect_exit 66 "$M2MLAT" bag other --topic /x
grep -q "other: a folder without .mcap files" err.txt || fail "empty folder: $(cat err.txt)"
echo "bag_folder: ok"
