# rays make/trace and the benchmark's smoke run (figures are not checked: benchmarks are not tests).
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)
expect 0 "make camera rays" -- "$FOVREF" rays make cornell "$TMP/r.bin" --camera --width 16 --height 9
check_file "$TMP/r.bin" "camera rays"
[ "$(stat -c %s "$TMP/r.bin")" = $((16 * 9 * 32)) ] || { echo "FAIL: ray file size"; failures=$((failures+1)); }
expect 0 "trace" -- "$FOVREF" rays trace cornell "$TMP/r.bin" "$TMP/h.bin"
[ "$(stat -c %s "$TMP/h.bin")" = $((16 * 9 * 16)) ] || { echo "FAIL: hit file size"; failures=$((failures+1)); }
expect 0 "make random rays" -- "$FOVREF" rays make sphere-grid "$TMP/q.bin" --random 500 --seed 9
expect 0 "any-hit" -- "$FOVREF" rays trace sphere-grid "$TMP/q.bin" "$TMP/o.bin" --any-hit
# Interleaved closest hits: the same hit file, byte for byte, and the same counts (5000 rays: a
# chunk of 4096 and a shorter one, the 16 lanes each taking many rays).
expect 0 "make more random rays" -- "$FOVREF" rays make sphere-grid "$TMP/m.bin" --random 5000 --seed 3
expect 0 "trace one at a time" -- "$FOVREF" rays trace sphere-grid "$TMP/m.bin" "$TMP/q1.bin"
ONE="$OUT"
expect 0 "trace interleaved" -- "$FOVREF" rays trace sphere-grid "$TMP/m.bin" "$TMP/q16.bin" --interleave
checks=$((checks + 1))
cmp -s "$TMP/q1.bin" "$TMP/q16.bin" || { echo "FAIL: --interleave changed the hits"; failures=$((failures+1)); }
checks=$((checks + 1))
[ "$(grep -o 'traced.*tested' <<<"$ONE")" = "$(grep -o 'traced.*tested' <<<"$OUT")" ] || { echo "FAIL: --interleave changed the counts"; failures=$((failures+1)); }
expect 2 "--interleave with --any-hit" -- "$FOVREF" rays trace sphere-grid "$TMP/q.bin" "$TMP/qa.bin" --any-hit --interleave
contains "--interleave applies to closest-hit queries" "--interleave with --any-hit"
[ "$(stat -c %s "$TMP/o.bin")" = $((500 * 4)) ] || { echo "FAIL: occlusion file size"; failures=$((failures+1)); }
# Occlusion in packets: the same flags, byte for byte, and the same hit count, on random rays
# (packets of one or two) and on camera rays (full packets).
expect 0 "make coherent rays" -- "$FOVREF" rays make sphere-grid "$TMP/c.bin" --camera --width 64 --height 36
for f in m c; do
  expect 0 "any-hit one at a time ($f)" -- "$FOVREF" rays trace sphere-grid "$TMP/$f.bin" "$TMP/o1.bin" --any-hit
  ONE="$OUT"
  expect 0 "any-hit packets ($f)" -- "$FOVREF" rays trace sphere-grid "$TMP/$f.bin" "$TMP/o8.bin" --any-hit --packets
  checks=$((checks + 1))
  cmp -s "$TMP/o1.bin" "$TMP/o8.bin" || { echo "FAIL: --packets changed the occlusion flags ($f)"; failures=$((failures+1)); }
  checks=$((checks + 1))
  [ "$(grep -o 'rays: [0-9]* hit' <<<"$ONE")" = "$(grep -o 'rays: [0-9]* hit' <<<"$OUT")" ] || { echo "FAIL: --packets changed the hit count ($f)"; failures=$((failures+1)); }
done
expect 2 "--packets without --any-hit" -- "$FOVREF" rays trace sphere-grid "$TMP/q.bin" "$TMP/qp.bin" --packets
contains "--packets applies to --any-hit" "--packets without --any-hit"
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
expect 0 "bench --explain, two rounds" -- "$FOVREF" bench rays --scene cornell --width 32 --height 18 --repeats 1 --rounds 2 --explain 2
contains "fastest of 2 runs (2 rounds, fovref and Embree in turn)" "bench rays counts the rounds"
contains "| cornell      | shadow" "bench rays: the rows after the rounds"
if grep -q "comparison: Embree" <<<"$OUT"; then
  contains "hit/miss disagreements with Embree: none" "cornell agrees with Embree on every ray"
