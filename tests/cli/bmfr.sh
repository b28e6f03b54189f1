# BMFR and the path-traced reference from the command line: a denoised sequence dumps every
# phase; `fovref denoise bmfr` on those buffers (cameras from the bundle's manifest or from a
# cameras.json) reproduces every phase bit for bit; frames resumed from a dump give the bits of
# the whole sequence; NaN radiance is replaced and counted; bad inputs give one clear error; the
# reference continues its sums with --resume.
source "$(dirname "$0")/lib.bash"
common=(--scene cornell --width 64 --height 40 --time-step 0.1 --quiet)
phases=(bmfr_illumination bmfr_accumulated_noisy bmfr_spp bmfr_accept bmfr_fitted
  bmfr_accumulated_filtered bmfr_display bmfr_taa final)

expect 0 "pathtrace denoise=bmfr, 4 frames, every buffer" -- "$FOVREF" render --mode pathtrace \
  --param denoise=bmfr --frames 4 "${common[@]}" --dump "$TMP/seq"
for b in "${phases[@]}" radiance; do check_file "$TMP/seq/f003_$b.pfm" "dump $b"; done
for b in bmfr_weights bmfr_feature_range bmfr_previous_pixel; do
  check_file "$TMP/seq/f003_$b.exr" "dump $b (EXR: more than 3 channels or 2)"
done

# denoise bmfr on the dump: the same bits in every phase
expect 0 "denoise bmfr on a fovref dump" -- "$FOVREF" denoise bmfr "$TMP/seq" "$TMP/den" -q
for f in 0 3; do
  for b in "${phases[@]}"; do
    checks=$((checks + 1))
    cmp -s "$TMP/seq/f00${f}_$b.pfm" "$TMP/den/f00${f}_$b.pfm" ||
      { echo "FAIL: denoise: frame $f $b differs from the render's"; failures=$((failures + 1)); }
  done
done

# the documented input layout: four buffers per frame (and the optional emission) and cameras.json
mkdir -p "$TMP/ext"
for f in 0 1 2 3; do
  for b in radiance gbuffer_albedo gbuffer_shading_normal gbuffer_world_position emission; do
    cp "$TMP/seq/f00${f}_$b.pfm" "$TMP/ext/"
  done
done
python3 - "$TMP/seq/manifest.json" "$TMP/ext/cameras.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
json.dump({"width": m["case"]["width"], "height": m["case"]["height"],
           "frames": [{"camera": f["camera"]} for f in m["frames"]]}, open(sys.argv[2], "w"))
PY
expect 0 "denoise bmfr on external buffers + cameras.json" -- "$FOVREF" denoise bmfr "$TMP/ext" \
  "$TMP/den2" -q
checks=$((checks + 1))
cmp -s "$TMP/seq/f003_final.pfm" "$TMP/den2/f003_final.pfm" ||
  { echo "FAIL: cameras.json: frame 3 differs"; failures=$((failures + 1)); }
# bmfr_emission=separate: the emission files are kept out of the fit, as in the render
expect 0 "render with bmfr_emission=separate" -- "$FOVREF" render --mode pathtrace \
  --param denoise=bmfr --param bmfr_emission=separate --frames 4 "${common[@]}" --out "$TMP/sep"
expect 0 "denoise bmfr with bmfr_emission=separate" -- "$FOVREF" denoise bmfr "$TMP/ext" \
  "$TMP/den-sep" --param bmfr_emission=separate -q
checks=$((checks + 1))
cmp -s "$TMP/sep/f003_final.pfm" "$TMP/den-sep/f003_final.pfm" ||
  { echo "FAIL: bmfr_emission=separate: frame 3 differs"; failures=$((failures + 1)); }
checks=$((checks + 1))
! cmp -s "$TMP/sep/f003_final.pfm" "$TMP/seq/f003_final.pfm" ||
  { echo "FAIL: bmfr_emission=separate changed nothing on cornell"; failures=$((failures + 1)); }

# NaN radiance: replaced by 0, counted, the output finite
python3 - "$TMP/ext/f001_radiance.pfm" <<'PY'
import struct, sys
path = sys.argv[1]
data = open(path, "rb").read()
header_end = 0
for _ in range(3):
    header_end = data.index(b"\n", header_end) + 1
body = bytearray(data[header_end:])
body[0:4] = struct.pack("<f", float("nan"))
body[12:16] = struct.pack("<f", float("inf"))
open(path, "wb").write(data[:header_end] + bytes(body))
PY
expect 0 "denoise bmfr with NaN/Inf radiance" -- "$FOVREF" denoise bmfr "$TMP/ext" "$TMP/den3" -q
python3 - "$TMP/den3/manifest.json" "$TMP/den3/f003_final.pfm" >"$TMP/nan.txt" <<'PY'
import json, math, struct, sys
m = json.load(open(sys.argv[1]))
# the stages' inputs replace them and count them, as in every mode (nonfinite_stage_inputs)
print("nonfinite", m["frames"][1]["counters"]["nonfinite_stage_inputs"])
data = open(sys.argv[2], "rb").read()
end = 0
for _ in range(3):
    end = data.index(b"\n", end) + 1
