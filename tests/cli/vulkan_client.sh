# The Vulkan compute port (tools/clients/vulkan/, issue 30): Lund's Gaussian lerp and Meng's
# internal AA as GLSL compute shaders on Mesa's lavapipe, each fed the golden's own input
# buffers (stage-isolated). The diff passes on two cases per pass (the lerp: a composite kernel
# foveation with an off-centre gaze, a TAA sequence followed by the lerp; internal AA: kfr, kfr
# with TAA), and fails, naming the stage and a pixel, when the shader is built with an injected
# porting bug (the lerp: the pixel's corner for its centre; internal AA: v clamped, not wrapped).
source "$(dirname "$0")/lib.bash"
CLIENT=$(dirname "$FOVREF")/vk_passes
if [ ! -x "$CLIENT" ]; then
  echo "FAIL: $CLIENT was not built: Vulkan or glslc is missing (apt-get install libvulkan-dev"
  echo "      glslc mesa-vulkan-drivers, which tools/scripts/setup.sh does), then reconfigure"
  exit 1
fi
cd "$TMP" || exit 1
# pass CASE PROFILE STAGE: the pass on CASE, the diff with PROFILE, the injected bug caught
run_pass() {
  local pass=$1 case=$2 profile=$3 stage=$4
  [ -d "g_$case" ] || expect 0 "export $case" -- "$FOVREF" golden export "$case" "g_$case" -q
  expect 0 "$pass on lavapipe ($case)" -- "$CLIENT" --lavapipe "$pass" "g_$case" "v_$case"
  contains "on llvmpipe" "lavapipe named"
  expect 0 "diff --profile $profile ($case)" -- "$FOVREF" diff "g_$case" "v_$case" --profile "$profile" --json "$case.json"
  echo "$pass, $case: $(python3 -c "
import json; r = json.load(open('$case.json'))
l = [b for b in r['buffers'] if b['stage'] == '$stage' and 'max_abs_error' in b]
print(len(l), 'frames compared, max |error|', max(b['max_abs_error'] for b in l),
      ', max ulp', max(b['max_ulp'] for b in l))")"
  expect 0 "$pass with an injected bug ($case)" -- "$CLIENT" --lavapipe --bug "$pass" "g_$case" "b_$case"
  expect 1 "the diff catches it ($case)" -- "$FOVREF" diff "g_$case" "b_$case" --profile "$profile"
  contains "first failing stage: $stage, buffer " "names the stage"
  contains "first failing pixel (" "and a pixel"
}
run_pass lerp textured-room-ckfov-gaze-lerp gpu-rt gaussian_lerp
run_pass lerp checker-room-cfov-taa-clamp-screen gpu-rt gaussian_lerp
run_pass internal_aa checker-room-kfr gpu-raster internal_aa
run_pass internal_aa checker-room-kfr-taa-depth gpu-raster internal_aa
checks=$((checks + 1))
grep -q '"float_controls"' "v_textured-room-ckfov-gaze-lerp/vk_passes.json" ||
  { echo "FAIL: the dump records no float controls"; failures=$((failures + 1)); }
expect 0 "a bundle without the passes" -- "$FOVREF" golden export cornell-basic g_basic -q
expect 2 "the lerp on it" -- "$CLIENT" --lavapipe lerp g_basic v_basic
contains "no gaussian_lerp stage" "a clear message"
expect 2 "internal AA on it" -- "$CLIENT" --lavapipe internal_aa g_basic v_basic
contains "no lp_color_aa" "a clear message"
finish
