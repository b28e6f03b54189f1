// Meng's post anti-aliasing (shaders/post_aa.comp): the buffer before it in the screen chain
// (lerp_filtered, else taa_color, else resolved) in, the post_aa stage's buffer (`final`) out,
// on every frame that has it. The gaze and R come from the case's map (log_polar_map_block of
// passes/resolve.cpp: `gaze`, default the centre; R from `L`, kfr's default the farthest
// corner); the weights are computed in the shader with its native exp.
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"
#include "tools/clients/vulkan/passes/lp_map.h"

namespace fovref_client {

namespace {

/// The buffer post-AA reads in `frame`: the one before it in the screen chain.
std::string input_of(const json& frame) {
    for (const char* name : {"lerp_filtered", "taa_color", "resolved"})
        if (PassContext::has(frame, name)) return name;
    throw std::runtime_error("frame " + std::to_string(frame.at("frame").get<int>()) +
                             " has a post_aa stage but none of lerp_filtered, taa_color, "
                             "resolved to read");
}

int run(PassContext& ctx) {
    return ctx.each_frame(
        "post_aa",
        [&](const json& frame, const std::string& output) {
            Image in = ctx.read(frame, input_of(frame));
            if (in.channels > 4)
                throw std::runtime_error("more than 4 channels in " + input_of(frame));
            std::vector<std::uint32_t> map =
                log_polar_map_block(ctx, frame, in.width, in.height, 0, 0);
            Image result{in.width, in.height, in.channels,
                         std::vector<float>(in.data.size(), 0.0f)};
            const std::int32_t push[3] = {in.width, in.height, in.channels};
            ctx.dispatch("post_aa", {host(map), host(in.data), host(result.data)}, push,
                         sizeof push, groups(in.width, 16), groups(in.height, 16));
            ctx.write(frame.at("frame").get<int>(), output, result);
        },
        "the bundle has no post_aa stage");
}

const bool registered = register_pass(
    {"post_aa",
     "Meng's post anti-aliasing: resolved (or taa_color, lerp_filtered) -> the post_aa "
     "stage's buffer",
     "the kernel's step count truncated by int() instead of rounded up (eta 2 smaller)", run});

}  // namespace
}  // namespace fovref_client
