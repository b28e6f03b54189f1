# The Vulkan compute port (tools/clients/vulkan/, issue 30): Lund's Gaussian lerp as a GLSL
# compute shader on Mesa's lavapipe, fed each golden's own input buffer (stage-isolated). The
# diff passes --profile gpu-rt on two cases (a composite kernel foveation with an off-centre gaze;
# a TAA sequence followed by the lerp), and fails, naming the stage and a pixel, when the shader
# is built with an injected porting bug (the pixel's corner for its centre).
source "$(dirname "$0")/lib.bash"
CLIENT=$(dirname "$FOVREF")/vk_passes
if [ ! -x "$CLIENT" ]; then
  echo "FAIL: $CLIENT was not built: Vulkan or glslc is missing (apt-get install libvulkan-dev"
  echo "      glslc mesa-vulkan-drivers, which tools/scripts/setup.sh does), then reconfigure"
  exit 1
fi
cd "$TMP" || exit 1
for case in textured-room-ckfov-gaze-lerp checker-room-cfov-taa-clamp-screen; do
  expect 0 "export $case" -- "$FOVREF" golden export "$case" "g_$case" -q
  expect 0 "the lerp on lavapipe ($case)" -- "$CLIENT" --lavapipe lerp "g_$case" "v_$case"
  contains "on llvmpipe" "lavapipe named"
  expect 0 "diff --profile gpu-rt ($case)" -- "$FOVREF" diff "g_$case" "v_$case" --profile gpu-rt --json "$case.json"
  echo "$case: $(python3 -c "
import json; r = json.load(open('$case.json'))
l = [b for b in r['buffers'] if b['stage'] == 'gaussian_lerp' and 'max_abs_error' in b]
print(len(l), 'frames compared, max |error|', max(b['max_abs_error'] for b in l),
      ', max ulp', max(b['max_ulp'] for b in l))")"
  expect 0 "the lerp with an injected bug ($case)" -- "$CLIENT" --lavapipe --bug lerp "g_$case" "b_$case"
  expect 1 "the diff catches it ($case)" -- "$FOVREF" diff "g_$case" "b_$case" --profile gpu-rt
  contains "first failing stage: gaussian_lerp, buffer " "names the stage"
  contains "first failing pixel (" "and a pixel"
done
checks=$((checks + 1))
grep -q '"float_controls"' "v_textured-room-ckfov-gaze-lerp/vk_passes.json" ||
  { echo "FAIL: the dump records no float controls"; failures=$((failures + 1)); }
expect 0 "a bundle without the lerp" -- "$FOVREF" golden export cornell-basic g_basic -q
expect 2 "vk_passes on it" -- "$CLIENT" --lavapipe lerp g_basic v_basic
contains "no gaussian_lerp stage" "a clear message"
finish
