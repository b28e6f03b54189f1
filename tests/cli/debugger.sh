# `fovref probe --debugger gdb` prints a command line that stops in each pass's per-pixel function
# at the probed pixel; gdb (batch mode) runs it and must stop in the named function, at that
# pixel, with a source line. Runs where the binary can be stepped through (-O0 -g: the debug
# preset, which the test command builds); elsewhere it checks the printed command only.
source "$(dirname "$0")/lib.bash"

expect 0 "probe --debugger gdb (raster)" -- "$FOVREF" probe --scene cornell --mode basic --param primary=raster --width 64 --height 36 --pixel 30,20 --debugger gdb
contains "[debugger] stop at this pixel" "debugger section"
contains "primary_visibility: fovref::raster_fragment" "names the rasterizer's per-pixel function"
contains "shade_direct: fovref::shade_basic_pixel" "names the shading pass's per-pixel function"
contains "-ex 'break fovref::raster_fragment if x == 30 && y == 20'" "conditional breakpoint on the pixel"
contains "--first-frame 0 --frames 1" "renders only the probed frame"
RASTER_CMD=$(grep -o 'debug it: .*' <<<"$OUT" | sed 's/^debug it: //')
expect 0 "probe --debugger gdb (ray, frame 1)" -- "$FOVREF" probe --scene cornell --mode basic --width 64 --height 36 --pixel 12,30 --frame 1 --time-step 0.5 --debugger gdb
contains "--first-frame 1 --frames 1" "frame 1 alone"
RAY_CMD=$(grep -o 'debug it: .*' <<<"$OUT" | sed 's/^debug it: //')
expect 0 "probe --debugger lldb" -- "$FOVREF" probe --scene cornell --mode ground-truth --width 16 --height 9 --pixel 3,4 --debugger lldb
contains "lldb -o 'breakpoint set -n fovref::raycast_gbuffer_pixel -c \"x == 3 && y == 4\"'" "lldb breakpoint"
contains "fovref::ground_truth_pixel" "ground truth's per-pixel function"
expect 2 "a mode without per-pixel functions" -- "$FOVREF" probe --scene cornell --mode splat --width 16 --height 9 --pixel 3,4 --debugger gdb
contains "names no per-pixel functions" "clear message"
expect 2 "an unknown debugger" -- "$FOVREF" probe --scene cornell --mode basic --width 16 --height 9 --pixel 3,4 --debugger windbg

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
