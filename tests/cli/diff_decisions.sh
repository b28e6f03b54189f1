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
# ray_pixel: texel (16, 2)'s point (79.92, 30.99) lies 0.01 px from the edge between pixels
# (79, 30) and (79, 31). Counted in (79, 31) instead, it moves one count of ray_positions: the
# vulkan profile compares ray_positions exactly and attributes both changed pixels to the flip
cat > eps_pixel.json <<'JSON'
{"ray_pixel": {"margin": "pixel_edge(lp_screen_point)", "margin_epsilon": [0.02], "reason": "test"}}
JSON
# move_ray DIR X Y: the port counts texel (16, 2) in pixel (X, Y)
move_ray() {
  python3 "$SRC/tests/cli/fake_port.py" g "$1" 0
  rm "$1/f000_ray_pixel.exr"
  python3 - "$SRC/tests/cli" "$@" <<'PY'
import json, struct, sys
sys.path.insert(0, sys.argv[1]); from fake_port import read_pfm, write_pfm
out, x, y = sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
b = [b for b in json.load(open("g/manifest.json"))["frames"][0]["buffers"] if b["name"] == "ray_pixel"][0]
data = bytearray(open("g/f000_ray_pixel.f32", "rb").read())  # rows top first, 2 channels
k = 8 * (2 * b["width"] + 16)
old = struct.unpack_from("<2f", data, k)
assert old == (79.0, 30.0), old
struct.pack_into("<2f", data, k, x, y)
open(out + "/f000_ray_pixel.f32", "wb").write(data)
w, h, c, counts = read_pfm("g/f000_ray_positions.pfm")  # rows bottom first
counts[(h - 1 - 30) * w + 79] -= 1
counts[(h - 1 - y) * w + x] += 1
write_pfm(out + "/f000_ray_positions.pfm", w, h, c, counts)
PY
}
move_ray ray_near 79 31
expect 0 "a ray counted across the nearby pixel edge passes" -- "$FOVREF" diff g ray_near --profile vulkan --tolerance-file eps_pixel.json
contains "decision (margin pixel_edge(lp_screen_point)): 1 near-threshold flip(s)" "counted"
contains "2 failing pixel(s) attributed to near-threshold flips of ray_pixel" "both counts attributed"
expect 1 "beyond the profile's 4e-3 px the same flip fails" -- "$FOVREF" diff g ray_near --profile vulkan
contains "first failing stage: ray_positions, buffer 'ray_pixel'" "named"
# counted 9 pixels away instead: the flip is near (the oracle's margin decides that) but the
# count it moves to (70, 31) is not beside it, so ray_positions fails there
move_ray ray_far 70 31
expect 1 "a ray counted 9 pixels away fails" -- "$FOVREF" diff g ray_far --profile vulkan --tolerance-file eps_pixel.json
contains "first failing stage: ray_positions, buffer 'ray_positions'" "named"
contains "first failing pixel (70, 31)" "at the pixel no flip explains"
# Pass 2's decisions (resolve_tap, resolve_mip_level) against the oracle's margins: kfr's mip
# resolve. NEAR: the buffer pixel whose lambda lies closest to an integer; FAR: one whose lambda
# lies at least 0.3 from one
expect 0 "export kfr" -- "$FOVREF" golden export checker-room-kfr k -q --raw-copies
read -r NX NY NM NL FX FY FL W < <(python3 - "$SRC/tests/cli" <<'PY'
import sys; sys.path.insert(0, sys.argv[1]); from fake_port import read_pfm
w, h, _, margin = read_pfm("k/f000_resolve_mip_margin.pfm")
_, _, _, level = read_pfm("k/f000_resolve_mip_level.pfm")
at = lambda k: (k % w, h - 1 - k // w)  # PFM rows bottom to top
near = min((m, k) for k, m in enumerate(margin) if 0 < m < 1e29)[1]
far = next(k for k, m in enumerate(margin) if 0.3 < m < 1e29)
print(*at(near), margin[near], level[near], *at(far), level[far], w)
PY
)
cat > eps_level.json <<JSON
{"resolve_mip_level": {"margin": "resolve_mip_margin", "margin_epsilon": [$(python3 -c "print($NM * 1.5)")],
                       "reason": "test: 1.5 x the nearest margin"}}
JSON
python3 "$SRC/tests/cli/fake_port.py" k level_near 0 --wrong "resolve_mip_level:0:$NX:$NY:$((${NL%.*} + 1))"
expect 0 "a level flip within epsilon of an integer lambda passes" -- "$FOVREF" diff k level_near --profile vulkan --tolerance-file eps_level.json
contains "decision (margin resolve_mip_margin): 1 near-threshold flip(s)" "counted"
python3 "$SRC/tests/cli/fake_port.py" k level_far 0 --wrong "resolve_mip_level:0:$FX:$FY:$((${FL%.*} + 1))"
expect 1 "a level flip far from an integer lambda fails" -- "$FOVREF" diff k level_far --profile vulkan --tolerance-file eps_level.json
contains "first failing stage: resolve, buffer 'resolve_mip_level'" "named"
contains "interior mismatch ($FX, $FY)" "at its pixel"
# resolve_tap has two channels (an EXR, and its raw copy): the port's is the raw copy, changed
python3 "$SRC/tests/cli/fake_port.py" k tap_far 0
rm tap_far/f000_resolve_tap.exr
python3 - "$FX" "$FY" "$W" <<'PY'
import struct, sys
x, y, w = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3])
data = bytearray(open("k/f000_resolve_tap.f32", "rb").read())  # rows top first, 2 channels
struct.pack_into("<f", data, 4 * 2 * (y * w + x), struct.unpack_from("<f", data, 4 * 2 * (y * w + x))[0] + 1)
open("tap_far/f000_resolve_tap.f32", "wb").write(data)
PY
expect 1 "a tap flip far from its threshold fails" -- "$FOVREF" diff k tap_far --profile vulkan
contains "first failing stage: resolve, buffer 'resolve_tap'" "named"
# --require all leaves out the oracle's margins, which no port writes
rm k_port -rf; python3 "$SRC/tests/cli/fake_port.py" k k_port 0
rm k_port/*_margin.pfm
expect 0 "--require all without the margins" -- "$FOVREF" diff k k_port --profile vulkan --require all
rm k_port/f000_resolve_tap.*
expect 1 "--require all still requires the decisions" -- "$FOVREF" diff k k_port --profile vulkan --require all
contains "resolve_tap" "the missing one named"
# bad tolerance files: a margin without its epsilon
echo '{"lp_valid": {"margin": "screen_border(lp_screen_point)", "reason": "x"}}' > bad.json
expect 2 "margin without epsilon" -- "$FOVREF" diff g near --tolerance-file bad.json
contains "needs \"margin_epsilon\"" "named"
finish
