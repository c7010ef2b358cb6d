#!/usr/bin/env bash
# The performance benchmark: m2mlat against the Python + numpy/pandas baseline on the same input, and
# the micro-benchmarks, summed up in one table (docs/benchmarks.md explains the method).
#
#   bench/run.sh [BUILD_DIR] [--events N] [--bootstrap B] [--store-events M] [--markdown]
#
# BUILD_DIR (default: build) holds m2mlat, bench/m2mlat_bench, bench/m2mlat_lean_stats and
# bench/m2mlat_rate_bench (built with -DCMAKE_BUILD_TYPE=Release or RelWithDebInfo; `make bench`
# builds and runs this).
# --events N: events per side (default 10,000,000; 100000 is the CI smoke test, well under a
# minute). --bootstrap B: resamples of the runs with confidence intervals (default 200).
# --store-events M: also a store of M events (in sessions of 10^7) appended, reopened and read
# (m2mlat_store_read_bench; 10^8 takes about 10 minutes and 4 GB of disk: not run unless asked).
# --markdown prints the table as Markdown.
#
# Steps: simulate two kernel logs of ~N edges each (preset static_5g, three magnets 20 degrees apart,
# field sensors: misses, bounces, spurious edges); run `m2mlat stats --cause-file --effect-file
# --json --bootstrap B`, m2mlat_lean_stats and bench/baseline.py on them, each with B = 0 and B,
# through bench/measure.py (wall time, peak memory); run m2mlat_bench with the same N and B, and
# m2mlat_rate_bench (8 kHz samples a side through the store for an hour at 10^7 events,
# proportionally less for fewer, at least 10 s); print the table. Everything goes to a temporary
# directory under $TMPDIR (or /tmp), removed at the end.
set -euo pipefail

usage() {
  sed -n '5,12p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit 2
}

