# `fovref denoise bmfr` on input in the BMFR authors' conventions (issue 29): the colour already
# divided by max(albedo, 0.01) (--demodulated), per-frame pixel offsets and the two reprojection
# limits in cameras.json. A synthetic sequence written that way gives the same bits in every phase
# as the same sequence in fovref's own layout (radiance, the limits as --param). Also --frames,
# --output, stage times in the manifest, and the input files checked before any work.
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)
cd "$TMP" || exit 1
expect 0 "a path-traced sequence" -- "$FOVREF" render --mode pathtrace --scene cornell --width 64 \
  --height 40 --time-step 0.1 --frames 4 --param denoise=bmfr --dump seq -q
# fovref's layout (radiance) and the authors' (colour / max(albedo, 0.01), offsets, limits)
"$PY" - "$SRC/tests/cli" <<'PYEOF' || { echo "FAIL: writing the inputs"; exit 1; }
import json, os, shutil, struct, sys
sys.path.insert(0, sys.argv[1])
import fake_port
m = json.load(open("seq/manifest.json"))
f32 = lambda v: struct.unpack("<f", struct.pack("<f", v))[0]
floor = f32(0.01)
for d in ("ours", "authors"):
    os.makedirs(d, exist_ok=True)
for frame in range(4):
    p = "f%03d_" % frame
    for b in ("gbuffer_albedo", "gbuffer_shading_normal", "gbuffer_world_position", "radiance"):
        shutil.copyfile("seq/" + p + b + ".pfm", "ours/" + p + b + ".pfm")
        if b != "radiance":
            shutil.copyfile("seq/" + p + b + ".pfm", "authors/" + p + b + ".pfm")
    w, h, c, radiance = fake_port.read_pfm("seq/" + p + "radiance.pfm")
    _, _, _, albedo = fake_port.read_pfm("seq/" + p + "gbuffer_albedo.pfm")
    # binary32 division (the binary64 quotient rounded once to binary32 is the binary32 quotient)
    colour = [f32(r / max(a, floor)) for r, a in zip(radiance, albedo)]
    fake_port.write_pfm("authors/" + p + "radiance.pfm", w, h, c, colour)
cams = [{"camera": f["camera"]} for f in m["frames"]]
json.dump({"width": 64, "height": 40, "frames": cams}, open("ours/cameras.json", "w"))
json.dump({"width": 64, "height": 40, "position_limit_squared": 0.02, "normal_limit_squared": 0.3,
           "frames": [dict(c, pixel_offset=[0.5, 0.5]) for c in cams]}, open("authors/cameras.json", "w"))
PYEOF
expect 0 "fovref's layout, limits as --param" -- "$FOVREF" denoise bmfr ours den-ours \
  --param bmfr_position_limit_squared=0.02 --param bmfr_normal_limit_squared=0.3 -q
expect 0 "the authors' layout: --demodulated, offsets and limits in cameras.json" -- \
  "$FOVREF" denoise bmfr authors den-authors --demodulated -q
for f in 0 1 3; do
  for b in bmfr_illumination bmfr_accumulated_noisy bmfr_spp bmfr_accept bmfr_fitted \
    bmfr_accumulated_filtered bmfr_display bmfr_taa final; do
    checks=$((checks + 1))
    cmp -s "den-ours/f00${f}_$b.pfm" "den-authors/f00${f}_$b.pfm" ||
      { echo "FAIL: frame $f $b differs between the two layouts"; failures=$((failures + 1)); }
  done
done
checks=$((checks + 1))  # the limits changed something: not the default's bits
! cmp -s den-ours/f003_final.pfm seq/f003_final.pfm ||
  { echo "FAIL: the limits changed nothing"; failures=$((failures + 1)); }
expect 2 "limits given twice, differently" -- "$FOVREF" denoise bmfr authors bad1 --demodulated \
  --param bmfr_position_limit_squared=0.05
contains "disagree; give one" "the conflict is named"
expect 2 "--demodulated with separate emission" -- "$FOVREF" denoise bmfr authors bad2 \
  --demodulated --param bmfr_emission=separate
