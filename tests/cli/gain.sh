# fovref gain: P1's three cases (SPEC §5.6), one FOV, --json, and bad values (exit 2, the option
# named on one line).
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)

expect 0 "P1's table" -- "$FOVREF" gain
contains "perfect-hmd-oval   ellipse 160 x 135 deg" "oval case"
contains "93.81%  94% (P1 §4)" "oval figure next to P1's"
contains "70.28%  at least 70% (P1 §4)" "Vive figure next to P1's"
contains "94.57%  95% (the thesis's summary of P1)" "disc figure next to the thesis's"
contains "proportional to V (c/deg), not to V^2" "density note"
expect 0 "P1's table as JSON" -- "$FOVREF" gain --json
checks=$((checks + 1))
if ! "$PY" -c '
import json, sys
j = json.loads(sys.argv[1])
got = {c["name"]: round(c["gain_percent"], 1) for c in j["cases"]}
assert got == {"perfect-hmd-oval": 93.8, "htc-vive": 70.3, "perfect-hmd-disc": 94.6}, got
assert all(round(c["gain_percent"]) == c["quoted_percent"] for c in j["cases"])
assert "not to V^2" in j["note"]
' "$OUT"; then
  echo "FAIL: gain --json"; failures=$((failures + 1))
fi
expect 0 "one ellipse" -- "$FOVREF" gain --shape ellipse --fov-deg 160,135
contains "gain       93.81%" "one ellipse"
contains "not to V^2" "density note for one case"
expect 0 "one disc, shape from one value" -- "$FOVREF" gain --fov-deg 110 --max-cpd 15.3
contains "disc 110 deg diameter" "one disc"
contains "gain       70.28%" "one disc"
contains "full rate up to e = 14.7" "clamp radius"
expect 0 "one disc as JSON" -- "$FOVREF" gain --fov-deg 160 --json
checks=$((checks + 1))
if ! "$PY" -c '
import json, sys
j = json.loads(sys.argv[1])
assert j["shape"] == "disc" and abs(j["gain_percent"] - 94.5696) < 1e-3, j
assert j["display_cpd"] == 60 and j["full_rate_radius_deg"] == 5.79, j
' "$OUT"; then
  echo "FAIL: gain --fov-deg 160 --json"; failures=$((failures + 1))
fi
expect 0 "help" -- "$FOVREF" gain --help
contains "--fov-deg" "help"
contains "--max-cpd" "help"
contains "not to V^2" "density note in help"
expect 0 "top-level help lists gain" -- "$FOVREF" --help
contains "fovref gain" "top-level help"

# Bad values: exit 2, one line naming the option.
bad() {  # OPTION-TEXT DESCRIPTION -- command...
  local text=$1 what=$2; shift 2
  expect 2 "$what" "$@"
  contains "$text" "$what"
  checks=$((checks + 1))
  if [ "$(wc -l <<<"$OUT")" -ne 1 ]; then echo "FAIL: $what: not one line: $OUT"; failures=$((failures + 1)); fi
}
bad "--fov-deg" "FOV too wide" -- "$FOVREF" gain --fov-deg 400
bad "--fov-deg" "FOV zero" -- "$FOVREF" gain --fov-deg 160,0
bad "--fov-deg" "FOV nan" -- "$FOVREF" gain --fov-deg nan
bad "--fov-deg" "FOV not a number" -- "$FOVREF" gain --fov-deg abc
bad "--fov-deg" "three values" -- "$FOVREF" gain --fov-deg 1,2,3
bad "--shape disc takes one --fov-deg value" "disc with two values" -- "$FOVREF" gain --shape disc --fov-deg 100,90
bad "--shape ellipse takes --fov-deg W,H" "ellipse with one value" -- "$FOVREF" gain --shape ellipse --fov-deg 100
bad "--shape" "unknown shape" -- "$FOVREF" gain --shape square --fov-deg 100
bad "--max-cpd" "negative c/deg" -- "$FOVREF" gain --fov-deg 100 --max-cpd -1
bad "--max-cpd" "infinite c/deg" -- "$FOVREF" gain --fov-deg 100 --max-cpd inf
bad "--max-cpd needs --fov-deg" "c/deg alone" -- "$FOVREF" gain --max-cpd 20
bad "--angle-steps" "no angles" -- "$FOVREF" gain --angle-steps 0
finish
