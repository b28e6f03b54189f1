# The end-to-end composite-foveation frame (passes/frame.cpp): rendered from the bundle's exported
# scene, not from golden intermediates, and every stage's buffers diffed (--require all): cfov on
# cornell and checker-room (textured: the procedural checker is a PFM), kfov on cornell.
# Injected bug: the texel centre without +1/2 in the log-polar ray generation.
#
# run_frame CASE: run_pass's checks on a bundle with its scene, every buffer required; the bug's
# first failing buffer is an id buffer (the shifted texels hit other triangles).
run_frame() {
  local case=$1
  # the pass needs the scene (--with-scene): re-export a bundle another fragment made without it
  [ -f "g_$case/scene/scene.json" ] || rm -rf "g_$case"
  export_case "$case" --with-scene
  expect 0 "frame on lavapipe ($case)" -- "$CLIENT" --lavapipe frame "g_$case" "v_frame_$case"
  contains "on llvmpipe" "lavapipe named"
  expect 0 "every buffer of the frame, --profile vulkan ($case)" -- "$FOVREF" diff "g_$case" "v_frame_$case" --profile vulkan --require all --json "frame-$case.json"
  echo "frame, $case: $(python3 -c "
import json; r = json.load(open('frame-$case.json'))
l = [b for b in r['buffers'] if 'max_abs_error' in b]
print(len(l), 'value buffers compared, max |error|', max(b['max_abs_error'] for b in l))")"
  expect 0 "frame with an injected bug ($case)" -- "$CLIENT" --lavapipe --bug frame "g_$case" "b_frame_$case"
  expect 1 "the diff catches it ($case)" -- "$FOVREF" diff "g_$case" "b_frame_$case" --profile vulkan
  contains "first failing stage: lp_trace, buffer " "names the stage"
  checks=$((checks + 1))
  python3 "$FRAGMENTS/bug_changed.py" "g_$case" "v_frame_$case" "b_frame_$case" <<<"$OUT" ||
    { echo "FAIL: the pixel named is not one the bug changed (frame, $case)"; failures=$((failures + 1)); }
}
for case in cornell-cfov checker-room-cfov cornell-kfov; do run_frame "$case"; done
# a bundle exported without its scene: a clear message naming the option
expect 0 "export without the scene" -- "$FOVREF" golden export cornell-cfov g_frame_noscene --raw-copies -q
expect 2 "the frame pass on it" -- "$CLIENT" --lavapipe frame g_frame_noscene v_frame_noscene
contains "--with-scene" "names the export option"
