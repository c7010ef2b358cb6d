# Clock steps: a simulated run whose vehicle clock is stepped by +40 ms or -40 ms mid-run, written
# into each file format and into a store, analysed offline with default flags. No latency after the
# step may be off by the step without a flag: corrected pairs match the simulator's truth, flagged
# pairs carry the flag and stay out of the statistics, and stats/pair print the counts.
source "$(dirname "$0")/lib.bash"

SIM=(--manoeuvres 120 --set effect_clock.step_at=120s)

# check_pairs PAIRS_CSV CAUSE_EVENTS_FILE TRUTH_CSV MIN_CORRECTED [CAUSE_STEP_NS]: every pair that is
# neither ambiguous (flag 1) nor after a step of unknown offset (flag 512) has a true partner and its
# latency is within 5 ms of the true latency (the step is 40 ms); prints "corrected flagged". With
# CAUSE_STEP_NS the cause board was stepped: its times may be reported corrected by that much.
check_pairs() {
  "$PY" - "$@" <<'PYEOF'
import csv, json, sys
pairs_path, cause_path, truth_path, min_corrected = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
cause_step = int(sys.argv[5]) if len(sys.argv) > 5 else 0
def stamps(path):
    out = []
    for line in open(path):
        line = line.strip()
        if not line or line.startswith('#') or line.startswith('scenario,'):
            continue
        if line.startswith('{'):
            j = json.loads(line)
            if 'time_ns' in j: out.append(int(j['time_ns']))
        elif 'GPIO_' in line:
            out.append(int(line.rsplit(':', 1)[1]))
        else:
            out.append(int(line.split(',')[7]))  # m2mlat-events/2: time_ns is the 8th column
    return out
cause = stamps(cause_path)
truth = {cause[int(r['cause_index'])]: int(r['true_latency_ns']) for r in csv.DictReader(open(truth_path))}
rows = [r for r in csv.DictReader(l for l in open(pairs_path) if not l.startswith('#'))]
corrected = flagged = 0
for r in rows:
    flags = int(r['pair_flags'])
    if flags & 256: corrected += 1
    if flags & (1 | 512):
        flagged += flags & 512 != 0
        continue
    t = int(r['cause_time_ns'])
    if t not in truth and t + cause_step in truth:
        t += cause_step
    if t not in truth:
        # A step measured from a kernel log's stamps is known to ~0.1 ms: its corrected stamps lie that near.
        near = [k for k in truth if min(abs(k - t), abs(k - t - cause_step)) < 1_000_000]
        t = near[0] if near else t
    if t not in truth:
        sys.exit(f"unflagged pair with no true partner: cause {t}")
    err = int(r['latency_ns']) - truth[t]
    if abs(err) > 5_000_000:
        sys.exit(f"unflagged pair off by {err / 1e6:.3f} ms (cause {t}, flags {flags})")
if corrected < min_corrected:
    sys.exit(f"only {corrected} corrected pairs, expected at least {min_corrected}")
print(corrected, flagged)
PYEOF
}

for step in 40ms -40ms; do
  "$M2MLAT" simulate "${SIM[@]}" --set effect_clock.step=$step --store "s$step.db" --out-dir "csv$step" >/dev/null
  "$M2MLAT" simulate "${SIM[@]}" --set effect_clock.step=$step --out-dir "jsonl$step" --format events-jsonl >/dev/null
  "$M2MLAT" simulate "${SIM[@]}" --set effect_clock.step=$step --out-dir "klog$step" --format kernel-log >/dev/null
  for input in store csv jsonl klog; do
    case $input in
      store) args=("s$step.db"); cause="csv$step/operator.csv" ;;
      csv) args=(--cause-file "csv$step/operator.csv" --effect-file "csv$step/vehicle.csv"); cause=${args[1]} ;;
      jsonl) args=(--cause-file "jsonl$step/operator.jsonl" --effect-file "jsonl$step/vehicle.jsonl"); cause=${args[1]} ;;
      klog) args=(--cause-file "klog$step/operator.log" --effect-file "klog$step/vehicle.log"); cause=${args[1]} ;;
    esac
    "$M2MLAT" pair "${args[@]}" --out pairs.csv >/dev/null
    counts=$(check_pairs pairs.csv "$cause" "csv$step/truth.csv" 40) || fail "$input, step $step: $counts"
    read -r corrected flagged <<<"$counts"
    "$M2MLAT" stats "${args[@]}" >stats.txt
    # The step table names the stepped board and the counts the pairs file holds (a kernel log may
    # show a small level change of the clock after the step too: kernel_log_fine_steps.hpp).
    grep -Eq "^[^ ]+ +0 +[1-9][0-9]* +$corrected +$flagged\$" stats.txt ||
      { cat stats.txt >&2; fail "$input, step $step: stats does not count $corrected corrected, $flagged flagged"; }
    "$M2MLAT" stats --json "${args[@]}" >stats.json
    "$PY" -c 'import json,sys; s=json.load(open("stats.json"))["scenarios"][0]; c=s["clock_steps"]; sys.exit(0 if c["effect_steps"]>=1 and c["pairs_corrected"]==int(sys.argv[1]) else 1)' "$corrected" ||
      fail "$input, step $step: stats --json lacks the clock steps"
  done
