# Pass 2 of the log-polar modes: bilinear with the gaze buffer (cfov), with a kernel (kfov),
# with a polynomial kernel, L from the corners and an off-centre gaze (ckfov), and Meng's mip
# resolve after internal AA (kfr, raster-fed). Injected bug: v not wrapped at the buffer's seam.
run_pass resolve checker-room-cfov vulkan resolve
run_pass resolve cornell-kfov vulkan resolve
run_pass resolve checker-room-kfr vulkan resolve
run_pass resolve textured-room-ckfov-gaze-lerp vulkan resolve
# Gupta's stereo pass 2 with the barrel distortion. Injected bug: the distortion the wrong way.
run_pass stereo_resolve checker-room-stereo-lp-barrel vulkan resolve
# Without the barrel the injected bug changes nothing: the correct pass alone.
export_case cornell-stereo-lp
expect 0 "stereo_resolve on lavapipe (cornell-stereo-lp)" -- "$CLIENT" --lavapipe stereo_resolve g_cornell-stereo-lp v_stereo_resolve_cornell-stereo-lp
expect 0 "diff --profile vulkan (stereo_resolve, cornell-stereo-lp)" -- "$FOVREF" diff g_cornell-stereo-lp v_stereo_resolve_cornell-stereo-lp --profile vulkan --require final
# Meng's post-AA after the mip resolve (kfr) and after TAA. Injected bug: eta's steps truncated.
run_pass post_aa checker-room-kfr vulkan post_aa
run_pass post_aa checker-room-kfr-taa-depth vulkan post_aa
# Each pass refuses a bundle without its stage, naming what is missing.
export_case cornell-basic
expect 2 "resolve on a bundle without pass 2" -- "$CLIENT" --lavapipe resolve g_cornell-basic v_resolve_basic
contains "no resolve stage" "a clear message"
expect 2 "resolve on a stereo bundle" -- "$CLIENT" --lavapipe resolve g_cornell-stereo-lp v_resolve_stereo
contains "stereo_resolve pass" "names the pass to use"
expect 2 "stereo_resolve on a mono bundle" -- "$CLIENT" --lavapipe stereo_resolve g_cornell-kfov v_stereo_mono
contains "not stereo-lp's" "a clear message"
expect 2 "post_aa on a bundle without it" -- "$CLIENT" --lavapipe post_aa g_cornell-kfov v_post_aa_kfov
contains "no post_aa stage" "a clear message"
