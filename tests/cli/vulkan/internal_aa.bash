# Meng's internal AA: kfr, kfr with TAA. Injected bug: v clamped, not wrapped.
run_pass internal_aa checker-room-kfr vulkan internal_aa
run_pass internal_aa checker-room-kfr-taa-depth vulkan internal_aa
