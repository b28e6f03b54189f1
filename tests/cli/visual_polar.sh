# The Visual-Polar and sparse modes from the command line: every mode renders and dumps its
# stages; a resumed visual-polar sequence gives the bits of the whole one; the probe explains a
# pixel (its resolve recomputed bit for bit) and a texel (clipped or traced, its BMFR block);
# `fovref diff` names the first Visual-Polar stage that differs; bad parameters give one clear
# error; `fovref bench visual-polar` runs.
source "$(dirname "$0")/lib.bash"
common=(--scene cornell --width 64 --height 48 --time-step 0.1 --quiet)

expect 0 "visual-polar, 3 frames, every buffer" -- "$FOVREF" render --mode visual-polar \
  --frames 3 "${common[@]}" --dump "$TMP/vp"
for b in vp_gbuffer_world_position vp_valid vp_radiance bmfr_illumination bmfr_fitted \
  bmfr_taa vp_color resolved blur_horizontal final; do
  check_file "$TMP/vp/f002_$b.pfm" "dump $b"
done
check_file "$TMP/vp/f002_bmfr_weights.exr" "dump bmfr_weights"
expect 0 "manifest counters" -- grep -q '"texels_clipped"' "$TMP/vp/manifest.json"
for mode in visual-polar-basic linear-falloff acuity; do
  expect 0 "$mode renders" -- "$FOVREF" render --mode "$mode" --frames 2 "${common[@]}" \
    --out "$TMP/$mode"
  check_file "$TMP/$mode/f001_final.pfm" "$mode final"
done
expect 0 "linear-falloff with BMFR" -- "$FOVREF" render --mode linear-falloff --frames 2 \
  --param denoise=bmfr "${common[@]}" --out "$TMP/lfb"
expect 0 "fovref modes lists visual-polar's parameters" -- "$FOVREF" modes
contains "blur_sigma_deg" "modes: visual-polar parameters"
contains "falloff_periphery_deg" "modes: linear-falloff parameters"

# resume: frame 2 alone from the dump of frames 0..1 has the bits of the sequence's frame 2
expect 0 "visual-polar frames 0..1" -- "$FOVREF" render --mode visual-polar --frames 2 \
  "${common[@]}" --dump "$TMP/first"
expect 0 "visual-polar frame 2 resumed" -- "$FOVREF" render --mode visual-polar --first-frame 2 \
  --frames 1 --resume "$TMP/first" "${common[@]}" --out "$TMP/resumed"
checks=$((checks + 1))
cmp -s "$TMP/vp/f002_final.pfm" "$TMP/resumed/f002_final.pfm" ||
  { echo "FAIL: resumed frame 2 differs"; failures=$((failures + 1)); }
expect 2 "visual-polar frame 2 without --resume" -- "$FOVREF" render --mode visual-polar \
  --first-frame 2 --frames 1 "${common[@]}" --out "$TMP/noresume"
contains "--resume" "the error names --resume"

# probe
expect 0 "probe a pixel" -- "$FOVREF" probe --mode visual-polar --scene cornell --width 64 \
  --height 48 --time-step 0.1 --frame 2 --pixel 50,10
contains "periphery: U = P^-1(r / s)" "probe: periphery"
contains "resolved: bit-identical to the rendered buffer" "probe: resolve recomputed"
contains "sigma" "probe: blur sigma"
expect 0 "probe a clipped texel" -- "$FOVREF" probe --mode visual-polar-basic --scene cornell \
  --width 64 --height 48 --texel 1,30
contains "clipped  yes" "probe: clipped texel"
expect 0 "probe a traced texel" -- "$FOVREF" probe --mode visual-polar --scene cornell --width 64 \
  --height 48 --texel 30,10
contains "[bmfr_fit] the BMFR block of this texel" "probe: the block"
contains "phi height H" "probe: staircase height"
expect 2 "probe a texel outside the buffer" -- "$FOVREF" probe --mode visual-polar --scene cornell \
  --width 64 --height 48 --texel 500,1
contains "outside the 43x32 Visual-Polar buffer" "probe: texel outside"

# diff orders the stages: a changed blur ramp fails first at blur_horizontal
expect 0 "visual-polar with a wider blur" -- "$FOVREF" render --mode visual-polar --frames 3 \
  --param blur_sigma_deg=0.8 "${common[@]}" --dump "$TMP/vp2"
expect 1 "diff of the two" -- "$FOVREF" diff "$TMP/vp" "$TMP/vp2"
contains "first failing stage: blur_horizontal" "diff: first failing VP stage"

# bad parameters
expect 2 "a buffer too small" -- "$FOVREF" render --mode visual-polar --param buffer_width=1 \
  "${common[@]}" --out "$TMP/bad"
contains "visual-polar" "bad buffer: message"
expect 2 "p_l below f_l" -- "$FOVREF" render --mode linear-falloff \
  --param falloff_fovea_deg=30 --param falloff_periphery_deg=20 "${common[@]}" --out "$TMP/bad"
contains "falloff_periphery_deg" "bad fall-off: message"
expect 2 "an unknown fill" -- "$FOVREF" render --mode acuity --param fill=grey "${common[@]}" \
  --out "$TMP/bad"
contains "fill" "bad fill: message"
FOVREF_MAX_IMAGE_PIXELS=1000 expect 2 "acuity samples above the limit" -- "$FOVREF" render \
  --mode acuity --param samples=5000 "${common[@]}" --out "$TMP/bad"
contains "FOVREF_MAX_IMAGE_PIXELS" "samples limit: message"
checks=$((checks + 1))
[ ! -e "$TMP/bad" ] || { echo "FAIL: a refused render wrote $TMP/bad"; failures=$((failures + 1)); }

# the benchmark runs (tiny sizes)
expect 0 "bench visual-polar" -- "$FOVREF" bench visual-polar --width 96 --height 96 \
  --repeats 1 --frames 2 --every 2 --spp 2 --error-size 64x36
contains "speed-up screen / VP" "bench: speed-up row"
contains "RMSE per ring" "bench: ring errors"
contains "LP      log-polar + BMFR" "bench: P5's log-polar method"
# ... with a moving gaze (a gaze track), and a missing track refused by name
printf 'frame,x,y\n0,20,30\n1,40,35\n2,60,40\n' > "$TMP/track.csv"
expect 0 "bench visual-polar, moving gaze, two rounds" -- "$FOVREF" bench visual-polar --width 96 --height 96 \
  --repeats 1 --rounds 2 --no-error --gaze-track "$TMP/track.csv"
contains "gaze moving along" "bench: the moving gaze named"
contains "fastest of 2 frames after an untimed first (2 rounds, the methods in turn)" "bench: the rounds counted"
contains "speed-up screen / VP" "bench: the speed-up row after the rounds"
contains "this size is not the target's" "bench: the target judged only at 1280x1440"
expect 2 "bench visual-polar, a missing gaze track" -- "$FOVREF" bench visual-polar --no-error \
  --gaze-track "$TMP/no-such-track.csv"
contains "no-such-track.csv" "bench: the missing track named"
# log-polar-pathtrace: probe --texel explains the BMFR block of a traced texel (recomputed, exit 0)
expect 0 "probe a log-polar-pathtrace texel" -- "$FOVREF" probe --scene cornell \
  --mode log-polar-pathtrace --width 64 --height 48 --frame 1 --texel 20,10
contains "[bmfr_fit] the BMFR block of this texel" "the block that denoised it"
finish
