# Koskela's Visual-Polar resolve and blur ramp, stage-isolated on the goldens' own inputs: the
# phi-mip resolve (gaze at the centre, off centre), the bilinear resolve with the gaze off screen
# (checker-room-visual-polar-basic, blur off: its resolve writes final), and the two blur passes.
# Injected bugs: phi clamped like rho instead of wrapped at 2 pi (vp_resolve); the weights
# divided by sqrt(2 pi) sigma instead of renormalised over the taps (blur_ramp).
for case in cornell-visual-polar checker-room-visual-polar cornell-visual-polar-basic \
  checker-room-visual-polar-basic; do
  run_pass vp_resolve "$case" vulkan resolve
done
for case in cornell-visual-polar checker-room-visual-polar cornell-visual-polar-basic; do
  run_pass blur_ramp "$case" vulkan blur_horizontal
done
expect 2 "the blur ramp on a case without it" -- "$CLIENT" --lavapipe blur_ramp \
  g_checker-room-visual-polar-basic v_blur_ramp_none
contains "no blur_horizontal and blur_vertical stages" "a clear message"
