# fovref probe explains one pixel and agrees with the rendered frame; fovref evaluate writes ring
# errors, and evaluating a mode equals evaluating that mode's rendered frames from a directory.
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)

expect 0 "probe basic" -- "$FOVREF" probe --scene cornell --mode basic --width 64 --height 36 --pixel 32,20 --frame 1 --time-step 0.5
contains "[primary_visibility]" "ray section"
contains "[shade_direct]" "shading section"
contains "radiance: bit-identical to the rendered buffer" "probe agrees with the frame"
contains "G-buffer pixel: bit-identical to the rendered buffers" "the pass's per-pixel function agrees with the G-buffer"
contains "shade_direct -> final" "buffer values"
expect 0 "probe raster primary on a textured scene" -- "$FOVREF" probe --scene checker-room --mode basic --param primary=raster --width 64 --height 36 --pixel 30,30
contains "texel 3" "texels and their lerps"
contains "bit-identical" "raster probe agrees"
# The rasterizer explained: the issue's grazing pixel, where it and the ray caster disagree.
expect 0 "probe a rasterized edge pixel" -- "$FOVREF" probe --scene checker-room --mode basic --param primary=raster --width 320 --height 180 --pixel 106,119
contains "fill rule         d3d" "fill rule"
contains "sample            pixel centre (27264/256 (106.5), 30592/256 (119.5))" "fixed-point sample"
contains "triangle 666      snapped corners" "candidate with snapped corners"
contains "E_bc 19 E_ca 12 E_ab 2975 -> covered" "edge values"
contains "passes: 3.57242799 < 3.87680817 of triangle 1" "depth test with both depths"
contains "fails: 3.59121752 > 3.57242799 of triangle 666" "losing candidate"
contains "winner            triangle 666" "winner"
contains "winner: the G-buffer's primitive id" "winner checked against the G-buffer"
contains "[ray caster (comparison)]" "ray caster labelled as a comparison"
contains "primitive 695" "the ray caster's other answer"
expect 0 "probe with the gl fill rule" -- "$FOVREF" probe --scene cornell --mode basic --param primary=raster --param fill_rule=gl --width 64 --height 36 --pixel 30,20
contains "fill rule         gl: a centre on an edge is covered by bottom and left edges" "gl fill rule"
expect 0 "probe ground truth" -- "$FOVREF" probe --scene cornell --mode ground-truth --width 32 --height 18 --pixel 16,9
contains "sample 15" "16 samples"
contains "mean: bit-identical" "ground truth agrees"
expect 0 "probe a mode without an explainer" -- "$FOVREF" probe --mode rng --width 8 --height 4 --pixel 3,2
contains "rng -> rng" "generic buffer listing"
expect 0 "probe --json" -- "$FOVREF" probe --scene cornell --mode basic --width 16 --height 9 --pixel 8,4 --json
contains '"consistent": true' "json"
expect 2 "pixel outside" -- "$FOVREF" probe --scene cornell --mode basic --width 16 --height 9 --pixel 16,4
contains "outside the 16x9 screen" "pixel outside"
expect 2 "malformed pixel" -- "$FOVREF" probe --scene cornell --mode basic --pixel 3
expect 2 "unknown mode" -- "$FOVREF" probe --scene cornell --mode nope --pixel 1,1
# Foveated modes: pass 2's taps, each tap's texel traced and shaded, the gaze buffer, a texel.
expect 0 "probe ckfov outside the gaze circle, with the Gaussian lerp" -- "$FOVREF" probe --scene checker-room --mode ckfov --width 160 --height 90 --pixel 130,20 --param filters=lerp
contains "forward map  (u, v) = (26.1863174, 144.785217)" "the forward map"
contains "tap 3      texel (26, 145) traced" "the four taps"
contains "resolved: bit-identical to the rendered buffer" "pass 2 agrees"
contains "[lp_trace] texel (25, 144)" "each tap's texel"
contains "texel: bit-identical to the rendered buffers" "the texel's G-buffer agrees"
contains "rand(frame 0, pixel 7945," "texel index j w + i seeds rand()"
contains "final: bit-identical to the rendered buffer" "the lerp agrees"
expect 0 "probe cfov inside the gaze circle" -- "$FOVREF" probe --scene cornell --mode cfov --width 160 --height 90 --pixel 80,45
contains "the gaze buffer's pixel" "gaze buffer source"
contains "[gaze_shade]" "gaze shading"
expect 0 "probe a texel" -- "$FOVREF" probe --scene cornell --mode cfov --width 160 --height 90 --texel 3,40 --gaze 70,50
contains "fovref probe: mode cfov, frame 0, texel (3, 40)" "texel header"
contains "gaze         (70, 50)" "--gaze"
contains "on screen: traced" "texel status"
expect 2 "texel outside the buffer" -- "$FOVREF" probe --scene cornell --mode cfov --width 160 --height 90 --texel 999,1
contains "outside the 49x149 log-polar buffer" "texel bounds"
expect 2 "texel of a mode without a buffer" -- "$FOVREF" probe --scene cornell --mode basic --width 16 --height 9 --texel 1,1
contains "has no foveation buffer" "texel needs a buffer"
expect 2 "pixel and texel" -- "$FOVREF" probe --scene cornell --mode cfov --width 16 --height 9 --texel 1,1 --pixel 1,1
expect 2 "an eye for a mono mode" -- "$FOVREF" probe --scene cornell --mode cfov --width 16 --height 9 --texel 1,1,0

