# Shared by the integration tests: each test is `bash <test>.sh M2MLAT DATA_DIR` and runs the real
# executable as separate processes in a temporary folder.
set -euo pipefail
M2MLAT=$(realpath "$1")
DATA=$(realpath "$2")
PY=/usr/bin/python3
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }
# expect_exit CODE command...: runs the command, fails unless it exits with CODE; keeps its stderr in err.txt
expect_exit() {
  local want=$1; shift
  set +e; "$@" >out.txt 2>err.txt; local got=$?; set -e
  [ "$got" = "$want" ] || { cat out.txt err.txt >&2; fail "'$*' exited $got, expected $want"; }
}
