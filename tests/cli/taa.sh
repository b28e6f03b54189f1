# TAA from the command line: sequences with every variant, frames A..B resumed from a dump with the
# bits of the whole sequence, the static-camera sequence, the probe's TAA section, evaluate's
# temporal error, and clear errors for what cannot work.
source "$(dirname "$0")/lib.bash"
common=(--scene checker-room --width 48 --height 27 --time-step 0.1 --quiet)
for v in depth clamp-screen; do
  expect 0 "basic taa=$v" -- "$FOVREF" render --mode basic --frames 3 --param taa=$v "${common[@]}" \
    --out "$TMP/basic-$v"
  check_file "$TMP/basic-$v/f002_final.pfm" "basic taa=$v"
done
expect 0 "cfov taa=clamp-buffer, every buffer" -- "$FOVREF" render --mode cfov --frames 5 \
  --param taa=clamp-buffer "${common[@]}" --dump "$TMP/seq"
for b in taa_view_depth final taa_age; do check_file "$TMP/seq/f004_$b.pfm" "dump $b"; done
check_file "$TMP/seq/f004_taa_bounds.exr" "dump taa_bounds (6 channels: EXR)"
expect 0 "kfr taa=depth" -- "$FOVREF" render --mode kfr --frames 2 --param taa=depth "${common[@]}" \
  --out "$TMP/kfr"

# Frames 3..4 resumed from the dump of frame 2: the same bits as in the sequence.
expect 0 "resume frames 3..4" -- "$FOVREF" render --mode cfov --frames 3..4 --param taa=clamp-buffer \
  "${common[@]}" --resume "$TMP/seq" --out "$TMP/resumed" --output all
for f in 3 4; do
  for b in final taa_age taa_view_depth; do
    checks=$((checks + 1))
    cmp -s "$TMP/seq/f00${f}_$b.pfm" "$TMP/resumed/f00${f}_$b.pfm" ||
      { echo "FAIL: resumed frame $f $b differs from the sequence's"; failures=$((failures + 1)); }
  done
done
expect 2 "frame 3 without --resume" -- "$FOVREF" render --mode cfov --first-frame 3 \
  --param taa=depth "${common[@]}" --out "$TMP/bad1"
contains "--resume" "the error names --resume"
checks=$((checks + 1)); [ ! -e "$TMP/bad1" ] || { echo "FAIL: a failed render left $TMP/bad1"; failures=$((failures + 1)); }
expect 2 "resume from another render" -- "$FOVREF" render --mode cfov --frames 3..3 --param taa=depth \
  "${common[@]}" --resume "$TMP/seq" --out "$TMP/bad2"
contains "other settings" "a mismatched dump is refused"
expect 2 "an empty range" -- "$FOVREF" render --mode basic --frames 4..2 "${common[@]}" --out "$TMP/bad3"
contains "4..2" "the range is named"
expect 2 "a range too long" -- "$FOVREF" render --mode basic --frames 0..2147483647 "${common[@]}" \
  --out "$TMP/bad3b"
contains "at most 100000 frames" "the limit is said"
expect 2 "resume without TAA" -- "$FOVREF" render --mode cfov --frames 3..3 "${common[@]}" \
  --resume "$TMP/seq" --out "$TMP/bad3c"
contains "carries no state" "nothing to resume"
expect 2 "static camera and a time step" -- "$FOVREF" render --mode basic --static-camera \
  --time-step 0.5 --scene checker-room --width 8 --height 8 --out "$TMP/bad3d"
contains "--static-camera and --time-step" "the conflict is named"
expect 2 "taa needs jittered rays" -- "$FOVREF" render --mode basic --param taa=depth \
  --param primary=raster "${common[@]}" --out "$TMP/bad4"
contains "primary=raster" "raster + taa"
expect 2 "a TAA tunable without TAA" -- "$FOVREF" render --mode cfov --param taa_tau=0.1 "${common[@]}" \
  --out "$TMP/bad5"
contains "taa_tau" "tunable named"
expect 2 "stereo TAA with the barrel distortion" -- "$FOVREF" render --mode stereo-lp --param taa=depth \
  --param barrel=on "${common[@]}" --out "$TMP/bad7"
