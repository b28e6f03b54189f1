// BMFR's weighted sum, phase II (shaders/bmfr_weighted_sum.comp; docs/bmfr.md, "Weighted sum"),
// stage-isolated: per frame that has the bmfr_weighted_sum stage, the golden's bmfr_weights and
// bmfr_feature_range (the fit's, one texel per block of the frame's shifted grid),
// gbuffer_world_position and gbuffer_shading_normal in; bmfr_fitted out. Screen space only: a
// Visual-Polar bundle (vp_valid) is refused.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

constexpr int block_size = 32;
constexpr int weight_count = 30;  // 10 weights per colour channel
constexpr int range_count = 12;   // min of features 4..9, then their max

// Checks that `image` is width x height x channels, naming it otherwise.
void check_shape(const Image& image, int width, int height, int channels, const char* name) {
    if (image.width != width || image.height != height || image.channels != channels)
        throw std::runtime_error(
            std::string("bmfr_weighted_sum: ") + name + " is " + std::to_string(image.width) + "x" +
            std::to_string(image.height) + "x" + std::to_string(image.channels) + ", expected " +
            std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(channels));
}

// Evaluates one frame's fit at every pixel and writes bmfr_fitted.
void weighted_sum_frame(PassContext& ctx, const json& frame) {
    Image world = ctx.read(frame, "gbuffer_world_position");
    Image normal = ctx.read(frame, "gbuffer_shading_normal");
    Image weights = ctx.read(frame, "bmfr_weights");
    Image range = ctx.read(frame, "bmfr_feature_range");
    const int width = world.width, height = world.height;
    // The grid: (ceil(W / 32) + 1) x (ceil(H / 32) + 1) cells
    const int cells_x = (width + block_size - 1) / block_size + 1;
    const int cells_y = (height + block_size - 1) / block_size + 1;
    check_shape(normal, width, height, 3, "gbuffer_shading_normal");
    check_shape(weights, cells_x, cells_y, weight_count, "bmfr_weights");
    check_shape(range, cells_x, cells_y, range_count, "bmfr_feature_range");
    Image fitted{width, height, 3,
                 std::vector<float>(static_cast<std::size_t>(width) * height * 3, 0.0f)};
    const int index = frame.at("frame").get<int>();
    const std::int32_t push[5] = {width, height, cells_x, cells_y, index};
    ctx.dispatch("bmfr_weighted_sum",
                 {host(world.data), host(normal.data), host(weights.data), host(range.data),
                  host(fitted.data)},
                 push, sizeof push, groups(width, 8), groups(height, 8));
    ctx.write(index, "bmfr_fitted", fitted);
}

int run(PassContext& ctx) {
    ctx.require_bmfr_block_32("bmfr_weighted_sum");
    ctx.notes["precise"] =
        "the squares w^2, the feature scaling and the weighted sum (binary32 "
        "in the oracle's order, no contraction)";
    ctx.notes["bmfr_weighted_sum_features"] =
        "binary32, as the oracle's weighted sum reads them (binary16 storage is the fit's)";
    return ctx.each_frame(
        "bmfr_weighted_sum",
        [&](const json& frame, const std::string&) {
            if (PassContext::has(frame, "vp_valid"))
                throw std::runtime_error("Visual-Polar BMFR is not ported");
            weighted_sum_frame(ctx, frame);
        },
        "the bundle has no bmfr_weighted_sum stage (bmfr_fitted)");
}

const bool registered =
    register_pass({"bmfr_weighted_sum",
                   "BMFR's weighted sum: bmfr_weights, bmfr_feature_range, gbuffer_world_position, "
                   "gbuffer_shading_normal -> bmfr_fitted",
                   "the block grid's offset of the previous frame", run});

}  // namespace
}  // namespace fovref_client
