// The P5 blur ramp (Koskela P5 §3.5; docs/visual-polar.md, "Blur ramp"): the separable Gaussian
// whose sigma ramps with eccentricity, as two dispatches of shaders/blur_ramp.comp per frame,
// stage-isolated: resolved -> blur_horizontal, and the golden's blur_horizontal -> the
// blur_vertical stage's buffer (final). The ramp is measured from the Visual-Polar map's gaze
// with its scale s = R / P(1) (R the farthest corner from the gaze) and fovea edge P(u0),
// computed once on the host as the resolve's pass does; the gaze is the case's `gaze`
// parameter (default the screen centre); `gaze_track` is refused.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

/// The push constants of shaders/blur_ramp.comp.
struct BlurParameters {
    std::int32_t width, height, channels, vertical;
    float gaze_x, gaze_y, scale, fovea_deg, sigma_deg, full_deg;
};

constexpr float vp_u0 = 0.0965f;

/// The acuity model's fitted inverse CDF P(u) in model degrees (P4 eq. 7), binary32.
float inverse_cdf(float u) {
    if (u <= vp_u0) return 18.64f * std::sqrt(std::max(u, 0.0f));
    return (((25.09f * u + 0.1680f) * u + 27.61f) * u + 23.87f) * u + 3.232f;
}

/// The ramp's geometry on the case's screen (the map's gaze, s and P(u0)) and parameters.
BlurParameters ramp_parameters(const PassContext& ctx, int channels) {
    if (!ctx.param("gaze_track", "").empty())
        throw std::runtime_error("blur_ramp: gaze_track is not read yet (give a case with `gaze`)");
    BlurParameters b{};
    b.width = ctx.width();
    b.height = ctx.height();
    b.channels = channels;
    b.gaze_x = 0.5f * static_cast<float>(b.width);
    b.gaze_y = 0.5f * static_cast<float>(b.height);
    const std::string gaze = ctx.param("gaze", "");
    if (!gaze.empty() && std::sscanf(gaze.c_str(), "%f,%f", &b.gaze_x, &b.gaze_y) != 2)
        throw std::runtime_error("blur_ramp: parameter gaze '" + gaze + "' is not X,Y");
    float r2 = 0.0f;
    for (const float cx : {0.0f, static_cast<float>(b.width)})
        for (const float cy : {0.0f, static_cast<float>(b.height)}) {
            const float dx = cx - b.gaze_x, dy = cy - b.gaze_y;
            r2 = std::max(r2, dx * dx + dy * dy);
        }
    b.scale = std::sqrt(r2) / inverse_cdf(1.0f);
    b.fovea_deg = inverse_cdf(vp_u0);
    b.sigma_deg = ctx.float_param("blur_sigma_deg", "0.564");
    b.full_deg = ctx.float_param("blur_full_deg", "30.0");
    return b;
}

/// One pass of the ramp over `in` (along y when `vertical`).
Image blur_pass(PassContext& ctx, Image& in, bool vertical) {
    if (in.channels < 1 || in.channels > 4)
        throw std::runtime_error("blur_ramp: " + std::to_string(in.channels) +
                                 " channels (1 to 4 supported)");
    BlurParameters b = ramp_parameters(ctx, in.channels);
    if (in.width != b.width || in.height != b.height)
        throw std::runtime_error("blur_ramp: the image is not the case's screen size");
    b.vertical = vertical ? 1 : 0;
    Image out{in.width, in.height, in.channels, std::vector<float>(in.data.size(), 0.0f)};
    const int extent = vertical ? b.height : b.width, lines = vertical ? b.width : b.height;
    ctx.dispatch("blur_ramp", {host(in.data), host(out.data)}, &b, sizeof b, groups(extent, 64),
                 static_cast<std::uint32_t>(lines));
    return out;
}

int run(PassContext& ctx) {
    ctx.notes["precise"] =
        "e = sqrt(dx^2 + dy^2) / s, the weights' recurrence and sum, and the weighted sum "
        "sum w_d c_d: not contracted to FMA, as the oracle";
    int frames = 0;
    for (const json& frame : ctx.frames()) {
        const std::string horizontal = PassContext::output_of(frame, "blur_horizontal");
        const std::string vertical = PassContext::output_of(frame, "blur_vertical");
        if (horizontal.empty() || vertical.empty()) continue;
        const int index = frame.at("frame").get<int>();
        Image resolved = ctx.read(frame, "resolved");
        ctx.write(index, horizontal, blur_pass(ctx, resolved, false));
        Image golden_horizontal = ctx.read(frame, horizontal);  // stage-isolated
        ctx.write(index, vertical, blur_pass(ctx, golden_horizontal, true));
        ++frames;
    }
    if (frames == 0)
        throw std::runtime_error(
            "blur_ramp: the bundle has no blur_horizontal and blur_vertical stages (blur=on)");
    return frames;
}

const bool registered = register_pass(
    {"blur_ramp",
     "the P5 blur ramp, two separable passes: resolved -> blur_horizontal -> final (each from the "
     "golden's input)",
     "weights divided by sqrt(2 pi) sigma instead of renormalised by their sum over the taps",
     run});

}  // namespace
}  // namespace fovref_client
