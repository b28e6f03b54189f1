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

expect 0 "bench foveation (small)" -- "$FOVREF" bench foveation --scene cornell --width 64 --height 36 --repeats 1 -q
contains "cfov+lerp" "bench rows"
contains "speed-up" "bench columns"
expect 2 "bench foveation: unknown mode" -- "$FOVREF" bench foveation --mode nope --width 16 --height 9
finish
