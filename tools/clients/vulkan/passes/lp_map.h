// The case's log-polar map as the shaders see it (shaders/include/lp_map.glsl's LpMap block),
// built on the host once per frame (passes/resolve.cpp); shared by the resolve, stereo resolve
// and post-AA passes.
#pragma once

#include <cstdint>
#include <vector>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {

/// The map of `frame` (its gaze, R, L, r_G = d_px tan(a_G) with the frame's display distance,
/// G, the kernel, from the case's parameters) on a screen_width x screen_height screen (one
/// eye's in stereo) with a buffer_width x buffer_height buffer (0 x 0 when the pass reads only
/// the gaze and R), as LpMap's 31 words. Throws std::runtime_error naming a parameter it cannot
/// use.
std::vector<std::uint32_t> log_polar_map_block(const PassContext& ctx, const json& frame,
                                               int screen_width, int screen_height,
                                               int buffer_width, int buffer_height);

}  // namespace fovref_client