done

# Steps of a few ms in a kernel log, whose lines are seconds apart, seen from its own two stamps and
# corrected (steps below ~10 ms once went unseen there, and every later latency was off by them).
for step in 5ms -8ms; do
  "$M2MLAT" simulate "${SIM[@]}" --set effect_clock.step=$step --out-dir "small$step" --format kernel-log >/dev/null
  "$M2MLAT" pair --cause-file "small$step/operator.log" --effect-file "small$step/vehicle.log" --out pairs.csv >/dev/null
  counts=$(check_pairs pairs.csv "small$step/operator.log" "small$step/truth.csv" 40) || fail "kernel log, step $step: $counts"
done

# The operator board stepped in a co-referenced rig: the vehicle's daemon follows its reference onto
# the new timescale, so the vehicle takes the step too (after its slew, flagged meanwhile).
for step in 40ms -40ms; do
  step_ns=$((${step%ms} * 1000000))
  "$M2MLAT" simulate "${SIM[@]}" --set sync=co_referenced --set cause_clock.step_at=97s \
    --set cause_clock.step=$step --store "op$step.db" --out-dir "op$step" >/dev/null
  for input in "op$step.db" "op$step/operator.csv op$step/vehicle.csv"; do
    # shellcheck disable=SC2086 # the files are two words on purpose
    if [ "${input%.db}" != "$input" ]; then "$M2MLAT" pair $input --out pairs.csv >/dev/null
    else set -- $input; "$M2MLAT" pair --cause-file "$1" --effect-file "$2" --out pairs.csv >/dev/null; fi
    counts=$(check_pairs pairs.csv "op$step/operator.csv" "op$step/truth.csv" 40 "$step_ns") ||
      fail "operator stepped $step ($input): $counts"
  done
  # The same rig's kernel logs carry no daemon offsets: the vehicle's log shows it slewing onto the
  # operator's step (its realtime - printk stamps move by the step over 80 s) and takes it over.
  "$M2MLAT" simulate "${SIM[@]}" --set sync=co_referenced --set cause_clock.step_at=97s \
    --set cause_clock.step=$step --format kernel-log --out-dir "opk$step" >/dev/null
  "$M2MLAT" pair --cause-file "opk$step/operator.log" --effect-file "opk$step/vehicle.log" --out pairs.csv >/dev/null
  counts=$(check_pairs pairs.csv "opk$step/operator.log" "opk$step/truth.csv" 20 "$step_ns") ||
    fail "operator stepped $step (kernel logs): $counts"
  # Imported one board at a time, in either order: the store keeps no printk stamps, so import reads
  # the follow while it holds them (the vehicle's log against the stored step, or read again).
  for order in "operator vehicle" "vehicle operator"; do
    rm -f follow.db
    for node in $order; do
      "$M2MLAT" import "opk$step/$node.log" --node "$node" --scenario k --store follow.db >out.txt
    done
    grep -q "vehicle: 1 clock step of another board taken over (seen in its kernel log)" out.txt ||
      { cat out.txt >&2; fail "import ($order), operator stepped $step: no follow said"; }
    "$M2MLAT" pair follow.db --out pairs.csv >/dev/null
    counts=$(check_pairs pairs.csv "opk$step/operator.log" "opk$step/truth.csv" 20 "$step_ns") ||
      fail "import ($order), operator stepped $step: $counts"
  done
done
# Each board's log imported into a store of its own: the boards meet when the stores are merged. A
# second merge adds nothing (the step is taken over once).
rm -f follow.db op.db veh.db
"$M2MLAT" import opk40ms/operator.log --node operator --scenario k --store op.db >/dev/null
"$M2MLAT" import opk40ms/vehicle.log --node vehicle --scenario k --store veh.db >/dev/null
"$M2MLAT" merge follow.db op.db veh.db >out.txt
grep -q "vehicle: 1 clock step of another board taken over (seen in its kernel log)" out.txt ||
  { cat out.txt >&2; fail "merge: no follow said"; }
"$M2MLAT" merge follow.db op.db veh.db >out.txt
! grep -q "taken over" out.txt || { cat out.txt >&2; fail "merge again: the step taken over twice"; }
"$M2MLAT" pair follow.db --out pairs.csv >/dev/null
counts=$(check_pairs pairs.csv opk40ms/operator.log opk40ms/truth.csv 20 40000000) || fail "merged stores: $counts"

# The vehicle's log gone before the operator's is imported: its stamps after the step are left out.
rm -f follow.db && cp opk40ms/vehicle.log gone.log
"$M2MLAT" import gone.log --node vehicle --scenario k --store follow.db >/dev/null
rm gone.log
"$M2MLAT" import opk40ms/operator.log --node operator --scenario k --store follow.db >/dev/null 2>err.txt
grep -q "gone.log: cannot be read again" err.txt || { cat err.txt >&2; fail "import: no note for a log gone"; }
"$M2MLAT" pair follow.db --out pairs.csv >/dev/null
counts=$(check_pairs pairs.csv opk40ms/operator.log opk40ms/truth.csv 0 40000000) || fail "import, log gone: $counts"
[ "${counts#* }" -ge 20 ] || fail "import, log gone: only ${counts#* } pairs left out"