expect 0 "evaluate two modes" -- "$FOVREF" evaluate --scene cornell --mode basic,splat --width 96 --height 54 --frames 4 --every 2 --time-step 0.5 --out "$TMP/ev"
for f in rings.csv frames.csv summary.json rings.svg heatmap_basic.png heatmap_splat.png; do
  check_file "$TMP/ev/$f" "evaluate output $f"
done
expect 0 "render the same frames" -- "$FOVREF" render --scene cornell --mode basic --width 96 --height 54 --frames 4 --time-step 0.5 --out "$TMP/frames" -q
expect 0 "evaluate rendered frames" -- "$FOVREF" evaluate --scene cornell --frames-dir "$TMP/frames" --width 96 --height 54 --frames 4 --every 2 --time-step 0.5 --out "$TMP/ev2" -q
"$PY" - "$TMP/ev/rings.csv" "$TMP/ev2/rings.csv" <<'PYTHON' || { echo "FAIL: rings.csv content"; failures=$((failures + 1)); }
import csv, sys
a = [r for r in csv.DictReader(open(sys.argv[1]))]
b = [r for r in csv.DictReader(open(sys.argv[2]))]
basic = [r for r in a if r["label"] == "basic"]
assert len(basic) == 20 and len([r for r in a if r["label"] == "splat"]) == 20
assert sum(int(r["pixels"]) for r in basic) == 96 * 54  # the rings cover the screen
# The same frames, rendered by the mode or read from files, give the same ring errors.
for x, y in zip(basic, b):
    assert {k: v for k, v in x.items() if k != "label"} == {k: v for k, v in y.items() if k != "label"}, (x, y)
# basic is closer to the ground truth than the centroid splat in every ring with pixels.
splat = [r for r in a if r["label"] == "splat"]
for x, y in zip(basic, splat):
    if x["mse"] and y["mse"]:
        assert float(x["mse"]) <= float(y["mse"]), (x, y)
PYTHON
checks=$((checks + 1))
expect 2 "evaluate without a mode" -- "$FOVREF" evaluate --scene cornell --out "$TMP/ev3"
expect 2 "evaluate a missing frames dir" -- "$FOVREF" evaluate --scene cornell --frames-dir "$TMP/none" --out "$TMP/ev3"
expect 2 "evaluate frames of another size" -- "$FOVREF" evaluate --scene cornell --frames-dir "$TMP/frames" --width 64 --height 36 --frames 1 --out "$TMP/ev3" -q
contains "reference" "size mismatch message"

# The metrics benchmark runs; with scikit-image installed its SSIM equals ours to 1e-6.
expect 0 "bench metrics" -- "$FOVREF" bench metrics --size 64x48 --repeats 1
contains "SSIM (luma given)" "bench rows"
if "$PY" -c "import skimage" 2>/dev/null; then
  contains "(target <= 1e-6: met)" "SSIM equals scikit-image's"
else
  echo "SKIPPED: scikit-image comparison (python3-skimage is not installed)"
fi
finish