else
  contains "--explain: no disagreements to list (Embree not found" "explain without Embree"
fi
expect 2 "bench --explain out of range" -- "$FOVREF" bench rays --scene cornell --explain -1
expect 0 "basic via raster" -- "$FOVREF" render --scene cornell --mode basic --primary raster --width 16 --height 9 --out "$TMP/br" -q
expect 2 "bad --primary" -- "$FOVREF" render --scene cornell --mode basic --primary gpu --out "$TMP/bp"
# tile frustum culling: every row (screen tiles with each test and option, cfov buffer tiles,
# sphere-grid's shadow frusta;
# cornell has no point light) lost 0
expect 0 "bench frustum" -- "$FOVREF" bench frustum --scene cornell sphere-grid --width 64 --height 36 --tile-size 16 32 -q
checks=$((checks + 1))
rows=$(grep -cE '^  (cornell|sphere-grid) ' <<<"$OUT")
bad=$(grep -E '^  (cornell|sphere-grid) ' <<<"$OUT" | awk '$NF != 0' | wc -l)
[ "$rows" -eq 34 ] && [ "$bad" -eq 0 ] || { echo "FAIL: bench frustum rows $rows, lost-hit rows $bad"; failures=$((failures + 1)); }
expect 2 "bench frustum bad tile size" -- "$FOVREF" bench frustum --tile-size 0
# the probe explains a pixel's tile: its frustum, its culled tree, the path to its hit's leaf
expect 0 "probe with frustum culling" -- "$FOVREF" probe --scene cornell --mode basic --width 64 --height 36 --pixel 30,20 --param frustum=lund
contains "[frustum_cull] the pixel's tile and its culled BVH" "the section"
contains "tile         (0, 0): pixels 0..31 x 0..31" "the tile"
contains "the same through the culled tree" "the hit kept"
contains "leaf, box" "the path to the hit's leaf"
# rays cull: the culled trees for a GPU; the files agree with the manifest and with each other
expect 0 "rays cull" -- "$FOVREF" rays cull checker-room "$TMP/rc" --width 64 --height 36 \
  --tile-size 16 --shadow -q
checks=$((checks + 1))
"$PY" - "$TMP/rc" <<'PYEOF' || { echo "FAIL: rays cull files"; failures=$((failures + 1)); }
import json, os, struct, sys
d = sys.argv[1]
m = json.load(open(os.path.join(d, "manifest.json")))
assert os.path.getsize(os.path.join(d, "triangles.bin")) == 40 * m["triangles"]
for prefix, total in (("", m["nodes"]), ("shadow_", m["shadow"]["nodes"])):
    tiles = open(os.path.join(d, prefix + "tiles.bin"), "rb").read()
    nodes = open(os.path.join(d, prefix + "nodes.bin"), "rb").read()
    assert len(nodes) == 32 * total, (prefix, len(nodes), total)
    assert len(tiles) == 32 * m["tiles_x"] * m["tiles_y"]
    at = 0
    for k in range(m["tiles_x"] * m["tiles_y"]):
        tx, ty, x0, y0, x1, y1, first, count = struct.unpack_from("<8I", tiles, 32 * k)
        assert (tx, ty) == (k % m["tiles_x"], k // m["tiles_x"]) and first == at, (k, first, at)
        assert x0 == 16 * tx and y0 == 16 * ty and x1 == min(x0 + 16, 64) and y1 == min(y0 + 16, 36)
        for r in range(count):
            node = struct.unpack_from("<3fI3fI", nodes, 32 * (first + r))
            if node[7] > 0:
                assert node[3] + node[7] <= m["triangles"]
            elif node[0] <= node[4]:  # an inner node's children lie in the tile's records
                assert node[3] + 1 < count, (k, r, node)
        at += count
    assert at == total
PYEOF
expect 2 "rays cull --test" -- "$FOVREF" rays cull cornell "$TMP/rc2" --test hunt
expect 2 "rays cull --shadow without a point light" -- "$FOVREF" rays cull cornell "$TMP/rc3" --shadow
contains "rays cull: --shadow: the scene has no point light" "names the option and what is missing"
checks=$((checks + 1))
[ ! -e "$TMP/rc3" ] || { echo "FAIL: rays cull left $TMP/rc3 behind"; failures=$((failures + 1)); }
finish
