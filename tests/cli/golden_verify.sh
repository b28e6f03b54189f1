# Every committed golden recomputes bit-exactly with this build.
source "$(dirname "$0")/lib.bash"
expect 0 "golden verify" -- "$FOVREF" golden verify --dir "$SRC/golden"
contains "0 failed" "golden verify"
cat <<<"$OUT"
finish
