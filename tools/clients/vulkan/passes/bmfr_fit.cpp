// BMFR's fit, phase II (shaders/bmfr_fit.comp; docs/bmfr.md, "Phase II: the fit"): per frame
// that has the bmfr_fit stage, bmfr_accumulated_noisy, gbuffer_world_position and
// gbuffer_shading_normal in, bmfr_weights (30 per block) and bmfr_feature_range (12 per block)
// out, one workgroup per block of the frame's shifted 32x32 grid. The block matrix lives in a
// scratch buffer in the case's bmfr_storage precision (binary16 by default, as the authors).
// On a Visual-Polar buffer (a bundle with vp_valid) it reads vp_gbuffer_* and vp_valid, and the
// host computes each column's row count n_c of the frame (passes/vp_rows.h: the triangular clip
// or BMFR's staircase; the shader takes each block column's phi height from them).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "tools/clients/vulkan/pass.h"
#include "tools/clients/vulkan/passes/vp_rows.h"

namespace fovref_client {
namespace {

struct FitParameters {
    std::int32_t width, height, cells_x, cells_y, frame, half_storage, visual_polar;
    float noise_amount, pivot_epsilon;
    std::int32_t jenkins_hash;  ///< the regularisation's hash: 1 Jenkins (default), 0 Wang
};

constexpr int block_size = 32;
constexpr int block_pixels = block_size * block_size;
constexpr int weight_count = 30;  // 10 weights per colour channel
constexpr int range_count = 12;   // min of features 4..9, then their max

// Whether the case stores the block matrix in binary16 (bmfr_storage, default half).
bool half_storage(const PassContext& ctx) {
    const std::string storage = ctx.param("bmfr_storage", "half");
    if (storage != "half" && storage != "float")
        throw std::runtime_error("bmfr_fit: bmfr_storage must be 'half' or 'float', got '" +
                                 storage + "'");
    return storage == "half";
}

// Fits every block of one frame and writes its two buffers.
void fit_frame(PassContext& ctx, const json& frame, bool half, bool jenkins) {
    const bool visual_polar = PassContext::has(frame, "vp_valid");
    const std::string gbuffer = visual_polar ? "vp_gbuffer_" : "gbuffer_";
    Image accumulated = ctx.read(frame, "bmfr_accumulated_noisy");
    Image world = ctx.read(frame, gbuffer + "world_position");
    Image normal = ctx.read(frame, gbuffer + "shading_normal");
    Image valid = visual_polar ? ctx.read(frame, "vp_valid") : Image{1, 1, 1, {1.0f}};
    const int width = accumulated.width, height = accumulated.height;
    for (const Image* image : {&world, &normal})
        if (image->width != width || image->height != height || image->channels != 3)
            throw std::runtime_error(
                "bmfr_fit: the G-buffer is not the size of "
                "bmfr_accumulated_noisy");
    // The grid: (ceil(W / 32) + 1) x (ceil(H / 32) + 1) cells, shifted per frame (Visual-Polar:
    // ceil(h / 32) rows of cells, and n_c per column for the staircase)
    const int cells_x = (width + block_size - 1) / block_size + 1;
    const int cells_y = (height + block_size - 1) / block_size + (visual_polar ? 0 : 1);
    const int frame_index = frame.at("frame").get<int>();
    std::vector<std::int32_t> column_rows(1, 0);
    if (visual_polar) column_rows = vp_column_rows(ctx, width, height, frame_index);
    const int blocks = cells_x * cells_y;
    Image weights{cells_x, cells_y, weight_count,
                  std::vector<float>(static_cast<std::size_t>(blocks) * weight_count, 0.0f)};
    Image range{cells_x, cells_y, range_count,
                std::vector<float>(static_cast<std::size_t>(blocks) * range_count, 0.0f)};
    // 1024 rows x 13 columns per block: 7 packed binary16 pairs or 13 binary32 words per row
    std::vector<std::uint32_t> matrix(static_cast<std::size_t>(blocks) * block_pixels *
                                      (half ? 7 : 13));
    const FitParameters push{
        width, height, cells_x,        cells_y, frame_index, half ? 1 : 0, visual_polar ? 1 : 0,
        0.01f, 1e-7f,  jenkins ? 1 : 0};
    ctx.dispatch("bmfr_fit",
                 {host(accumulated.data), host(world.data), host(normal.data), host(matrix),
                  host(weights.data), host(range.data), host(valid.data), host(column_rows)},
                 &push, sizeof push, static_cast<std::uint32_t>(cells_x),
                 static_cast<std::uint32_t>(cells_y));
    ctx.write(frame_index, "bmfr_weights", weights);
    ctx.write(frame_index, "bmfr_feature_range", range);
}

int run(PassContext& ctx) {
    ctx.require_bmfr_block_32("bmfr_fit");
    const bool half = half_storage(ctx);
    const std::string hash = ctx.param("bmfr_noise_hash", "jenkins");
    if (hash != "jenkins" && hash != "wang")
        throw std::runtime_error("bmfr_noise_hash must be 'jenkins' or 'wang', got '" + hash + "'");
    ctx.notes["bmfr_noise_hash"] = hash;
    ctx.notes["bmfr_storage"] = half ? "binary16 (packHalf2x16, clamped to +-65504)" : "binary32";
    ctx.notes["precise"] =
        "the regularisation noise and its addition, s + x_c^2 and s + u_c^2 (the oracle's "
        "products and sums without contraction); the reductions (binary32 trees, the oracle "
        "binary64 in row order) may contract";
    return ctx.each_frame(
        "bmfr_fit",
        [&](const json& frame, const std::string&) {
            fit_frame(ctx, frame, half, hash == "jenkins");
        },
        "the bundle has no bmfr_fit stage (bmfr_weights)");
}

const bool registered = register_pass(
    {"bmfr_fit",
     "BMFR's fit: bmfr_accumulated_noisy, gbuffer_world_position, gbuffer_shading_normal (or "
     "vp_gbuffer_* and vp_valid) -> bmfr_weights, bmfr_feature_range",
     "the block grid shifted by the previous frame's offset", run});

}  // namespace
}  // namespace fovref_client
