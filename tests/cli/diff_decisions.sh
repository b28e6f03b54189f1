# Threshold decisions in `fovref diff` (docs/diff.md, "Threshold decisions"): a flip of a
# decision buffer where the oracle lay within ε of its threshold is near-threshold (reported,
# not a failure) and explains the downstream pixels it changed; a flip far from it fails.
source "$(dirname "$0")/lib.bash"
cd "$TMP" || exit 1
expect 0 "export" -- "$FOVREF" golden export checker-room-cfov g -q --raw-copies
# Texel (16, 2): its screen point (79.92, 30.99) lies 0.077 px inside the right border; texel
# (20, 31): (-12.4, 51.3), 14 px off screen. An ε of 0.1 px makes the first near-threshold.
cat > eps.json <<'JSON'
{"lp_valid": {"margin": "screen_border(lp_screen_point)", "margin_epsilon": [0.1],
              "reason": "test: 0.1 px"}}
JSON
# near: the texel flips to untraced, its colour to black, and the screen pixel under it too
python3 "$SRC/tests/cli/fake_port.py" g near 0 --wrong lp_valid:0:16:2:0 --wrong lp_color:0:16:2:0 \
  --wrong final:0:79:30:0
expect 0 "a near-threshold flip passes" -- "$FOVREF" diff g near --profile vulkan --tolerance-file eps.json
contains "1 near-threshold flip(s)" "counted"
contains "1 failing pixel(s) attributed to near-threshold flips of lp_valid" "lp_color's pixel attributed"
expect 0 "json" -- "$FOVREF" diff g near --profile vulkan --tolerance-file eps.json --json near.json
checks=$((checks + 1))
python3 -c "
import json; r = json.load(open('near.json'))
v = [b for b in r['buffers'] if b['name'] == 'lp_valid'][0]
f = [b for b in r['buffers'] if b['name'] == 'final'][0]
assert v['near_threshold_flips'] == 1 and v['decision_margin'] == 'screen_border(lp_screen_point)', v
assert abs(v['near_threshold_max_margin'] - 0.0767) < 1e-3, v['near_threshold_max_margin']
assert f['attributed_pixels'] == 1 and f['attributed_to'] == ['lp_valid'], f
" || { echo "FAIL: the JSON report's decision fields"; failures=$((failures + 1)); }
# without the wider ε (the profile's 4e-3 px) the same flip is far: it fails
expect 1 "the same flip beyond the profile's epsilon" -- "$FOVREF" diff g near --profile vulkan
contains "first failing stage: lp_trace, buffer 'lp_valid'" "the decision buffer fails"
contains "the nearest 0.0767 from it" "with the oracle's margin"
# far: a texel 14 px off screen flips to traced
python3 "$SRC/tests/cli/fake_port.py" g far 0 --wrong lp_valid:0:20:31:1
expect 1 "a far flip fails" -- "$FOVREF" diff g far --profile vulkan --tolerance-file eps.json
contains "0 near-threshold flip(s)" "not near"
contains "interior mismatch (20, 31)" "and named"
# a pixel the flip cannot explain still fails: a wrong final pixel far from the texel
python3 "$SRC/tests/cli/fake_port.py" g other 0 --wrong lp_valid:0:16:2:0 --wrong final:0:10:10:0
expect 1 "an unexplained pixel fails" -- "$FOVREF" diff g other --profile vulkan --tolerance-file eps.json
contains "first failing pixel (10, 10)" "named"
# bad tolerance files: a margin without its epsilon
echo '{"lp_valid": {"margin": "screen_border(lp_screen_point)", "reason": "x"}}' > bad.json
expect 2 "margin without epsilon" -- "$FOVREF" diff g near --tolerance-file bad.json
contains "needs \"margin_epsilon\"" "named"
finish
