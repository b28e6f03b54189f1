# fovref diff against a perturbed copy of a golden bundle (issue 4): exit codes, the first failing
# stage and pixel, tolerances, every input format, corrupt inputs, JSON and the HTML report
# (rendered in headless Chromium when it is installed).
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)

expect 0 "export a bundle" -- "$FOVREF" golden export cornell-basic "$TMP/bundle" -q
cp -r "$TMP/bundle" "$TMP/cand"
rm -f "$TMP/cand"/*.png "$TMP/cand/manifest.json"

expect 0 "identical buffers pass" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand"
contains "RESULT: PASS (20 compared, 0 out of tolerance" "identical"

# Perturb (PFM rows are stored bottom-to-top; 80x45 RGB): frame 0 gbuffer_albedo one ulp up at
# (40, 20) channel 1, and frame 0 final pixel (10, 30) channel 0 by +0.25.
"$PY" - "$TMP/cand" <<'PYTHON'
import struct, sys
def poke(path, x, y, c, change):
    data = bytearray(open(path, "rb").read())
    offset = 0
    for _ in range(3):
        offset = data.index(b"\n", offset) + 1
    w, h, channels = 80, 45, 3
    at = offset + (((h - 1 - y) * w + x) * channels + c) * 4
    data[at:at + 4] = change(bytes(data[at:at + 4]))
    open(path, "wb").write(data)
up_one_ulp = lambda b: struct.pack("<I", struct.unpack("<I", b)[0] + 1)
plus_quarter = lambda b: struct.pack("<f", struct.unpack("<f", b)[0] + 0.25)
poke(sys.argv[1] + "/f000_gbuffer_albedo.pfm", 40, 20, 1, up_one_ulp)
poke(sys.argv[1] + "/f000_final.pfm", 10, 30, 0, plus_quarter)
PYTHON
expect 1 "perturbed candidate fails" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --json "$TMP/r.json" --html "$TMP/html"
contains "first failing stage: primary_visibility, buffer 'gbuffer_albedo', frame 0" "names the first failing stage"
contains "first failing pixel (40, 20)" "names the ulp pixel"
contains "RESULT: FAIL (20 compared, 2 out of tolerance" "counts"
contains "explain it: fovref probe --scene cornell --mode basic --width 80 --height 45" "probe command"
check_file "$TMP/r.json" "JSON report"
check_file "$TMP/html/index.html" "HTML report"
"$PY" - "$TMP/r.json" <<'PYTHON' || { echo "FAIL: JSON report content"; failures=$((failures + 1)); }
import json, sys
r = json.load(open(sys.argv[1]))
assert r["pass"] is False and r["failed"] == 2, r["failed"]
assert r["first_failing"] == {"frame": 0, "buffer": "gbuffer_albedo", "stage": "primary_visibility"}
b = {(x["frame"], x["name"]): x for x in r["buffers"]}
albedo, final = b[(0, "gbuffer_albedo")], b[(0, "final")]
assert albedo["max_ulp"] == 1 and albedo["failing_pixels"] == 1
assert albedo["first_failing_pixel"]["x"] == 40 and albedo["first_failing_pixel"]["y"] == 20
assert final["worst_pixels"][0]["x"] == 10 and final["worst_pixels"][0]["y"] == 30
assert abs(final["max_abs_error"] - 0.25) < 1e-6
assert len(final["rings"]) == 20 and final["psnr"] != "inf"
assert b[(1, "final")]["status"] == "pass" and b[(0, "gbuffer_view_depth")]["psnr"] == "inf"
PYTHON
checks=$((checks + 1))

# The probe command the report prints runs and explains that pixel.
probe=$(grep -o 'explain it: .*' <<<"$OUT" | sed 's/explain it: fovref //')
expect 0 "the printed probe command" -- "$FOVREF" $probe
contains "pixel (40, 20)" "probe explains the worst pixel of the first failing buffer"

# Tolerances from the command line and from a file.
expect 1 "ulp tolerance on the albedo: final still fails" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --tolerance gbuffer_albedo:ulp=1
contains "first failing stage: shade_direct, buffer 'final', frame 0" "next failing stage"
cat > "$TMP/tol.json" <<'JSON'
{
  "gbuffer_albedo": {"ulp": 1, "reason": "GPU texture filtering rounds differently"},
  "final": {"abs": 0.3, "reason": "test"}
}
JSON
expect 0 "tolerance file admits both" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --tolerance-file "$TMP/tol.json"
contains "RESULT: PASS" "tolerance file"
expect 0 "one failing pixel allowed" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --tolerance '*:pixels=1'
printf '{\n  "final": {"abs": 0.3,\n  "bogus": 1}\n}\n' > "$TMP/bad.json"
expect 2 "tolerance file with an unknown key" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --tolerance-file "$TMP/bad.json"
contains "bad.json:3" "tolerance file line"
printf '{"final": {"abs": 0.3,}}' > "$TMP/bad.json"
expect 2 "tolerance file that is not JSON" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --tolerance-file "$TMP/bad.json"
contains "bad.json:1" "malformed tolerance file"
expect 2 "malformed --tolerance" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --tolerance final:abs=oops
contains "not a valid value for abs" "malformed --tolerance"

# Formats: raw binary32 (top row first, interleaved) and EXR are read; PNG is sRGB-decoded.
mkdir -p "$TMP/formats"
"$PY" - "$TMP/bundle/f000_final.pfm" "$TMP/formats/final.raw" <<'PYTHON'
import struct, sys
data = open(sys.argv[1], "rb").read()
offset = 0
for _ in range(3):
    offset = data.index(b"\n", offset) + 1
w, h = 80, 45
rows = [data[offset + r * w * 12: offset + (r + 1) * w * 12] for r in range(h)]
open(sys.argv[2], "wb").write(b"".join(reversed(rows)))
PYTHON
expect 0 "raw dump of the final image" -- "$FOVREF" diff "$TMP/bundle" "$TMP/formats" --frame 0
contains "RESULT: PASS (1 compared" "raw with the golden's shape"
expect 0 "a single raw file" -- "$FOVREF" diff "$TMP/bundle" "$TMP/formats/final.raw"
expect 1 "raw read bottom-up is wrong" -- "$FOVREF" diff "$TMP/bundle" "$TMP/formats/final.raw" --raw-bottom-up
head -c 1000 "$TMP/formats/final.raw" > "$TMP/formats/short.raw"
expect 2 "truncated raw" -- "$FOVREF" diff "$TMP/bundle" "$TMP/formats/short.raw"
contains "needs 43200 bytes, the file has 1000" "truncated raw"
expect 0 "EXR buffer (motion) and a raw with explicit size" -- "$FOVREF" diff "$TMP/bundle/f000_final.pfm" "$TMP/formats/final.raw" --raw-size 80x45x3
expect 1 "PNG preview vs float golden: quantised" -- "$FOVREF" diff "$TMP/bundle" "$TMP/bundle/f000_final.png"
contains "shade_direct" "png candidate compared with final"
expect 0 "PNG preview within 8-bit tolerance where not clipped" -- "$FOVREF" diff "$TMP/bundle" "$TMP/bundle/f000_final.png" --tolerance 'final:abs=0.01,pixels=400'
head -c 200 "$TMP/cand/f000_final.pfm" > "$TMP/formats/f000_final.pfm"
expect 2 "truncated PFM candidate" -- "$FOVREF" diff "$TMP/bundle" "$TMP/formats"
contains "f000_final.pfm" "names the corrupt file"
expect 0 "render at another size" -- "$FOVREF" render --scene cornell --mode basic --width 40 --height 20 --out "$TMP/small" -q
expect 2 "size mismatch" -- "$FOVREF" diff "$TMP/bundle" "$TMP/small/f000_final.pfm"
contains "size mismatch" "size mismatch"
expect 2 "missing golden" -- "$FOVREF" diff "$TMP/nope" "$TMP/cand"
expect 2 "nothing to compare" -- "$FOVREF" diff "$TMP/bundle" "$TMP/html"
contains "nothing to compare" "nothing to compare"
expect 2 "usage" -- "$FOVREF" diff "$TMP/bundle"
expect 0 "image vs image" -- "$FOVREF" diff "$TMP/bundle/f001_final.pfm" "$TMP/cand/f001_final.pfm"
expect 1 "image vs image, perturbed" -- "$FOVREF" diff "$TMP/bundle/f000_final.pfm" "$TMP/cand/f000_final.pfm" --json -
contains '"pass": false' "JSON on stdout"

# A 1048577x1 image: the report's downscale kept 0 rows and the report failed (issue 11).
"$PY" - "$TMP" <<'PYTHON'
import struct, sys
w = 1048577
for name, last in (("wide_a", 0.5), ("wide_b", 0.7)):
    open(f"{sys.argv[1]}/{name}.pfm", "wb").write(b"Pf\n%d 1\n-1\n" % w + struct.pack("<%df" % w, *([0.5] * (w - 1) + [last])))
PYTHON
expect 1 "a 1048577x1 image with an HTML report" -- "$FOVREF" diff "$TMP/wide_a.pfm" "$TMP/wide_b.pfm" --html "$TMP/wide_html"
check_file "$TMP/wide_html/index.html" "report of a one-row image"

# The HTML report in a real browser: the images decode and the failing stage is marked.
checks=$((checks + 1))
if ! grep -q 'id="first-failing"' "$TMP/html/index.html" || ! grep -q 'gbuffer_albedo' "$TMP/html/index.html"; then
  echo "FAIL: HTML content"; failures=$((failures + 1))
fi
# --flip: the bundle's display model gives the pixels per degree; two plain images use NVlabs's
# default observer (67.02 ppd, not the 60 degree field of view of the error ranges); both say so,
# and say how the pooled values are summed.
expect 1 "--flip on a bundle" -- "$FOVREF" diff "$TMP/bundle" "$TMP/cand" --flip --json "$TMP/flip.json"
contains "pixels per degree (display model, viewing distance" "bundle: display model"
contains "LDR-FLIP pooling: binary64 sums" "pooling stated"
expect 1 "--flip on two plain files" -- "$FOVREF" diff "$TMP/bundle/f000_final.pfm" "$TMP/cand/f000_final.pfm" --flip --json "$TMP/flip2.json"
contains "67.02 pixels per degree (NVlabs default observer" "plain images: NVlabs default observer"
"$PY" - "$TMP/flip2.json" <<'PYTHON' || { echo "FAIL: FLIP JSON"; failures=$((failures + 1)); }
import json, sys
r = json.load(open(sys.argv[1]))
items = [i for i in r["buffers"] if "flip" in i]
assert items, "no flip entry"
f = items[0]["flip"]
assert abs(f["pixels_per_degree"] - 67.0206451) < 1e-5, f
assert "NVlabs default observer" in f["observer"] and "binary64" in f["pooling"], f
assert 0 < f["mean"] <= f["max"] <= 1, f
PYTHON

CHROMIUM=$(command -v chromium || command -v chromium-browser || true)
if [ -n "$CHROMIUM" ]; then
  expect 0 "headless Chromium renders the report" -- timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --user-data-dir="$TMP/chrome" --dump-dom "file://$TMP/html/index.html"
  decoded=$(grep -o 'id="images-loaded">[0-9]* of [0-9]* decoded' <<<"$OUT")
  checks=$((checks + 1))
  if [[ "$decoded" =~ \>([0-9]+)\ of\ ([0-9]+)\ decoded ]] && [ "${BASH_REMATCH[1]}" = "${BASH_REMATCH[2]}" ] && [ "${BASH_REMATCH[1]}" -ge 6 ]; then
    echo "chromium: $decoded"
  else
    echo "FAIL: images in the HTML report did not all decode: '$decoded'"; failures=$((failures + 1))
  fi
  contains '"><b>primary_visibility</b>, buffer <b>gbuffer_albedo</b>, frame 0</a>' "failing stage in the DOM"
  expect 0 "screenshot" -- timeout 120 "$CHROMIUM" --headless --no-sandbox --disable-gpu --user-data-dir="$TMP/chrome" --window-size=1200,900 --screenshot="$TMP/shot.png" "file://$TMP/html/index.html"
  check_file "$TMP/shot.png" "screenshot of the report"
else
  echo "SKIPPED: headless Chromium check (chromium is not installed: apt-get install chromium)"
fi
finish
