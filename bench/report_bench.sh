#!/usr/bin/env bash
# How long `m2mlat report` takes, and how large its HTML gets, on two scenarios of N pairs each
# (default 1,000,000): wall time, peak memory, sizes of report.html and the pgfplots folder.
#
#   bench/report_bench.sh [BUILD_DIR] [--pairs N] [--bootstrap B]
#
# BUILD_DIR (default: build) holds an optimised m2mlat (RelWithDebInfo or Release). The inputs are
# two m2mlat-events/1 CSV files written by numpy (lognormal latencies around 850 ms, the second
# scenario 40 ms slower), in a temporary folder removed at the end.
#
# Measured (development VM, 2 cores shared with other work, GCC 12 -O2, N = 1,000,000 per scenario):
#   B = 200:  3.7 s CPU (8.7-11 s wall on the loaded VM), 513 MiB peak, report.html 497 KiB, pgfplots/ 204 KiB
#   B = 2000: 24 s CPU (50 s wall), same memory and sizes; `m2mlat stats` alone with B = 200: 1.4 s CPU
# (docs/report.md, Speed).
set -euo pipefail
build=build
pairs=1000000
bootstrap=200
while (($#)); do
  case "$1" in
    --pairs) pairs=$2; shift 2 ;;
    --bootstrap) bootstrap=$2; shift 2 ;;
    -*) sed -n '5p' "$0" >&2; exit 2 ;;
    *) build=$1; shift ;;
  esac
done
m2mlat=$(realpath "$build/m2mlat")
work=$(mktemp -d "${TMPDIR:-/tmp}/m2mlat-report-bench.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
/usr/bin/python3 - "$pairs" <<'PY'
import sys
import numpy as np
n = int(sys.argv[1])
rng = np.random.default_rng(1)
t = 1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * 4_000_000_000 + rng.integers(0, 1_000_000_000, n)
lat = (rng.lognormal(np.log(850), 0.12, n) * 1e6).astype(np.int64)
nodes = np.array(["operator", "vehicle"])
for name, shift in (("scenario_a", 0), ("scenario_b", 40_000_000)):
    side = np.concatenate([np.zeros(n, dtype=np.int64), np.ones(n, dtype=np.int64)])
    time = np.concatenate([t, t + lat + shift])
    order = np.argsort(time, kind="stable")
    with open(f"{name}.csv", "w") as f:
        f.write("node,channel,time_ns\n")
        f.writelines(f"{nodes[k]},wheel,{x}\n" for k, x in zip(side[order], time[order]))
PY
/usr/bin/time -f "%e %M" -o time.txt "$m2mlat" report scenario_a.csv scenario_b.csv --no-groups \
  --bootstrap "$bootstrap" --out out > /dev/null
read -r seconds kib < time.txt
printf 'pairs per scenario  %s\nbootstrap           %s\nwall time           %s s\npeak memory         %s MiB\n' \
  "$pairs" "$bootstrap" "$seconds" "$((kib / 1024))"
printf 'report.html         %s KiB\npgfplots/           %s KiB\n' "$(( $(stat -c %s out/report.html) / 1024 ))" \
  "$(du -sk out/pgfplots | cut -f1)"
