# Shared by the integration tests: each test is `bash <test>.sh M2MLAT DATA_DIR` and runs the real
# executable as separate processes in a temporary folder.
set -Eeuo pipefail
# A command that fails outside a condition ends the test: say which, or it ends without a word.
# (Only in the test's own shell: inside $(...) a failure is the caller's to judge.)
on_error() { [ "$BASH_SUBSHELL" -gt 0 ] || echo "FAIL: ${BASH_SOURCE[1]}:$2: \`$3\` exited $1" >&2; }
trap 'on_error $? $LINENO "$BASH_COMMAND"' ERR
M2MLAT=$(realpath "$1")
DATA=$(realpath "$2")
# The reference study's published results, beside the checkout (../shared/data, not part of this
# repository): a test that reads them fails without them rather than passing on nothing.
UPSTREAM=$(realpath -m "$(dirname "$(realpath "$0")")/../../../shared/data/upstream-results")
require_upstream() {
  [ -f "$UPSTREAM/$1" ] || { echo "FAIL: no reference data: $UPSTREAM/$1 (../shared/data beside the checkout)" >&2; exit 1; }
}
PY=/usr/bin/python3
WORK=$(mktemp -d)
# Background processes a test starts go into PIDS: at the end they get CLEANUP_SIGNAL (TERM unless
# the test sets another) and are waited for, then the work folder goes.
PIDS=()
CLEANUP_SIGNAL=TERM
cleanup() {
  local pid
  for pid in "${PIDS[@]}"; do kill -"$CLEANUP_SIGNAL" "$pid" 2>/dev/null || true; done
  for pid in "${PIDS[@]}"; do wait "$pid" 2>/dev/null || true; done
  rm -rf "$WORK"
}
trap cleanup EXIT
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }
# expect_exit CODE command...: runs the command, fails unless it exits with CODE; keeps its stderr in err.txt
expect_exit() {
  local want=$1; shift
  local got=0
  "$@" >out.txt 2>err.txt || got=$?  # in a list: the expected failure is not an error of the test
  [ "$got" = "$want" ] || { cat out.txt err.txt >&2; fail "'$*' exited $got, expected $want"; }
}
