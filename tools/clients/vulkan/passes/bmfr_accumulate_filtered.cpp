// BMFR's phase III, the accumulation of the fit (shaders/bmfr_accumulate_filtered.comp;
// docs/bmfr.md, "Phase III"), stage-isolated: per frame that has the bmfr_accumulate_filtered
// stage, the golden's bmfr_fitted and phase I's bmfr_spp, bmfr_accept and bmfr_previous_pixel
// in; the history is the golden's PREVIOUS frame's bmfr_accumulated_filtered (frame 0: none).
// Out: bmfr_accumulated_filtered. Screen space only: a Visual-Polar bundle (vp_valid) is refused.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

struct FilteredPush {
    std::int32_t width, height, has_history;
    float alpha_min;
};

// Checks that `image` is width x height x channels, naming it otherwise.
void check_shape(const Image& image, int width, int height, int channels, const char* name) {
    if (image.width != width || image.height != height || image.channels != channels)
        throw std::runtime_error(std::string("bmfr_accumulate_filtered: ") + name +
                                 " is not the size of bmfr_fitted");
}

// Runs phase III on one frame (its history: `previous`, nullptr on frame 0).
void filter_frame(PassContext& ctx, const json& frame, const json* previous) {
    Image fitted = ctx.read(frame, "bmfr_fitted");
    Image spp = ctx.read(frame, "bmfr_spp");
    Image accept = ctx.read(frame, "bmfr_accept");
    Image previous_pixel = ctx.read(frame, "bmfr_previous_pixel");
    const int width = fitted.width, height = fitted.height;
    check_shape(spp, width, height, 1, "bmfr_spp");
    check_shape(accept, width, height, 1, "bmfr_accept");
    check_shape(previous_pixel, width, height, 2, "bmfr_previous_pixel");
    Image history{1, 1, 3, {0, 0, 0}};
    if (previous) {
        history = ctx.read(*previous, "bmfr_accumulated_filtered");
        check_shape(history, width, height, 3, "the previous bmfr_accumulated_filtered");
    }
    Image filtered{width, height, 3, std::vector<float>(fitted.data.size(), 0.0f)};
    const FilteredPush push{width, height, previous ? 1 : 0, 0.1f};  // the authors' alpha min
    ctx.dispatch("bmfr_accumulate_filtered",
                 {host(fitted.data), host(spp.data), host(accept.data), host(previous_pixel.data),
                  host(history.data), host(filtered.data)},
                 &push, sizeof push, groups(width, 8), groups(height, 8));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, "bmfr_accumulated_filtered", filtered);
}

int run(PassContext& ctx) {
    ctx.notes["precise"] =
        "the tap weights, the history's sum and the blend (the oracle's binary32 order)";
    return ctx.each_frame(
        "bmfr_accumulate_filtered",
        [&](const json& frame, const std::string&) {
            if (PassContext::has(frame, "vp_valid"))
                throw std::runtime_error("Visual-Polar BMFR is not ported");
            const json* previous = ctx.previous_frame(frame);
            filter_frame(ctx, frame, previous);
        },
        "the bundle has no bmfr_accumulate_filtered stage (bmfr_accumulated_filtered)");
}

const bool registered = register_pass(
    {"bmfr_accumulate_filtered",
     "BMFR's phase III: bmfr_fitted, bmfr_spp, bmfr_accept, bmfr_previous_pixel and the previous "
     "frame's bmfr_accumulated_filtered -> bmfr_accumulated_filtered",
     "phase I's blend factor reused: alpha = max(1 / (spp + 1), 0.1)", run});

}  // namespace
}  // namespace fovref_client
