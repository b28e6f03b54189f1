# BMFR's fit (phase II): one workgroup per block of the frame's shifted grid, features scaled to
# the block's range and a Householder QR with parallel reductions in shared memory, the matrix in
# binary16 (cornell) or binary32 (checker-room, blocks mirrored at the borders); on a
# Visual-Polar buffer (staircase blocks, rows wrapping on phi). Injected bug: the grid shifted by
# the previous frame's offset.
run_pass bmfr_fit cornell-pathtrace-bmfr vulkan bmfr_fit
run_pass bmfr_fit checker-room-pathtrace-bmfr-float vulkan bmfr_fit
run_pass bmfr_fit cornell-visual-polar vulkan bmfr_fit
export_case cornell-basic
expect 2 "bmfr_fit on a bundle without BMFR" -- "$CLIENT" --lavapipe bmfr_fit g_cornell-basic v_bmfr_fit_basic
contains "no bmfr_fit stage" "a clear message"
