# The foveated modes from the command line: render with --gaze and a gaze track, fovref density
# (table, CSV, SVG), bench foveation on a small screen, and bad input (exit 2).
source "$(dirname "$0")/lib.bash"

expect 0 "render cfov with --gaze" -- "$FOVREF" render --scene cornell --mode cfov --width 64 --height 36 --gaze 20,10 --out "$TMP/cfov" -q
check_file "$TMP/cfov/f000_final.pfm" "final"
check_file "$TMP/cfov/manifest.json" "manifest"
# holds DESCRIPTION -- test...: a shell test that must hold.
holds() {
  local what=$1; shift 2
  checks=$((checks + 1))
  if ! "$@"; then echo "FAIL: $what"; failures=$((failures + 1)); fi
}
printf 'frame,x,y\n0,10,10\n1,50,20\n' > "$TMP/track.csv"
expect 0 "render a sequence with a gaze track" -- "$FOVREF" render --scene cornell --mode kfr --width 64 --height 36 --frames 2 --param gaze_track="$TMP/track.csv" --out "$TMP/track" -q
expect 2 "a malformed gaze track" -- "$FOVREF" render --scene cornell --mode fov --width 16 --height 9 --param gaze_track=/nonexistent.csv --out "$TMP/bad" -q
contains "/nonexistent.csv" "the track file named"
printf '0,1,2\n0,3,4\n' > "$TMP/bad.csv"
expect 2 "frames not increasing" -- "$FOVREF" render --scene cornell --mode fov --width 16 --height 9 --param gaze_track="$TMP/bad.csv" --out "$TMP/bad" -q
contains "bad.csv:2: frame 0 does not follow frame 0" "file and line"
holds "nothing written on an error" -- test ! -e "$TMP/bad"
expect 2 "kfr with a gaze buffer" -- "$FOVREF" render --scene cornell --mode kfr --width 16 --height 9 --param gaze_angle=0.2 --out "$TMP/bad2" -q
contains "the deferred variant has no gaze buffer" "deferred + gaze buffer refused"

expect 0 "density" -- "$FOVREF" density cfov --rings 10 --out "$TMP/density"
contains "gaze buf" "gaze buffer rows"
check_file "$TMP/density/density.csv" "density.csv"
check_file "$TMP/density/density.svg" "density.svg"
holds "one CSV row per ring" -- test "$(wc -l < "$TMP/density/density.csv")" -eq 11
expect 2 "density of a mode without a buffer" -- "$FOVREF" density basic
contains "unknown foveation preset 'basic'" "density needs a log-polar mode"
expect 2 "density with an unknown parameter" -- "$FOVREF" density fov --param ipd=1
contains "not a parameter of mode 'fov'" "parameter checked"

expect 0 "bench foveation (small)" -- "$FOVREF" bench foveation --scene cornell --width 64 --height 36 --repeats 1 --stages -q
contains "cfov+lerp" "bench rows"
contains "speed-up" "bench columns"
contains "w-target" "bench work column"
contains "    gaze_trace" "bench --stages lists the stages"
contains "1.5x basic" "bench flags issue 33's kfr target"
printf 'frame,x,y\n0,30,18\n1,34,20\n' > "$TMP/track.csv"
expect 0 "bench foveation with a moving gaze, two rounds" -- "$FOVREF" bench foveation --scene cornell --mode cfov --width 64 --height 36 --repeats 1 --rounds 2 --gaze-track "$TMP/track.csv" -q
contains "gaze moving along" "the header names the gaze track"
contains "fastest of 2 frames (the first frame, which builds the BVH, is not timed), over 2 rounds" "the header counts the rounds"
contains "  cfov " "the row printed after its last round"
expect 2 "bench foveation: no rounds" -- "$FOVREF" bench foveation --rounds 0 --width 16 --height 9
contains "--rounds" "the option named"
expect 2 "bench foveation: a missing gaze track" -- "$FOVREF" bench foveation --gaze-track "$TMP/none.csv" --width 16 --height 9
expect 2 "bench foveation: unknown mode" -- "$FOVREF" bench foveation --mode nope --width 16 --height 9
# probe --texel I,J,EYE explains one texel of one eye of stereo-lp.
expect 0 "probe a stereo texel" -- "$FOVREF" probe --scene cornell --mode stereo-lp --width 96 --height 54 --texel 10,7,1
contains "texel (10, 7) of eye 1" "the eye named"
contains "texel: bit-identical to the rendered buffers" "the texel recomputed"
expect 2 "a stereo texel without its eye" -- "$FOVREF" probe --scene cornell --mode stereo-lp --width 96 --height 54 --texel 10,7
contains "needs the eye too" "the eye asked for"
expect 2 "an eye for a mono mode" -- "$FOVREF" probe --scene cornell --mode cfov --width 64 --height 36 --texel 10,7,0
contains "an eye applies to stereo-lp only" "the eye refused"

