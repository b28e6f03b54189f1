# Shared helpers for the CLI tests: each test script gets the fovref binary and the source dir.
set -u
FOVREF=$1
SRC=$2
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
failures=0
checks=0

# expect CODE DESCRIPTION -- command...: runs the command, checks its exit code, keeps its output
# in $OUT (stdout + stderr).
expect() {
  local want=$1 what=$2; shift 3
  checks=$((checks + 1))
  OUT=$("$@" 2>&1); local got=$?
  if [ "$got" -ne "$want" ]; then
    echo "FAIL: $what: exit $got, expected $want: $*"; echo "$OUT" | head -20
    failures=$((failures + 1))
  fi
}

# contains TEXT DESCRIPTION: the last command's output contains TEXT.
contains() {
  checks=$((checks + 1))
  if ! grep -qF -- "$1" <<<"$OUT"; then
    echo "FAIL: $2: output lacks '$1'"; echo "$OUT" | head -20
    failures=$((failures + 1))
  fi
}

check_file() {
  checks=$((checks + 1))
  if [ ! -s "$1" ]; then echo "FAIL: $2: missing $1"; failures=$((failures + 1)); fi
}

finish() {
  echo "$((checks - failures)) passed, $failures failed"
  [ "$failures" -eq 0 ]
}
