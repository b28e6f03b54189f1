// Meng's internal AA in the log-polar buffer (shaders/internal_aa.comp): lp_color and lp_valid
// in, lp_color_aa out, on every frame that has lp_color_aa.
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

int run(PassContext& ctx) {
    return ctx.each_frame(
        "internal_aa",
        [&](const json& frame, const std::string& output) {
            Image colour = ctx.read(frame, "lp_color");
            Image valid = ctx.read(frame, "lp_valid");
            Image result{colour.width, colour.height, colour.channels,
                         std::vector<float>(colour.data.size(), 0.0f)};
            const std::int32_t push[3] = {colour.width, colour.height, colour.channels};
            ctx.dispatch("internal_aa", {host(colour.data), host(valid.data), host(result.data)},
                         push, sizeof push, groups(colour.width, 8), groups(colour.height, 8));
            ctx.write(frame.at("frame").get<int>(), output, result);
        },
        "the bundle has no internal_aa stage (lp_color_aa)");
}

const bool registered = register_pass(
    {"internal_aa", "Meng's internal AA in the log-polar buffer: lp_color, lp_valid -> lp_color_aa",
     "v clamped at the buffer's edges, not wrapped", run});

}  // namespace
}  // namespace fovref_client