contains "emission.pfm (or .exr): missing" "the emission it would need is checked first"
# --frames and --output: frames 2 .. 3 written, final only, stage times in the manifest
expect 0 "--frames 2..3 --output final" -- "$FOVREF" denoise bmfr ours part --frames 2..3 \
  --output final -q
checks=$((checks + 1))
[ "$(ls part | grep -c '\.pfm$')" = 2 ] && [ -f part/f002_final.pfm ] && [ -f part/f003_final.pfm ] ||
  { echo "FAIL: --frames/--output wrote: $(ls part)"; failures=$((failures + 1)); }
checks=$((checks + 1))
cmp -s part/f003_final.pfm seq/f003_final.pfm ||
  { echo "FAIL: frame 3 of --frames 2..3 differs from the render's"; failures=$((failures + 1)); }
"$PY" -c "
import json; m = json.load(open('part/manifest.json'))
stages = {s['name']: s for s in m['frames'][0]['stages']}
assert m['frames'][0]['frame'] == 2, m['frames'][0]['frame']
assert 'load_inputs' in stages and 'bmfr_fit' in stages, list(stages)
assert all('seconds' in s for s in stages.values()) and sum(s['seconds'] for s in stages.values()) > 0
" || { echo "FAIL: the manifest's stages"; failures=$((failures + 1)); }
checks=$((checks + 1))
expect 2 "--frames beyond the input" -- "$FOVREF" denoise bmfr ours bad3 --frames 9
contains "has 4 frame(s)" "the error says how many"
# a missing input of a later frame: found before any work, nothing written
rm ours/f003_gbuffer_albedo.pfm
expect 2 "a missing input of frame 3" -- "$FOVREF" denoise bmfr ours bad4 -q
contains "f003_gbuffer_albedo.pfm (or .exr): missing (frame 3)" "named before any work"
checks=$((checks + 1))
[ ! -e bad4 ] || { echo "FAIL: bad4 was created"; failures=$((failures + 1)); }
# bench bmfr --input: the phases timed on the same external buffers
expect 0 "bench bmfr --input" -- "$FOVREF" bench bmfr --input authors --demodulated -q
contains "BMFR (all phases)" "the phases timed"
contains "bmfr_fit" "per phase"
# tools/scripts/bmfr_authors_compare.py writes the cameras as matrices for the authors' code and
# for fovref: its view-projection (docs/bmfr.md's formula in numpy binary32) must be fovref's
# bit for bit, else the comparison would measure the transcription
"$PY" - "$SRC/tools/scripts" <<'PYEOF' || { echo "FAIL: writing the matrices"; exit 1; }
import importlib.util, json, os, shutil, sys
spec = importlib.util.spec_from_file_location("compare", sys.argv[1] + "/bmfr_authors_compare.py")
compare = importlib.util.module_from_spec(spec)
spec.loader.exec_module(compare)
shutil.copytree("ours", "matrices")
shutil.copyfile("seq/f003_gbuffer_albedo.pfm", "matrices/f003_gbuffer_albedo.pfm")  # removed above
cams = json.load(open("ours/cameras.json"))
cams["frames"] = [{"view_projection": compare.view_projection(f["camera"], 64, 40)}
                  for f in cams["frames"]]
json.dump(cams, open("matrices/cameras.json", "w"))
PYEOF
expect 0 "the script's matrices" -- "$FOVREF" denoise bmfr matrices den-matrices --output \
  bmfr_accumulated_noisy,bmfr_taa --param bmfr_position_limit_squared=0.02 \
  --param bmfr_normal_limit_squared=0.3 -q
for b in bmfr_accumulated_noisy bmfr_taa; do
  checks=$((checks + 1))
  cmp -s "den-ours/f003_$b.pfm" "den-matrices/f003_$b.pfm" ||
    { echo "FAIL: frame 3 $b differs with the script's matrices"; failures=$((failures + 1)); }
done
expect 1 "the comparison without the authors' code" -- "$PY" \
  "$SRC/tools/scripts/bmfr_authors_compare.py" --authors "$TMP/no-such-checkout" --fovref "$FOVREF"
contains "opencl/bmfr.cpp is missing" "names the file it needs"
finish
