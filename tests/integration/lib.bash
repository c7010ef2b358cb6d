# Shared by the integration tests: each test is `bash <test>.sh M2MLAT DATA_DIR` and runs the real
# executable as separate processes in a temporary folder.
set -Eeuo pipefail
# A command that fails outside a condition ends the test: say which, or it ends without a word.
# (Only in the test's own shell: inside $(...) a failure is the caller's to judge.)
on_error() { [ "$BASH_SUBSHELL" -gt 0 ] || echo "FAIL: ${BASH_SOURCE[1]}:$2: \`$3\` exited $1" >&2; }
trap 'on_error $? $LINENO "$BASH_COMMAND"' ERR
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
