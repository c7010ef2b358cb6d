#!/usr/bin/env bash
# Runs integration tests (tests/integration/<name>.sh) against the arm64 m2mlat under qemu-aarch64:
# ctest prefixes unit-test programs with the emulator, but the integration scripts start m2mlat
# themselves, so they get a small wrapper in its place that execs the emulator (qemu passes signals
# on to the program, so the scripts' kill/wait work unchanged). Prints one line per test with its
# time, then "N passed, N failed"; exits 1 if any failed.
#
#   tests/packaging/arm64_integration.sh ARM64_M2MLAT [NAME...]
# Default NAMEs: $M2MLAT_ARM64_INTEGRATION, else the subset docs/packaging.md explains (those that
# need no kernel GPIO, no chronyd, no browser, and run in reasonable time under emulation).
# M2MLAT_QEMU overrides the emulator command (default: qemu-aarch64).
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: $0 ARM64_M2MLAT [NAME...]" >&2; exit 2; }
BIN=$(realpath "$1")
shift
REPO=$(cd "$(dirname "$0")/../.." && pwd)
DEFAULT="demo exactness bad_input rig_formats separated_logs upstream_data report_upstream collect_pairs"
if [ $# -gt 0 ]; then NAMES=("$@"); else read -r -a NAMES <<<"${M2MLAT_ARM64_INTEGRATION:-$DEFAULT}"; fi
QEMU=${M2MLAT_QEMU:-qemu-aarch64}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

file -L "$BIN" | grep -q 'ARM aarch64' || { echo "$BIN is not an arm64 program" >&2; exit 2; }
printf '#!/bin/sh\nexec %s %q "$@"\n' "$QEMU" "$BIN" >"$WORK/m2mlat"
chmod +x "$WORK/m2mlat"
"$WORK/m2mlat" --version >/dev/null || { echo "the arm64 m2mlat does not run under $QEMU" >&2; exit 1; }

passed=0 failed=0
for name in "${NAMES[@]}"; do
  script=$REPO/tests/integration/$name.sh
  [ -f "$script" ] || { echo "SKIP $name (no $script)"; continue; }
  start=$SECONDS
  if bash "$script" "$WORK/m2mlat" "$REPO/tests/data" >"$WORK/$name.log" 2>&1; then
    echo "PASS $name ($((SECONDS - start)) s)"
    passed=$((passed + 1))
  else
    echo "FAIL $name ($((SECONDS - start)) s)"
    tail -n 30 "$WORK/$name.log" | sed 's/^/    /'
    failed=$((failed + 1))
  fi
done
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
