# render --out / --dump write what they say; bad input exits 2 and writes nothing.
source "$(dirname "$0")/lib.bash"
expect 0 "render splat" -- "$FOVREF" render --scene cornell --mode splat --width 32 --height 18 \
  --frames 2 --out "$TMP/out" --dump "$TMP/dump" --quiet
check_file "$TMP/out/manifest.json" "render --out"
check_file "$TMP/out/f000_final.pfm" "render --out"
check_file "$TMP/out/f001_final.png" "render --out"
for b in splat_depth splat_primitive splat_normal splat_albedo final; do
  check_file "$TMP/dump/f000_$b.pfm" "dump $b"
  check_file "$TMP/dump/f000_$b.png" "dump preview $b"
done
check_file "$TMP/dump/manifest.json" "dump manifest"
grep -q '"seconds"' "$TMP/dump/manifest.json" || { echo "FAIL: dump manifest lacks stage times"; failures=$((failures+1)); }

expect 0 "only some buffers" -- "$FOVREF" render --scene cornell --mode splat --width 8 --height 8 \
  --output splat_depth --out "$TMP/depth"
contains "headlight_shade (skipped)" "a stage nobody consumes is skipped"
check_file "$TMP/depth/f000_splat_depth.pfm" "--output"

expect 0 "mode without scene" -- "$FOVREF" render --mode halton --out "$TMP/halton" --quiet
check_file "$TMP/halton/f000_halton_offsets.exr" "halton"

# --scalar: the SIMD paths off (post-AA, the blur ramp), the same bits
for mode in kfr visual-polar-basic; do
  expect 0 "$mode" -- "$FOVREF" render --scene cornell --mode $mode --width 96 --height 54 --out "$TMP/simd-$mode" --quiet
  expect 0 "$mode --scalar" -- "$FOVREF" render --scene cornell --mode $mode --width 96 --height 54 --scalar --out "$TMP/scalar-$mode" --quiet
  checks=$((checks + 1))
  if ! cmp -s "$TMP/simd-$mode/f000_final.pfm" "$TMP/scalar-$mode/f000_final.pfm"; then
    echo "FAIL: $mode --scalar changed the final image"; failures=$((failures + 1))
  fi
done

expect 2 "unknown mode" -- "$FOVREF" render --scene cornell --mode nope --out "$TMP/bad1"
contains "unknown mode" "unknown mode"
expect 2 "unknown parameter" -- "$FOVREF" render --scene cornell --mode splat --param alpha=2 --out "$TMP/bad2"
contains "'alpha'" "unknown parameter"
expect 2 "unknown buffer" -- "$FOVREF" render --scene cornell --mode splat --output nope --out "$TMP/bad3"
expect 2 "absurd size" -- "$FOVREF" render --scene cornell --mode splat --width 1000000 --out "$TMP/bad4"
contains "--width" "absurd size"
expect 2 "needs a scene" -- "$FOVREF" render --mode splat --out "$TMP/bad5"
for d in bad1 bad2 bad3 bad4 bad5; do
  checks=$((checks + 1))
  if [ -e "$TMP/$d" ]; then echo "FAIL: $d was written after an error"; failures=$((failures + 1)); fi
done
finish
