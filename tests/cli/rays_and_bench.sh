# rays make/trace and the benchmark's smoke run (figures are not checked: benchmarks are not tests).
source "$(dirname "$0")/lib.bash"
expect 0 "make camera rays" -- "$FOVREF" rays make cornell "$TMP/r.bin" --camera --width 16 --height 9
check_file "$TMP/r.bin" "camera rays"
[ "$(stat -c %s "$TMP/r.bin")" = $((16 * 9 * 32)) ] || { echo "FAIL: ray file size"; failures=$((failures+1)); }
expect 0 "trace" -- "$FOVREF" rays trace cornell "$TMP/r.bin" "$TMP/h.bin"
[ "$(stat -c %s "$TMP/h.bin")" = $((16 * 9 * 16)) ] || { echo "FAIL: hit file size"; failures=$((failures+1)); }
expect 0 "make random rays" -- "$FOVREF" rays make sphere-grid "$TMP/q.bin" --random 500 --seed 9
expect 0 "any-hit" -- "$FOVREF" rays trace sphere-grid "$TMP/q.bin" "$TMP/o.bin" --any-hit
[ "$(stat -c %s "$TMP/o.bin")" = $((500 * 4)) ] || { echo "FAIL: occlusion file size"; failures=$((failures+1)); }
: > "$TMP/empty.bin"
expect 0 "empty ray file" -- "$FOVREF" rays trace cornell "$TMP/empty.bin" "$TMP/eh.bin"
head -c 100 "$TMP/r.bin" > "$TMP/cut.bin"
expect 2 "truncated ray file" -- "$FOVREF" rays trace cornell "$TMP/cut.bin" "$TMP/ch.bin"
contains "truncated" "truncated ray file"
expect 2 "missing ray file" -- "$FOVREF" rays trace cornell "$TMP/none.bin" "$TMP/nh.bin"
# A ray with NaN in it (the first float of the file: origin x of ray 0) is rejected by index.
cp "$TMP/r.bin" "$TMP/nan.bin"
printf '\x00\x00\xc0\x7f' | dd of="$TMP/nan.bin" bs=1 seek=0 conv=notrunc status=none
expect 2 "NaN ray" -- "$FOVREF" rays trace cornell "$TMP/nan.bin" "$TMP/nanh.bin"
contains "ray 0: origin x" "NaN ray"
for f in ch.bin nh.bin nanh.bin; do
  checks=$((checks + 1))
  if [ -e "$TMP/$f" ]; then echo "FAIL: $f written after an error"; failures=$((failures + 1)); fi
done
expect 2 "make needs a kind" -- "$FOVREF" rays make cornell "$TMP/x.bin"
expect 0 "bench smoke run" -- "$FOVREF" bench rays --scene cornell --width 32 --height 18 --repeats 1
contains "| cornell      | primary" "bench table"
contains "raster gbuf" "bench table"
expect 2 "bench unknown scene" -- "$FOVREF" bench rays --scene nope
expect 0 "bench --explain" -- "$FOVREF" bench rays --scene cornell --width 32 --height 18 --repeats 1 --explain 2
if grep -q "comparison: Embree" <<<"$OUT"; then
  contains "hit/miss disagreements with Embree: none" "cornell agrees with Embree on every ray"
else
  contains "--explain: no disagreements to list (Embree not found" "explain without Embree"
fi
expect 2 "bench --explain out of range" -- "$FOVREF" bench rays --scene cornell --explain -1
expect 0 "basic via raster" -- "$FOVREF" render --scene cornell --mode basic --primary raster --width 16 --height 9 --out "$TMP/br" -q
expect 2 "bad --primary" -- "$FOVREF" render --scene cornell --mode basic --primary gpu --out "$TMP/bp"
# tile frustum culling: every row (screen tiles and cfov buffer tiles) lost 0
expect 0 "bench frustum" -- "$FOVREF" bench frustum --scene cornell sphere-grid --width 64 --height 36 --tile-size 16 32 -q
checks=$((checks + 1))
rows=$(grep -cE '^  (cornell|sphere-grid) ' <<<"$OUT")
bad=$(grep -E '^  (cornell|sphere-grid) ' <<<"$OUT" | awk '$NF != 0' | wc -l)
[ "$rows" -eq 18 ] && [ "$bad" -eq 0 ] || { echo "FAIL: bench frustum rows $rows, lost-hit rows $bad"; failures=$((failures + 1)); }
expect 2 "bench frustum bad tile size" -- "$FOVREF" bench frustum --tile-size 0
# the probe explains a pixel's tile: its frustum, its culled tree, the path to its hit's leaf
expect 0 "probe with frustum culling" -- "$FOVREF" probe --scene cornell --mode basic --width 64 --height 36 --pixel 30,20 --param frustum=lund
contains "[frustum_cull] the pixel's tile and its culled BVH" "the section"
contains "tile         (0, 0): pixels 0..31 x 0..31" "the tile"
contains "the same through the culled tree" "the hit kept"
contains "leaf, box" "the path to the hit's leaf"
finish
