# fovref stress --fast (issue 17): the fast part of the numerical stress suite passes, every row
# is finite and deterministic where it is checked, within its bound where one is stated, and the
# out-of-range parameters are refused; --case filters, an unknown group is an error.
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)

expect 0 "stress --fast" -- "$FOVREF" stress --fast --json "$TMP/stress.json" -q
contains "0 failed" "no case failed"
check_file "$TMP/stress.json" "JSON rows"
"$PY" - "$TMP/stress.json" <<'PYTHON' || { echo "FAIL: stress rows"; failures=$((failures + 1)); }
import json, sys
rows = json.load(open(sys.argv[1]))["rows"]
groups = {r["group"] for r in rows}
for g in ["camera rays", "tiny screens", "grazing rays", "bmfr blocks", "log-polar round trip",
          "parameter limits", "scene scale and position", "non-finite inputs", "injected NaN/Inf"]:
    assert g in groups, g
assert len(rows) > 60, len(rows)
for r in rows:
    assert r["pass"], r
    if "bound" in r:
        assert r["error"] <= r["bound"], r
    if r["expect_refused"]:
        assert r["refused"] and "outside" in r["note"] or "finite" in r["note"], r
    elif not r["refused"]:
        assert r["finite"] and r["deterministic"], r
assert sum(r["expect_refused"] for r in rows) >= 4
PYTHON
expect 0 "one group" -- "$FOVREF" stress --fast --case "camera rays" -q
contains "vfov 170 deg" "camera rays at 170 degrees"
contains "6 case(s), 0 failed" "only that group"
expect 2 "unknown group" -- "$FOVREF" stress --case nothing-like-this
contains "no case group matches" "says so"
finish
