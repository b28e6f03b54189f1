# `fovref probe --debugger gdb` prints a command line that stops in each pass's per-pixel function
# where the probed pixel (or texel) is computed: at the coordinates that function receives (the
# pixel, the texels pass 2 reads, the pixel within its eye, the BMFR block), in the probed frame
# and stage. gdb (batch mode) runs it, for every kind of mode, and every stop must be in the named
# function, at those coordinates, frame and stage, with a source line (tests/cli/gdb_stops.py).
# Runs where the binary can be stepped through (-O0 -g: the debug preset, which the test command
# builds); elsewhere it checks the printed commands only.
source "$(dirname "$0")/lib.bash"

expect 0 "probe --debugger gdb (raster)" -- "$FOVREF" probe --scene cornell --mode basic --param primary=raster --width 64 --height 36 --pixel 30,20 --debugger gdb
contains "[debugger] stop where this is computed" "debugger section"
contains "primary_visibility: fovref::raster_fragment" "names the rasterizer's per-pixel function"
contains "shade_direct: fovref::shade_basic_pixel" "names the shading pass's per-pixel function"
contains "-ex 'break fovref::raster_fragment if x == 30 && y == 20 && fovref::debugger_position.frame == 0 && fovref::debugger_position.stage == 0'" "conditional breakpoint on the pixel, frame and stage"
contains "--first-frame 0 --frames 1" "renders only the probed frame"
RASTER_CMD=$(grep -o 'debug it: .*' <<<"$OUT" | sed 's/^debug it: //')
expect 0 "probe --debugger gdb (ray, frame 1)" -- "$FOVREF" probe --scene cornell --mode basic --width 64 --height 36 --pixel 12,30 --frame 1 --time-step 0.5 --debugger gdb
contains "--first-frame 1 --frames 1" "frame 1 alone"
RAY_CMD=$(grep -o 'debug it: .*' <<<"$OUT" | sed 's/^debug it: //')
expect 0 "probe --debugger lldb" -- "$FOVREF" probe --scene cornell --mode ground-truth --width 16 --height 9 --pixel 3,4 --debugger lldb
contains "lldb -o 'breakpoint set -n fovref::raycast_gbuffer_pixel -c \"x == 3 && y == 4 && fovref::debugger_position.frame == 0 && fovref::debugger_position.stage == 0\"'" "lldb breakpoint"
contains "fovref::ground_truth_pixel" "ground truth's per-pixel function"
expect 2 "a mode without per-pixel functions" -- "$FOVREF" probe --scene cornell --mode splat --width 16 --height 9 --pixel 3,4 --debugger gdb
contains "names no per-pixel functions" "clear message"
expect 2 "an unknown debugger" -- "$FOVREF" probe --scene cornell --mode basic --width 16 --height 9 --pixel 3,4 --debugger windbg

# The texels a foveated pixel reads, not the pixel: cfov's pixel (180, 346) of 640x360 reads the
# log-polar texels (75..76, 215..216); the gaze passes do not compute it.
expect 0 "probe --debugger (cfov)" -- "$FOVREF" probe --scene cornell --mode cfov --width 640 --height 360 --pixel 180,346 --debugger gdb -q
contains "lp_trace: fovref::lp_gbuffer_texel at x, y = (75..76, 215..216) (lp_ texels)" "the texels pass 2 reads"
contains "break fovref::lp_gbuffer_texel if x >= 75 && x <= 76 && y >= 215 && y <= 216 && fovref::debugger_position.frame == 0 && fovref::debugger_position.stage == 0" "conditioned on the texels"
contains "gaze_trace: fovref::gaze_gbuffer_pixel: no stop (this pixel reads no gaze_ texel)" "the gaze pass is left out, saying why"
contains "resolve: fovref::resolve_pixel at x, y = (180, 346) (the pixel)" "pass 2 at the pixel"
expect 0 "probe --debugger (kfr)" -- "$FOVREF" probe --scene cornell --mode kfr --width 160 --height 90 --pixel 40,40 --debugger gdb -q
for f in "gbuffer_raster: fovref::raster_fragment" "lp_sample: fovref::deferred_gbuffer_texel" "lp_shade: fovref::shade_basic_pixel" "internal_aa: fovref::internal_aa_texel" "resolve: fovref::resolve_mip_pixel" "post_aa: fovref::post_aa_cached_pixel"; do
  contains "$f at" "kfr's passes: $f"
