# BMFR's per-pixel phases, stage-isolated, each frame's history the golden's previous frame:
# phase I (reprojection, accept bits, the noisy accumulation), the weighted sum of the golden's
# fit, phase III, the remodulation and the authors' YCoCg TAA, on cornell (binary16 fit storage)
# and checker-room (binary32, emission kept apart). Injected bugs: phase I's reprojected pixel
# without the -1/2 of the pixel centre; the weighted sum on the previous frame's block grid;
# phase III with phase I's blend factor 1 / (spp + 1); the remodulation without the albedo's
# floor 0.01; the TAA's YCoCg inverse without its /4.
for bmfr_case in cornell-pathtrace-bmfr checker-room-pathtrace-bmfr-float; do
  run_pass bmfr_accumulate "$bmfr_case" vulkan bmfr_accumulate_noisy
  run_pass bmfr_weighted_sum "$bmfr_case" vulkan bmfr_weighted_sum
  run_pass bmfr_accumulate_filtered "$bmfr_case" vulkan bmfr_accumulate_filtered
  run_pass bmfr_taa "$bmfr_case" vulkan bmfr_taa
done
# The remodulation's bug shows where the albedo is below 0.01 (cornell's sky and black pixels);
# checker-room's albedo is at least 0.0375, so it checks the correct shader only.
run_pass bmfr_remodulate cornell-pathtrace-bmfr vulkan bmfr_remodulate
expect 0 "bmfr_remodulate on lavapipe (checker-room)" -- "$CLIENT" --lavapipe bmfr_remodulate g_checker-room-pathtrace-bmfr-float v_bmfr_remodulate_checker
expect 0 "diff --profile vulkan (bmfr_remodulate, checker-room)" -- "$FOVREF" diff g_checker-room-pathtrace-bmfr-float v_bmfr_remodulate_checker --profile vulkan --require bmfr_display
# A bundle without BMFR: one clear line per pass
export_case cornell-basic
for bmfr_pass in bmfr_accumulate:bmfr_accumulate_noisy bmfr_weighted_sum:bmfr_weighted_sum \
  bmfr_accumulate_filtered:bmfr_accumulate_filtered bmfr_remodulate:bmfr_remodulate bmfr_taa:bmfr_taa; do
  expect 2 "${bmfr_pass%%:*} on a bundle without BMFR" -- "$CLIENT" --lavapipe "${bmfr_pass%%:*}" g_cornell-basic "v_${bmfr_pass%%:*}_basic"
  contains "no ${bmfr_pass##*:} stage" "a clear message"
done
