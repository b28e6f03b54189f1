# golden export writes a full bundle at any size.
source "$(dirname "$0")/lib.bash"
expect 0 "list" -- "$FOVREF" golden list --dir "$SRC/golden"
contains "cornell-splat" "list"
expect 0 "export" -- "$FOVREF" golden export cornell-splat "$TMP/bundle" --width 64 --height 36 --frames 2 \
  --dir "$SRC/golden" --quiet
check_file "$TMP/bundle/manifest.json" "export manifest"
grep -q '"width": 64' "$TMP/bundle/manifest.json" || { echo "FAIL: export width"; failures=$((failures+1)); }
for b in splat_depth splat_primitive splat_normal splat_albedo final; do
  check_file "$TMP/bundle/f001_$b.pfm" "export $b"
  check_file "$TMP/bundle/f001_$b.png" "export preview $b"
done
# --raw-copies: the EXR buffers (2 channels here) also as raw binary32, top row first, the same
# values; --timings: each stage's seconds in the manifest
expect 0 "export --raw-copies --timings" -- "$FOVREF" golden export cornell-cfov "$TMP/raw" \
  --width 40 --height 24 --raw-copies --timings --dir "$SRC/golden" --quiet
checks=$((checks + 1))
python3 - "$TMP/raw" <<'PY' || { echo "FAIL: raw copies or timings"; failures=$((failures + 1)); }
import json, os, struct, sys
d = sys.argv[1]
m = json.load(open(os.path.join(d, "manifest.json")))
f = m["frames"][0]
b = [b for b in f["buffers"] if b["name"] == "lp_screen_point"][0]
assert b["file"].endswith(".exr") and b["raw_file"] == "f000_lp_screen_point.f32", b
raw = open(os.path.join(d, b["raw_file"]), "rb").read()
assert len(raw) == 4 * b["width"] * b["height"] * 2, len(raw)
# the PFM buffers have no raw copy; every stage that ran has its seconds
assert all("raw_file" not in x for x in f["buffers"] if x["channels"] in (1, 3))
assert all(s["seconds"] >= 0 for s in f["stages"] if s["ran"]), f["stages"]
# every parameter of the mode with the value used: cfov's defaults (sigma 1.4, a_G 0.2) and the
# case's own (none given here but the size)
p = m["effective_params"]
# (defaults as the binary32 value's 9 significant digits: "1.39999998" reads back as 1.4f)
assert abs(float(p["sigma"]) - 1.4) < 1e-6 and abs(float(p["gaze_angle"]) - 0.2) < 1e-6, p
assert p["resolve"] == "bilinear" and p["L"] == "diagonal", p
assert set(p) >= {"alpha", "L", "lp_aspect", "filters", "taa"}, sorted(p)
PY
expect 0 "export with --param" -- "$FOVREF" golden export cornell-cfov "$TMP/param" --width 40 --height 24 --param sigma=2 --dir "$SRC/golden" --quiet
checks=$((checks + 1))
python3 -c "import json, sys; p = json.load(open('$TMP/param/manifest.json'))['effective_params']; sys.exit(0 if p['sigma'] == '2' else 1)" ||
  { echo "FAIL: effective_params lacks the given sigma"; failures=$((failures + 1)); }
SIZE=$(python3 -c "import json; b = [b for b in json.load(open('$TMP/raw/manifest.json'))['frames'][0]['buffers'] if b['name'] == 'lp_screen_point'][0]; print('%dx%dx2' % (b['width'], b['height']))")
expect 0 "the raw copy's values are the EXR's" -- "$FOVREF" diff "$TMP/raw/f000_lp_screen_point.exr" "$TMP/raw/f000_lp_screen_point.f32" --raw-size "$SIZE"
expect 2 "export unknown case" -- "$FOVREF" golden export nope "$TMP/x" --dir "$SRC/golden"
finish
