# Lund's Gaussian lerp: a composite kernel foveation with an off-centre gaze; a TAA sequence
# followed by the lerp. Injected bug: the pixel's corner for its centre.
run_pass lerp textured-room-ckfov-gaze-lerp vulkan gaussian_lerp
run_pass lerp checker-room-cfov-taa-clamp-screen vulkan gaussian_lerp
