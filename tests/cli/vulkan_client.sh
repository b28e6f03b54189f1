# The Vulkan compute port (tools/clients/vulkan/, issue 30) on Mesa's lavapipe: every pass in
# tests/cli/vulkan/*.bash runs on golden bundles' own inputs (stage-isolated) and the diff passes
# with the port's tolerance profile; built with its injected porting bug, the diff fails and
# names the pass's stage and a pixel the bug changed.
source "$(dirname "$0")/lib.bash"
CLIENT=$(dirname "$FOVREF")/vk_passes
if [ ! -x "$CLIENT" ]; then
  echo "FAIL: $CLIENT was not built: Vulkan or glslc is missing (apt-get install libvulkan-dev"
  echo "      glslc mesa-vulkan-drivers, which tools/scripts/setup.sh does), then reconfigure"
  exit 1
fi
FRAGMENTS=$(cd "$(dirname "$0")/vulkan" && pwd)
cd "$TMP" || exit 1
# export CASE [golden export options]: the bundle g_CASE, once
export_case() {
  local case=$1
  shift
  [ -d "g_$case" ] || expect 0 "export $case" -- "$FOVREF" golden export "$case" "g_$case" --raw-copies -q "$@"
}
# run_pass PASS CASE PROFILE STAGE: the pass on CASE, the diff with PROFILE passes; with the
# injected bug the diff fails, naming STAGE and a pixel where the bug's output differs from
# the correct one
run_pass() {
  local pass=$1 case=$2 profile=$3 stage=$4
  export_case "$case"
  expect 0 "$pass on lavapipe ($case)" -- "$CLIENT" --lavapipe "$pass" "g_$case" "v_${pass}_$case"
  contains "on llvmpipe" "lavapipe named"
  expect 0 "diff --profile $profile ($pass, $case)" -- "$FOVREF" diff "g_$case" "v_${pass}_$case" --profile "$profile" --json "$pass-$case.json"
  echo "$pass, $case: $(python3 -c "
import json; r = json.load(open('$pass-$case.json'))
l = [b for b in r['buffers'] if b['stage'] == '$stage' and 'max_abs_error' in b]
d = [b for b in r['buffers'] if b['stage'] == '$stage' and 'decision_margin' in b]
print(len(l), 'buffers compared, max |error|', max(b['max_abs_error'] for b in l),
      ', max ulp', max(b['max_ulp'] for b in l), ';', len(d), 'decision buffers compared,',
      sum(b['near_threshold_flips'] for b in d), 'near-threshold flips')")"
  # the stage's threshold decisions that the port takes are written and compared as decisions
  checks=$((checks + 1))
  python3 -c "
import json, sys; r = json.load(open('$pass-$case.json'))
decisions = {'lp_valid', 'vp_valid', 'resolve_tap', 'resolve_mip_level', 'taa_age', 'bmfr_accept'}
missing = [b['name'] for b in r['buffers'] if b['stage'] == '$stage' and b['name'] in decisions
           and b['status'] != 'pass']
sys.exit('decision buffers not compared: ' + ', '.join(missing) if missing else 0)" ||
    { echo "FAIL: $pass, $case: its decisions are not compared"; failures=$((failures + 1)); }
  expect 0 "$pass with an injected bug ($case)" -- "$CLIENT" --lavapipe --bug "$pass" "g_$case" "b_${pass}_$case"
  expect 1 "the diff catches it ($pass, $case)" -- "$FOVREF" diff "g_$case" "b_${pass}_$case" --profile "$profile"
  contains "first failing stage: $stage, buffer " "names the stage"
  contains "first failing pixel (" "and a pixel"
  # the named pixel is one the bug changed: the correct and the buggy outputs differ there
  checks=$((checks + 1))
  python3 "$FRAGMENTS/bug_changed.py" "g_$case" "v_${pass}_$case" "b_${pass}_$case" <<<"$OUT" ||
    { echo "FAIL: the pixel named is not one the bug changed ($pass, $case)"; failures=$((failures + 1)); }
}
# VK_FRAGMENTS=taa,bmfr runs only those fragments (while working on a pass)
for fragment in "$FRAGMENTS"/*.bash; do
  name=$(basename "$fragment" .bash)
  [ -z "${VK_FRAGMENTS:-}" ] || [[ ",$VK_FRAGMENTS," == *",$name,"* ]] || continue
  # shellcheck source=/dev/null
  source "$fragment"
done
[ -n "${VK_FRAGMENTS:-}" ] && { finish; exit; }
# the dump's port.json (device, driver, float controls), which the diff prints
expect 0 "diff prints the port" -- "$FOVREF" diff g_textured-room-ckfov-gaze-lerp v_lerp_textured-room-ckfov-gaze-lerp --profile vulkan
contains "port: device: llvmpipe" "the device"
contains "port: float_controls: binary32 denormals" "the float controls"
expect 0 "a bundle without the passes" -- "$FOVREF" golden export cornell-basic g_basic -q
expect 2 "the lerp on it" -- "$CLIENT" --lavapipe lerp g_basic v_basic
contains "no gaussian_lerp stage" "a clear message"
expect 2 "internal AA on it" -- "$CLIENT" --lavapipe internal_aa g_basic v_basic
contains "no internal_aa stage" "a clear message"
expect 2 "an unknown pass" -- "$CLIENT" --lavapipe nosuchpass g_basic v_basic
contains "unknown pass 'nosuchpass'" "named"
finish