# fovref diff points at a texel for a log-polar buffer (with the eye in stereo) and moves a gaze
# buffer's pixel to the screen; each printed probe command runs.
PY=$(command -v /usr/bin/python3 || command -v python3)
bump() {  # bump FILE X Y: adds 0.5 to channel 0 of element (X, Y) of a little-endian PFM
  "$PY" - "$@" <<'PYTHON'
import struct, sys
path, x, y = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
data = bytearray(open(path, "rb").read())
lines = data.split(b"\n", 3)
channels = 3 if lines[0] == b"PF" else 1
w, h = map(int, lines[1].split())
at = len(lines[0]) + len(lines[1]) + len(lines[2]) + 3 + ((h - 1 - y) * w + x) * channels * 4
value = struct.unpack("<f", data[at:at + 4])[0] + 0.5
data[at:at + 4] = struct.pack("<f", value)
open(path, "wb").write(data)
PYTHON
}
expect 0 "export a stereo golden" -- "$FOVREF" golden export cornell-stereo-lp "$TMP/st_gold" -q
cp -r "$TMP/st_gold" "$TMP/st_cand"
W_EYE=$("$PY" -c "import json,sys; print(json.load(open(sys.argv[1]))['frames'][0]['counters']['buffer_width'])" "$TMP/st_gold/manifest.json")
bump "$TMP/st_cand/f000_lp_color.pfm" $((W_EYE + 5)) 9
expect 1 "a stereo texel changed" -- "$FOVREF" diff "$TMP/st_gold" "$TMP/st_cand"
contains "buffer 'lp_color'" "names the buffer"
contains "--texel 5,9,1" "the texel of eye 1"
CMD=$(grep -o "explain it: fovref probe.*" <<<"$OUT" | sed 's/^explain it: fovref //')
# shellcheck disable=SC2086
expect 0 "the printed stereo probe command runs" -- "$FOVREF" $CMD
contains "texel (5, 9) of eye 1" "explains that texel"
expect 0 "export a composite golden" -- "$FOVREF" golden export cornell-cfov "$TMP/cf_gold" -q
cp -r "$TMP/cf_gold" "$TMP/cf_cand"
X0=$("$PY" -c "import json,sys; print(json.load(open(sys.argv[1]))['frames'][0]['counters']['gaze_window_x0'])" "$TMP/cf_gold/manifest.json")
Y0=$("$PY" -c "import json,sys; print(json.load(open(sys.argv[1]))['frames'][0]['counters']['gaze_window_y0'])" "$TMP/cf_gold/manifest.json")
bump "$TMP/cf_cand/f000_gaze_color.pfm" 4 3
expect 1 "a gaze pixel changed" -- "$FOVREF" diff "$TMP/cf_gold" "$TMP/cf_cand"
contains "buffer 'gaze_color'" "names the gaze buffer"
contains "--pixel $((X0 + 4)),$((Y0 + 3))" "the screen pixel of the gaze buffer's pixel"
# A Visual-Polar texel: the mode's description of its buffers (vp_* are texels) gives --texel.
expect 0 "export a Visual-Polar golden" -- "$FOVREF" golden export cornell-visual-polar-basic "$TMP/vp_gold" -q
cp -r "$TMP/vp_gold" "$TMP/vp_cand"
bump "$TMP/vp_cand/f000_vp_color.pfm" 30 4
expect 1 "a Visual-Polar texel changed" -- "$FOVREF" diff "$TMP/vp_gold" "$TMP/vp_cand"
contains "buffer 'vp_color'" "names the Visual-Polar buffer"
contains "--texel 30,4" "the Visual-Polar texel"
CMD=$(grep -o "explain it: fovref probe.*" <<<"$OUT" | sed 's/^explain it: fovref //')
# shellcheck disable=SC2086
expect 0 "the printed Visual-Polar probe command runs" -- "$FOVREF" $CMD
contains "texel (30, 4)" "explains that texel"
finish