done
checks=$((checks + 1))
if grep -q "lp_trace\|gaze_trace" <<<"$OUT"; then echo "FAIL: kfr lists passes it does not have"; failures=$((failures + 1)); fi
expect 0 "--texel with --debugger" -- "$FOVREF" probe --scene cornell --mode cfov --width 160 --height 90 --texel 20,30 --debugger gdb -q
contains "lp_trace: fovref::lp_gbuffer_texel at x, y = (20, 30) (lp_ texel)" "stops at the texel"
contains "resolve: fovref::resolve_pixel: no stop (a screen pass" "screen passes left out"
expect 0 "probe --debugger, TAA on frame 2" -- "$FOVREF" probe --scene cornell --mode basic --param taa=depth --width 32 --height 18 --pixel 5,6 --frame 2 --debugger gdb -q
contains "--frames 3" "frames 0 .. 2 run"
contains "x == 5 && y == 6 && fovref::debugger_position.frame == 2 && fovref::debugger_position.stage == 2" "TAA stops in frame 2 only"

# Run the printed commands in gdb's batch mode where this binary is the one they name.
if ! grep -q -- "--args $FOVREF " <<<"$RASTER_CMD" && ! grep -q -- "--args $(readlink -f "$FOVREF") " <<<"$RASTER_CMD"; then
  echo "SKIPPED: gdb run (this build is not -O0 -g; the debug preset's suite runs it)"
  finish
  exit $?
fi
if ! command -v gdb >/dev/null; then
  echo "FAIL: gdb is not installed (tools/scripts/setup.sh installs it)"; exit 1
fi
cd "$TMP" || exit 1
# gdb_stops WHAT PROBE_ARGS...: the probe's breakpoints run under gdb; every stop checked.
gdb_stops() {
  local what=$1; shift
  expect 0 "probe --debugger --json ($what)" -- "$FOVREF" probe "$@" --debugger gdb --json -q
  printf '%s\n' "$OUT" >"$TMP/probe.json"
  expect 0 "gdb stops where the probe says ($what)" -- python3 "$SRC/tests/cli/gdb_stops.py" "$TMP/probe.json" "$TMP"
  echo "gdb, $what: $(tail -1 <<<"$OUT")"
}
gdb_stops "cfov, log-polar texels" --scene cornell --mode cfov --width 160 --height 90 --pixel 40,85
gdb_stops "cfov, gaze buffer" --scene cornell --mode cfov --width 160 --height 90 --pixel 80,45
gdb_stops "cfov, --texel" --scene cornell --mode cfov --width 160 --height 90 --texel 20,30
gdb_stops "kfr" --scene cornell --mode kfr --width 160 --height 90 --pixel 40,40
gdb_stops "fov + TAA, frame 1" --scene cornell --mode fov --param taa=depth --width 96 --height 54 --pixel 10,50 --frame 1
gdb_stops "stereo-lp + TAA, right eye, frame 1" --scene cornell --mode stereo-lp --param taa=depth --width 128 --height 48 --pixel 100,30 --frame 1
gdb_stops "pathtrace + BMFR, frame 1" --scene cornell --mode pathtrace --param denoise=bmfr --width 64 --height 36 --pixel 40,20 --frame 1
gdb_stops "visual-polar (BMFR), frame 1" --scene cornell --mode visual-polar --width 64 --height 36 --pixel 20,12 --frame 1
gdb_stops "visual-polar-basic" --scene cornell --mode visual-polar-basic --width 64 --height 36 --pixel 50,30
# -batch ends gdb after the last command; after `run` stops, show where and the pixel.
batch() { sed "s/^gdb -q /gdb -q -batch /; s/ -ex run / -ex run $1 /" <<<"$2"; }
expect 0 "gdb stops in the rasterizer" -- bash -c "$(batch "-ex 'print x' -ex 'print y'" "$RASTER_CMD")"
contains "Breakpoint 1, fovref::raster_fragment (" "stops in raster_fragment"
contains "x=30, y=20" "at the pixel"
grep -qE "at [^ ]*ref/raster/rasterizer\.cpp:[0-9]+" <<<"$OUT" || { echo "FAIL: no source line"; echo "$OUT" | tail -5; failures=$((failures + 1)); }
checks=$((checks + 1))
contains "\$1 = 30" "x is the pixel's"
expect 0 "gdb continues to the shading pass" -- bash -c "$(batch "-ex continue -ex 'print x' -ex 'print y' -ex 'print frame'" "$RAY_CMD")"
contains "Breakpoint 1, fovref::raycast_gbuffer_pixel (" "first the ray caster"
contains "Breakpoint 2, fovref::shade_basic_pixel (" "then the shading pass"
grep -qE "at [^ ]*ref/trace/shade_basic\.cpp:[0-9]+" <<<"$OUT" || { echo "FAIL: no source line in shade_basic.cpp"; echo "$OUT" | tail -5; failures=$((failures + 1)); }
checks=$((checks + 1))
contains "\$3 = 1" "in frame 1"
finish
