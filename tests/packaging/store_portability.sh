#!/usr/bin/env bash
# A store written on one architecture reads identically on the other: the amd64 m2mlat writes a store
# (the simulated rig, fixed seed), the arm64 one reads and exports it under qemu-aarch64, and the
# exports (events, pairs) and the statistics must equal the amd64 ones byte for byte; and the other
# way round. SQLite's file format is endian-neutral and the schema holds only integers and text (no
# blobs, no floating point: timestamps are int64 ns), so any difference is a bug in m2mlat. The
# simulator itself is meant to be portable (core/portable_math), so both architectures' runs with one
# seed must give the same events too.
#
#   tests/packaging/store_portability.sh AMD64_M2MLAT ARM64_M2MLAT
# M2MLAT_QEMU overrides the emulator command (default: qemu-aarch64).
set -euo pipefail
[ $# -eq 2 ] || { echo "usage: $0 AMD64_M2MLAT ARM64_M2MLAT" >&2; exit 2; }
AMD=$(realpath "$1")
ARM=$(realpath "$2")
read -r -a QEMU <<<"${M2MLAT_QEMU:-qemu-aarch64}"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
amd() { "$AMD" "$@"; }
arm() { "${QEMU[@]}" "$ARM" "$@"; }

# Every reading of a store: events and pairs (CSV and JSON Lines), and the statistics as JSON.
read_all() {  # read_all amd|arm STORE PREFIX
  local run=$1 store=$2 p=$3
  $run export "$store" --format events-csv -o "$p.events.csv"
  $run export "$store" --format events-jsonl -o "$p.events.jsonl"
  for scenario in $SCENARIOS; do  # pairs are exported one scenario at a time
    $run export "$store" --what pairs --scenario "$scenario" --format pairs-csv -o "$p.pairs-$scenario.csv"
  done
  cat "$p".pairs-*.csv >"$p.pairs.csv"
  $run stats "$store" --json --seed 1 >"$p.stats.json"
}
rows() { grep -cvE '^#|^(node|cause_node),' "$1"; }  # a CSV export's rows: no format line, no header
same() {  # same A B WHAT
  cmp -s "$1" "$2" || { diff -u "$1" "$2" | head -n 20 >&2; fail "$3: $1 and $2 differ"; }
}

SCENARIOS="static_wifi dynamic_autonomous"
for scenario in $SCENARIOS; do
  amd simulate --scenario "$scenario" --seed 11 --store amd.db >/dev/null
  arm simulate --scenario "$scenario" --seed 11 --store arm.db >/dev/null
done
for store in amd arm; do
  read_all amd "$store.db" "$store-by-amd"
  read_all arm "$store.db" "$store-by-arm"
done
[ "$(rows amd-by-amd.events.csv)" -gt 100 ] || fail "the simulated store has too few events"
for f in events.csv events.jsonl pairs.csv stats.json; do
  same "amd-by-amd.$f" "amd-by-arm.$f" "the amd64 store read on arm64 ($f)"
  same "arm-by-arm.$f" "arm-by-amd.$f" "the arm64 store read on amd64 ($f)"
  same "amd-by-amd.$f" "arm-by-arm.$f" "the simulator on amd64 and arm64 with one seed ($f)"
done
echo "store_portability: $(rows amd-by-amd.events.csv) events, $(rows amd-by-amd.pairs.csv) pairs: identical on amd64 and arm64 in both directions"
