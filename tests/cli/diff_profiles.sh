# The GPU profiles cover every buffer family (issue 29): a fake port of cornell-cfov, kfr, a TAA
# case and a BMFR case - a few ulps of noise in every value buffer - passes --profile gpu-rt and
# gpu-raster; one wrong texel in an intermediate stage fails that stage first, and the diff names
# the probe of that texel. A misspelt buffer or a pattern that matches nothing in --tolerance or
# --require is an error naming the nearest names; a pattern applies to its family.
source "$(dirname "$0")/lib.bash"
PY=$(command -v /usr/bin/python3 || command -v python3)
cd "$TMP" || exit 1
# port CASE ULPS [--wrong BUFFER:FRAME:X:Y:VALUE]: the golden bundle g_CASE and a fake port c_CASE
port() {
  local case=$1; shift
  [ -d "g_$case" ] || "$FOVREF" golden export "$case" "g_$case" -q || { echo "FAIL: export $case"; failures=$((failures + 1)); }
  rm -rf "c_$case"
  "$PY" "$SRC/tests/cli/fake_port.py" "g_$case" "c_$case" "$@" || { echo "FAIL: fake port $case"; failures=$((failures + 1)); }
}
for case in cornell-cfov cornell-kfr checker-room-cfov-taa-clamp-buffer cornell-pathtrace-bmfr cornell-visual-polar; do
  port "$case" 2
  for profile in gpu-rt gpu-raster; do
    expect 0 "$case, 2 ulps everywhere, --profile $profile" -- "$FOVREF" diff "g_$case" "c_$case" --profile "$profile"
  done
  expect 1 "$case, 2 ulps, bit-exact" -- "$FOVREF" diff "g_$case" "c_$case"
done
# One wrong texel in the log-polar shading: lp_shade fails first, the probe names the texel
port cornell-cfov 2 --wrong lp_color:0:20:40:5
expect 1 "one wrong lp_color texel" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov --profile gpu-rt
contains "first failing stage: lp_shade, buffer 'lp_color', frame 0: 1 pixel(s) out of tolerance" "lp_shade fails first"
contains "explain it: fovref probe --scene cornell --mode cfov --width 80 --height 45 --frame 0 --texel 20,40" "the probe of the texel"
# BMFR: one pixel with wrong accept bits fails phase I first (the 1-spp buffers allow a share of pixels)
port cornell-pathtrace-bmfr 2 --wrong bmfr_accept:1:30:20:5
expect 1 "one wrong accept mask" -- "$FOVREF" diff g_cornell-pathtrace-bmfr c_cornell-pathtrace-bmfr --profile gpu-rt
contains "first failing stage: bmfr_accumulate_noisy, buffer 'bmfr_accept', frame 1" "phase I fails first"
# Names and patterns in --tolerance and --require
port cornell-cfov 2
expect 2 "a misspelt --tolerance" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov --tolerance gbuffer_veiw_depth:ulp=4
contains "the golden has no buffer 'gbuffer_veiw_depth' (nearest: " "nearest names"
expect 2 "a pattern that matches nothing" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov --tolerance 'vp_*:ulp=4'
contains "the pattern 'vp_*' matches no buffer of the golden (it has: lp_* " "the golden's families"
expect 1 "bit-exact fails on 2 ulps" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov
expect 0 "a pattern covers its family" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov --tolerance 'lp_*:ulp=2' --tolerance 'gaze_*:ulp=2' --tolerance 'final:ulp=2' --tolerance 'ray_positions:ulp=2' --tolerance 'resolve_*:ulp=2'
expect 2 "--require with a misspelt name" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov --require lp_colour
contains "--require: the golden has no buffer 'lp_colour' (nearest: lp_color" "nearest"
expect 0 "--require with a pattern" -- "$FOVREF" diff g_cornell-cfov c_cornell-cfov --profile gpu-rt --require 'lp_gbuffer_*,final'
finish
