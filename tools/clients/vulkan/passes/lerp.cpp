// Lund's Gaussian lerp (shaders/gaussian_lerp.comp): input the buffer before it (taa_color with
// TAA, else resolved), output the gaussian_lerp stage's buffer; the gaze from the case's `gaze`
// parameter (default the screen centre); `gaze_track` is refused.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

struct LerpParameters {
    std::int32_t width, height, channels;
    float gaze_x, gaze_y, ramp_start, ramp_span;
};

int run(PassContext& ctx) {
    const int width = ctx.width(), height = ctx.height();
    if (!ctx.param("gaze_track", "").empty())
        throw std::runtime_error("lerp: gaze_track is not read yet (give a case with `gaze`)");
    float gaze_x = 0.5f * static_cast<float>(width), gaze_y = 0.5f * static_cast<float>(height);
    const std::string gaze = ctx.param("gaze", "");
    if (!gaze.empty()) std::sscanf(gaze.c_str(), "%f,%f", &gaze_x, &gaze_y);
    // The ramp: D / 6 to the farthest corner (computed once on the host, as a renderer would)
    const float diagonal = std::sqrt(static_cast<float>(width * width + height * height));
    float farthest = 0.0f;
    for (const float cx : {0.0f, static_cast<float>(width)})
        for (const float cy : {0.0f, static_cast<float>(height)})
            farthest = std::max(farthest, std::hypot(cx - gaze_x, cy - gaze_y));
    return ctx.each_frame(
        "gaussian_lerp",
        [&](const json& frame, const std::string& output) {
            Image in =
                ctx.read(frame, PassContext::has(frame, "taa_color") ? "taa_color" : "resolved");
            Image result{in.width, in.height, in.channels,
                         std::vector<float>(in.data.size(), 0.0f)};
            const LerpParameters push{width,
                                      height,
                                      in.channels,
                                      gaze_x,
                                      gaze_y,
                                      diagonal / 6.0f,
                                      farthest - diagonal / 6.0f};
            ctx.dispatch("gaussian_lerp", {host(in.data), host(result.data)}, &push, sizeof push,
                         groups(width, 8), groups(height, 8));
            ctx.write(frame.at("frame").get<int>(), output, result);
        },
        "the bundle has no gaussian_lerp stage");
}

const bool registered = register_pass(
    {"lerp", "Lund's Gaussian lerp: resolved (or taa_color) -> the gaussian_lerp stage's buffer",
     "pixel centre without +1/2", run});

}  // namespace
}  // namespace fovref_client
