// BMFR's TAA, the authors' YCoCg TAA in display space (shaders/bmfr_taa.comp; docs/bmfr.md,
// "TAA"), stage-isolated: per frame that has the bmfr_taa stage, the golden's bmfr_display and
// phase I's bmfr_previous_pixel in; the history is the golden's PREVIOUS frame's bmfr_taa (frame
// 0: none). Out: bmfr_taa. Screen space only: a Visual-Polar bundle (vp_valid) is refused.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

struct TaaPush {
    std::int32_t width, height, has_history;
    float taa_alpha;
};

// Runs the TAA on one frame (its history: `previous`, nullptr on frame 0).
void taa_frame(PassContext& ctx, const json& frame, const json* previous) {
    Image display = ctx.read(frame, "bmfr_display");
    Image previous_pixel = ctx.read(frame, "bmfr_previous_pixel");
    const int width = display.width, height = display.height;
    if (display.channels != 3 || previous_pixel.width != width || previous_pixel.height != height ||
        previous_pixel.channels != 2)
        throw std::runtime_error("bmfr_taa: bmfr_previous_pixel is not the size of bmfr_display");
    Image history{1, 1, 3, {0, 0, 0}};
    if (previous) {
        history = ctx.read(*previous, "bmfr_taa");
        if (history.width != width || history.height != height || history.channels != 3)
            throw std::runtime_error("bmfr_taa: the previous bmfr_taa is not the frame's size");
    }
    Image result{width, height, 3, std::vector<float>(display.data.size(), 0.0f)};
    const TaaPush push{width, height, previous ? 1 : 0, 0.2f};  // 0.2 new + 0.8 history
    ctx.dispatch(
        "bmfr_taa",
        {host(display.data), host(previous_pixel.data), host(history.data), host(result.data)},
        &push, sizeof push, groups(width, 16), groups(height, 16));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, "bmfr_taa", result);
}

int run(PassContext& ctx) {
    ctx.notes["precise"] =
        "the YCoCg transforms, the extents' means, the history's sum and the "
        "blend (the oracle's binary32 order)";
    return ctx.each_frame(
        "bmfr_taa",
        [&](const json& frame, const std::string&) {
            if (PassContext::has(frame, "vp_valid"))
                throw std::runtime_error("Visual-Polar BMFR is not ported");
            const json* previous = ctx.previous_frame(frame);
            taa_frame(ctx, frame, previous);
        },
        "the bundle has no bmfr_taa stage");
}

const bool registered = register_pass(
    {"bmfr_taa",
     "BMFR's YCoCg TAA: bmfr_display, bmfr_previous_pixel and the previous frame's bmfr_taa -> "
     "bmfr_taa",
     "the normalised YCoCg's inverse (no /4) after the unnormalised forward transform", run});

}  // namespace
}  // namespace fovref_client