build=build
events=10000000
bootstrap=200
store_events=
markdown=
build_given=
while (($#)); do
  case "$1" in
    --events) [[ $# -ge 2 ]] || usage; events=$2; shift 2 ;;
    --events=*) events=${1#--events=}; shift ;;
    --bootstrap) [[ $# -ge 2 ]] || usage; bootstrap=$2; shift 2 ;;
    --bootstrap=*) bootstrap=${1#--bootstrap=}; shift ;;
    --store-events) [[ $# -ge 2 ]] || usage; store_events=$2; shift 2 ;;
    --store-events=*) store_events=${1#--store-events=}; shift ;;
    --markdown) markdown=--markdown; shift ;;
    -h|--help) usage ;;
    -*) echo "run.sh: unknown option $1" >&2; usage ;;
    *) [[ -z $build_given ]] || usage; build=$1; build_given=1; shift ;;
  esac
done
[[ $events =~ ^[0-9]+$ && $events -ge 1000 ]] || { echo "run.sh: --events must be a number >= 1000" >&2; exit 2; }
[[ $bootstrap =~ ^[0-9]+$ && $bootstrap -ge 1 ]] || { echo "run.sh: --bootstrap must be a number >= 1" >&2; exit 2; }
[[ -z $store_events || ($store_events =~ ^[0-9]+$ && $store_events -ge 1000) ]] ||
  { echo "run.sh: --store-events must be a number >= 1000" >&2; exit 2; }

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
python=/usr/bin/python3  # Debian's, with python3-numpy and python3-pandas
m2mlat=$build/m2mlat
bench=$build/bench/m2mlat_bench
lean=$build/bench/m2mlat_lean_stats
rate=$build/bench/m2mlat_rate_bench
store_read=$build/bench/m2mlat_store_read_bench
for exe in "$m2mlat" "$bench" "$lean" "$rate" ${store_events:+"$store_read"}; do
  [[ -x $exe ]] || { echo "run.sh: $exe not found: build first (make build, or cmake --build $build)" >&2; exit 1; }
done
"$python" -c 'import numpy, pandas' 2>/dev/null ||
  { echo "run.sh: $python lacks numpy or pandas (apt-get install python3-numpy python3-pandas)" >&2; exit 1; }

work=$(mktemp -d "${TMPDIR:-/tmp}/m2mlat-bench-XXXXXX")
trap 'rm -rf "$work"' EXIT
trap 'exit 130' INT TERM

say() { echo "run.sh: $*" >&2; }

# The simulated rig: what the field looked like, with several magnets per wheel.
simulate() {  # simulate OUT_DIR MANOEUVRES
  "$m2mlat" simulate --out-dir "$1" --format kernel-log --scenario static_5g --manoeuvres "$2" --seed 1 \
    --set magnets_deg=0,20,40 --set sensor.miss_probability=0.01 --set sensor.bounce_probability=0.03 \
    --set sensor.spurious_per_minute=0.2 >/dev/null
}

# Edges per manoeuvre from a short run, then the run that gives ~N edges per side.
simulate "$work/calibration" 2000
per_2000=$(wc -l <"$work/calibration/operator.log")
manoeuvres=$(((events * 2000 + per_2000 - 1) / per_2000))
rm -rf "$work/calibration"
say "simulating $manoeuvres manoeuvres (~$events edges per side)"
simulate "$work/input" "$manoeuvres"
rm -f "$work/input/truth.csv"  # not needed here, and as large as a log
cause=$work/input/operator.log
effect=$work/input/vehicle.log

measure() {  # measure NAME COMMAND...: NAME.out = the command's output, NAME.measure = time and memory
  local name=$1
  shift
  "$python" "$here/measure.py" "$work/$name.out" -- "$@" >"$work/$name.measure" ||
    { say "failed: $*"; exit 1; }
  say "$name: $(cat "$work/$name.measure")"
}

for b in 0 "$bootstrap"; do
  measure "cli-$b" "$m2mlat" stats --cause-file "$cause" --effect-file "$effect" --json --bootstrap "$b"
  measure "lean-$b" "$lean" "$cause" "$effect" "$b"
  measure "baseline-$b" "$python" "$here/baseline.py" "$cause" "$effect" "$b"
done
rm -rf "$work/input"  # the micro-benchmarks make their own input

# Short cases are enough for a smoke test.
min_time=()
((events >= 1000000)) || min_time=(--benchmark_min_time=0.1)
say "micro-benchmarks (m2mlat_bench --events $events --bootstrap $bootstrap)"
TMPDIR=$work "$bench" --events "$events" --bootstrap "$bootstrap" "${min_time[@]}" \
  --benchmark_out="$work/micro.json" --benchmark_out_format=json >"$work/micro.txt" 2>&1 ||
  { cat "$work/micro.txt" >&2; say "m2mlat_bench failed"; exit 1; }

# The high-rate stream: an hour of 8 kHz samples a side at 10^7 events, proportionally less below.
rate_seconds=$((events >= 10000000 ? 3600 : events * 3600 / 10000000))
((rate_seconds >= 10)) || rate_seconds=10
say "high-rate stream (m2mlat_rate_bench --seconds $rate_seconds)"
TMPDIR=$work "$rate" --seconds "$rate_seconds" --json "$work/rate.json" >"$work/rate.txt" 2>&1 ||
  { cat "$work/rate.txt" >&2; say "m2mlat_rate_bench failed"; exit 1; }

# A big store reopened and read as an analysis reads it (sessions of 10^7 events, as a long drive's).
if [[ -n $store_events ]]; then
  store_sessions=$(((store_events + 9999999) / 10000000))
  say "a store of $store_events events (m2mlat_store_read_bench --events $store_events --sessions $store_sessions)"
  TMPDIR=$work "$store_read" --events "$store_events" --sessions "$store_sessions" --json "$work/store.json" \
    >"$work/store.txt" 2>&1 || { cat "$work/store.txt" >&2; say "m2mlat_store_read_bench failed"; exit 1; }
fi

"$python" "$here/report.py" "$work" "$events" "$bootstrap" $markdown