contains "barrel=off" "the way out is said"
expect 0 "stereo TAA" -- "$FOVREF" render --mode stereo-lp --frames 2 --param taa=depth "${common[@]}" \
  --out "$TMP/stereo"
expect 0 "probe stereo TAA" -- "$FOVREF" probe --scene checker-room --mode stereo-lp --width 48 \
  --height 27 --time-step 0.1 --param taa=clamp-buffer --frame 2 --pixel 40,10
contains "eye 1, pixel (16, 10) of its half" "the eye's own TAA"
contains "bit-identical to the rendered buffers" "stereo probe check"
expect 2 "an unknown variant" -- "$FOVREF" render --mode cfov --param taa=ghost "${common[@]}" --out "$TMP/bad6"
contains "clamp-buffer" "the variants are listed"

# A gaze track moves the gaze during a TAA sequence: the composite gaze window follows it.
printf 'frame,x,y\n0,10,10\n1,30,15\n' > "$TMP/track.csv"
expect 0 "TAA with a gaze track" -- "$FOVREF" render --mode cfov --frames 2 --param taa=depth \
  --param gaze_track="$TMP/track.csv" "${common[@]}" --dump "$TMP/track"
checks=$((checks + 1))
x0=$(python3 -c "import json;m=json.load(open('$TMP/track/manifest.json'));print(' '.join(str(f['counters']['gaze_window_x0']) for f in m['frames']))")
[ "$(cut -d' ' -f1 <<<"$x0")" != "$(cut -d' ' -f2 <<<"$x0")" ] ||
  { echo "FAIL: the gaze did not move with the track ($x0)"; failures=$((failures + 1)); }

# The static-camera sequence: jittered (Halton point per frame), no reprojection after frame 0.
expect 0 "static camera" -- "$FOVREF" render --mode basic --frames 3 --param taa=depth --static-camera \
  --scene checker-room --width 48 --height 27 --out "$TMP/static"
contains "taa_jitter_index 2" "frame 2 uses Halton point 2"
contains "taa_reprojection_skipped 1296" "a stationary camera reprojects nothing"

# The probe explains TAA; evaluate reports the temporal error.
expect 0 "probe TAA" -- "$FOVREF" probe --scene checker-room --mode cfov --width 48 --height 27 \
  --time-step 0.1 --param taa=depth --frame 2 --pixel 30,10
contains "[taa]" "probe TAA section"
contains "reprojected" "probe reprojection"
contains "bit-identical to the rendered buffers" "probe check"
expect 0 "evaluate temporal" -- "$FOVREF" evaluate --scene checker-room --width 48 --height 27 \
  --frames 3 --mode basic,basic:taa=depth --out "$TMP/ev" --quiet
# The TAA row of frame 2 carries its counters (kept + rejected + clamped + periphery = pixels);
# the row without TAA leaves them empty.
checks=$((checks + 1))
row=$(grep '^basic:taa=depth,2,' "$TMP/ev/frames.csv" | cut -d, -f11-15)
IFS=, read -r kept rejected clamped periphery skipped <<<"$row"
[ -n "$kept" ] && [ $((kept + rejected + clamped + periphery)) -eq 1296 ] && [ "$kept" -gt 0 ] ||
  { echo "FAIL: frames.csv TAA counters of basic:taa=depth frame 2: '$row'"; failures=$((failures + 1)); }
checks=$((checks + 1))
[ -z "$(grep '^basic,2,' "$TMP/ev/frames.csv" | cut -d, -f11-15 | tr -d ,)" ] ||
  { echo "FAIL: frames.csv has TAA counters for basic without TAA"; failures=$((failures + 1)); }
expect 0 "evaluate prints the temporal error" -- "$FOVREF" evaluate --scene checker-room --width 48 \
  --height 27 --frames 3 --mode basic:taa=depth --out "$TMP/ev2"
contains "temporal error" "evaluate prints the temporal error"
contains "reference ground-truth" "and the reference's"
finish
