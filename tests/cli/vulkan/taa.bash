# Lund's TAA, stage-isolated: each frame reads the golden's current colour and depth and its
# previous frame's output, age, depth and camera. Depth rejection and screen clamping in basic,
# buffer-space clamping and depth rejection (with the periphery rule) in cfov. Injected bug: the
# history's bilinear taps around p' instead of p' - 1/2 (half a pixel off; a moving camera
# needs it, so the static cases check the correct shader only).
run_pass taa checker-room-basic-taa-depth vulkan taa
run_pass taa checker-room-basic-taa-clamp-screen vulkan taa
run_pass taa checker-room-cfov-taa-clamp-buffer vulkan taa
run_pass taa checker-room-cfov-taa-depth vulkan taa
export_case checker-room-cfov-taa-static
expect 0 "taa on lavapipe (checker-room-cfov-taa-static)" -- "$CLIENT" --lavapipe taa g_checker-room-cfov-taa-static v_taa_static
expect 0 "diff --profile vulkan (taa, the stationary rule)" -- "$FOVREF" diff g_checker-room-cfov-taa-static v_taa_static --profile vulkan
export_case cornell-basic
expect 2 "taa on a bundle without TAA" -- "$CLIENT" --lavapipe taa g_cornell-basic v_taa_none
contains "no taa stage" "a clear message"