# Imported into a store: a kernel log's steps and an events file's clock records go with the
# sessions, and the first event after each step is flagged.
"$M2MLAT" import klog-40ms/operator.log --node operator --scenario k --store imported.db >/dev/null
"$M2MLAT" import klog-40ms/vehicle.log --node vehicle --scenario k --store imported.db >/dev/null
"$M2MLAT" pair imported.db --out pairs.csv >/dev/null
check_pairs pairs.csv klog-40ms/operator.log csv-40ms/truth.csv 40 >/dev/null || fail "imported kernel logs"
"$PY" -c 'import sqlite3,sys; c=sqlite3.connect(sys.argv[1]); q=lambda s: c.execute(s).fetchone()[0]
sys.exit(0 if q("select count(*) from events where flags & 8") == q("select count(*) from clock_samples where source = \"step\"") >= 1 else 1)' imported.db ||
  fail "imported kernel log: the first event after the step is not flagged"

# chronyd's log brings the step into a store whose events file has no step record.
grep -v '"source":"step"' csv40ms/vehicle.csv >vehicle.csv
"$PY" - csv40ms/vehicle.csv >chrony.log <<'PYEOF'
import datetime, json, sys
for line in open(sys.argv[1]):
    if line.startswith('# clock:') and '"source":"step"' in line:
        t = json.loads(line[len('# clock:'):])['time_ns'] + 1_000_000  # logged 1 ms after the step
        s = datetime.datetime.fromtimestamp(t // 10**9, datetime.timezone.utc).strftime('%Y-%m-%dT%H:%M:%S')
        print(f'{s}.{t % 10**9 // 1000:06d}+00:00 vehicle chronyd[754]: System clock was stepped by 0.040000 seconds')
PYEOF
"$M2MLAT" import csv40ms/operator.csv vehicle.csv --scenario c --store chrony.db >/dev/null
"$M2MLAT" import --clock-log chrony.log --node vehicle --scenario c --store chrony.db >out.txt
grep -q "1 clock steps of vehicle" out.txt || { cat out.txt >&2; fail "import --clock-log"; }
"$M2MLAT" pair chrony.db --out pairs.csv >/dev/null
check_pairs pairs.csv csv40ms/operator.csv csv40ms/truth.csv 40 >/dev/null || fail "chrony log"

# A store exported to an events file with --with-meta carries its clock records: the file alone gives
# the same pairs (but for the scenario, session and label columns: a file has no sessions).
"$M2MLAT" export s40ms.db --with-meta -o exported.csv
grep -q '^# clock: .*"source":"step"' exported.csv || fail "export lost the step record"
"$M2MLAT" pair s40ms.db --out store_pairs.csv >/dev/null
"$M2MLAT" pair exported.csv --out file_pairs.csv >/dev/null
cmp -s <(cut -d, -f4- store_pairs.csv) <(cut -d, -f4- file_pairs.csv) ||
  fail "the exported file pairs differently from its store"

# A step of unknown size (its record says only that the clock was set) and no clock sample after
# it that says the clock is good: every later pair is flagged and left out of the statistics.
"$M2MLAT" simulate "${SIM[@]}" --set effect_clock.step=40ms --set clock_sample_interval=0s --out-dir unknown >/dev/null
sed -i 's/"size_known":true/"size_known":false/' unknown/vehicle.csv
grep -q '"size_known":false' unknown/vehicle.csv || fail "no step record to change"
"$M2MLAT" pair --cause-file unknown/operator.csv --effect-file unknown/vehicle.csv --out pairs.csv >/dev/null
read -r corrected flagged <<<"$(check_pairs pairs.csv unknown/operator.csv unknown/truth.csv 0)"
[ "$corrected" = 0 ] && [ "$flagged" -ge 40 ] || fail "unknown step: $corrected corrected, $flagged flagged"
"$M2MLAT" stats --json --cause-file unknown/operator.csv --effect-file unknown/vehicle.csv >stats.json
# The statistics hold exactly the pairs with no pairing flag (1, 2, 4, 8) and not after the step (512).
"$PY" -c 'import csv,json,sys
s = json.load(open("stats.json"))["scenarios"][0]
rows = csv.DictReader(l for l in open("pairs.csv") if not l.startswith("#"))
clear = sum(1 for r in rows if int(r["pair_flags"]) & (15 | 512) == 0)
sys.exit(0 if s["latency"]["n"] == clear and s["clock_steps"]["pairs_after_step"] >= 40 else 1)' ||
  fail "unknown step: the flagged pairs are not left out of the statistics"

# An events file without clock records (as older versions wrote) still reads.
grep -v '^# clock:' csv40ms/vehicle.csv >old.csv
"$M2MLAT" stats --cause-file csv40ms/operator.csv --effect-file old.csv >/dev/null
echo "PASS"