values = struct.unpack("<%df" % ((len(data) - end) // 4), data[end:])
print("finite", all(math.isfinite(v) for v in values))
PY
OUT=$(cat "$TMP/nan.txt")
contains "nonfinite 2" "the two replaced values are counted"
contains "finite True" "the output stays finite"

# bad inputs: one clear line naming the file, exit 2, nothing written
rm "$TMP/ext/f002_gbuffer_albedo.pfm"
expect 2 "a missing buffer" -- "$FOVREF" denoise bmfr "$TMP/ext" "$TMP/bad1"
contains "f002_gbuffer_albedo.pfm (or .exr): missing" "the error names the file"
checks=$((checks + 1))
[ ! -e "$TMP/bad1" ] || { echo "FAIL: a failed denoise left $TMP/bad1"; failures=$((failures + 1)); }
echo '{"width": 64, "height": 40, "frames": [{"view_projection": [1, 2]}]}' >"$TMP/ext/cameras.json"
expect 2 "a malformed matrix" -- "$FOVREF" denoise bmfr "$TMP/ext" "$TMP/bad2"
contains "frames[0].view_projection: expected 16 numbers" "the error names the key"
echo '{"width": 64,' >"$TMP/ext/cameras.json"
expect 2 "a JSON syntax error" -- "$FOVREF" denoise bmfr "$TMP/ext" "$TMP/bad3"
contains "cameras.json: JSON syntax error" "the error names the file"
mkdir -p "$TMP/badman" && echo '{"case": 3, "frames": []}' >"$TMP/badman/manifest.json"
expect 2 "a manifest that is not a bundle's" -- "$FOVREF" denoise bmfr "$TMP/badman" "$TMP/bad3b"
contains "not a fovref bundle manifest" "the error names the file"
expect 2 "an unknown parameter" -- "$FOVREF" denoise bmfr "$TMP/seq" "$TMP/bad4" --param nope=1
contains "nope" "the error names the parameter"
expect 2 "bmfr_storage without denoise=bmfr" -- "$FOVREF" render --mode pathtrace \
  --param bmfr_storage=float "${common[@]}" --out "$TMP/bad5"
contains "applies to denoise=bmfr only" "the error says why"
expect 2 "denoise=nlm" -- "$FOVREF" render --mode pathtrace --param denoise=nlm "${common[@]}" \
  --out "$TMP/bad6"
contains "parameter 'denoise'" "the error names the parameter"
expect 2 "bmfr_emission=twice" -- "$FOVREF" render --mode pathtrace --param denoise=bmfr \
  --param bmfr_emission=twice "${common[@]}" --out "$TMP/bad6b"
contains "parameter 'bmfr_emission'" "the error names the parameter"

# frames 2..3 resumed from the dump of frame 1: the bits of the sequence
expect 0 "resume frames 2..3" -- "$FOVREF" render --mode pathtrace --param denoise=bmfr \
  --frames 2..3 "${common[@]}" --resume "$TMP/seq" --out "$TMP/resumed" --output all
for b in "${phases[@]}"; do
  checks=$((checks + 1))
  cmp -s "$TMP/seq/f003_$b.pfm" "$TMP/resumed/f003_$b.pfm" ||
    { echo "FAIL: resumed frame 3 $b differs from the sequence's"; failures=$((failures + 1)); }
done
expect 2 "frame 2 without --resume" -- "$FOVREF" render --mode pathtrace --param denoise=bmfr \
  --first-frame 2 "${common[@]}" --out "$TMP/bad7"
contains "--resume" "the error names --resume"

# the converged reference: 8 samples, then continued to 24, equal to one run of 24
expect 0 "reference spp=8" -- "$FOVREF" render --mode pathtrace-reference --param spp=8 \
  "${common[@]}" --out "$TMP/ref8"
expect 0 "reference continued to 24" -- "$FOVREF" render --mode pathtrace-reference \
  --param spp=24 "${common[@]}" --resume "$TMP/ref8" --out "$TMP/ref24"
expect 0 "reference spp=24 in one run" -- "$FOVREF" render --mode pathtrace-reference \
  --param spp=24 "${common[@]}" --out "$TMP/ref24b"
for b in final standard_error reference_sum; do
  checks=$((checks + 1))
  cmp -s "$TMP/ref24/f000_$b.pfm" "$TMP/ref24b/f000_$b.pfm" ||
    { echo "FAIL: resumed reference $b differs from one run"; failures=$((failures + 1)); }
done
expect 2 "reference resumed beyond its spp" -- "$FOVREF" render --mode pathtrace-reference \
  --param spp=4 "${common[@]}" --resume "$TMP/ref8" --out "$TMP/bad8"
contains "already holds 8 samples" "the error says how many"
expect 2 "reference resumed from another scene" -- "$FOVREF" render --mode pathtrace-reference \
  --param spp=24 --scene checker-room --width 64 --height 40 --quiet --resume "$TMP/ref8" \
  --out "$TMP/bad9"
contains "other settings" "the error says the settings differ"
# the benchmark, tiny: it runs and prints its tables
expect 0 "bench bmfr" -- "$FOVREF" bench bmfr --width 64 --height 40 --repeats 1 --error-width 32 \
  --error-height 24 --frames 2 --every 1 --reference-spp 2 -q
contains "BMFR (all phases)" "the cost table"
contains "RMSE BMFR" "the error table"
expect 2 "bench bmfr --every beyond --frames" -- "$FOVREF" bench bmfr --no-cost --frames 2 \
  --every 3 -q
contains "no frame would be compared" "the error says why"
finish
