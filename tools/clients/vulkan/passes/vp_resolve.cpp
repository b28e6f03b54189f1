// The Visual-Polar resolve (Koskela P5 §3.4; docs/visual-polar.md, "Resolve"): vp_color and
// vp_valid in, the resolve stage's buffer out (`resolved`, or `final` with blur=off), on every
// frame that has it. Two dispatches per frame: the phi-only pyramid, one workgroup per column
// (shaders/vp_resolve_mips.comp), then the lookup, one invocation per pixel
// (shaders/vp_resolve.comp). The map's constants (i_f, s, s P(u0)) and each column's row count
// n_i of the frame (passes/vp_rows.h: the triangular clip, or BMFR's staircase) are computed on
// the host, as a renderer would; the gaze is the case's `gaze` parameter (default the screen
// centre); `gaze_track` is refused. The dump also holds the decisions each pixel took, resolve_tap
// and (mip) resolve_mip_level, which the diff judges against the oracle's margins.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"
#include "tools/clients/vulkan/passes/vp_rows.h"

namespace fovref_client {
namespace {

/// The push constants of both shaders (shaders/include/vp_map.glsl).
struct VpResolveParameters {
    std::int32_t screen_width, screen_height, width, height, fovea_columns, channels, levels, mip;
    float gaze_x, gaze_y, scale, fovea_radius;
};

constexpr float vp_u0 = 0.0965f;

/// The acuity model's fitted inverse CDF P(u) in model degrees (P4 eq. 7), binary32.
float inverse_cdf(float u) {
    if (u <= vp_u0) return 18.64f * std::sqrt(std::max(u, 0.0f));
    return (((25.09f * u + 0.1680f) * u + 27.61f) * u + 23.87f) * u + 3.232f;
}

/// The map of a w x h buffer on the case's screen: i_f = round(0.24 w), s = R / P(1) with R the
/// farthest corner from the gaze, the fovea's radius s P(u0).
VpResolveParameters map_parameters(const PassContext& ctx, int width, int height, int channels) {
    if (!ctx.param("gaze_track", "").empty())
        throw std::runtime_error(
            "vp_resolve: gaze_track is not read yet (give a case with `gaze`)");
    VpResolveParameters m{};
    m.screen_width = ctx.width();
    m.screen_height = ctx.height();
    m.width = width;
    m.height = height;
    m.channels = channels;
    m.gaze_x = 0.5f * static_cast<float>(m.screen_width);
    m.gaze_y = 0.5f * static_cast<float>(m.screen_height);
    const std::string gaze = ctx.param("gaze", "");
    if (!gaze.empty() && std::sscanf(gaze.c_str(), "%f,%f", &m.gaze_x, &m.gaze_y) != 2)
        throw std::runtime_error("vp_resolve: parameter gaze '" + gaze + "' is not X,Y");
    m.fovea_columns = std::clamp(static_cast<int>(std::lround(0.24 * width)), 1, width - 1);
    float r2 = 0.0f;
    for (const float cx : {0.0f, static_cast<float>(m.screen_width)})
        for (const float cy : {0.0f, static_cast<float>(m.screen_height)}) {
            const float dx = cx - m.gaze_x, dy = cy - m.gaze_y;
            r2 = std::max(r2, dx * dx + dy * dy);
        }
    m.scale = std::sqrt(r2) / inverse_cdf(1.0f);
    m.fovea_radius = m.scale * inverse_cdf(vp_u0);
    const std::string resolve = ctx.param("resolve", "mip");
    if (resolve != "mip" && resolve != "bilinear")
        throw std::runtime_error("vp_resolve: parameter resolve '" + resolve +
                                 "' is neither mip nor bilinear");
    m.mip = resolve == "mip" ? 1 : 0;
    return m;
}

/// One frame: the pyramid (level 0 the buffer, the others zero until built), then the lookup;
/// `decisions` receives 4 values per pixel (vp_resolve.comp's).
Image resolve_frame(PassContext& ctx, int frame, const Image& colour, const Image& valid,
                    std::vector<float>& decisions, bool& mip) {
    if (colour.channels < 1 || colour.channels > 4)
        throw std::runtime_error("vp_resolve: vp_color has " + std::to_string(colour.channels) +
                                 " channels (1 to 4 supported)");
    if (valid.width != colour.width || valid.height != colour.height || valid.channels != 1)
        throw std::runtime_error(
            "vp_resolve: vp_valid is not a 1-channel buffer of vp_color's size");
    VpResolveParameters m = map_parameters(ctx, colour.width, colour.height, colour.channels);
    std::vector<std::int32_t> rows = vp_column_rows(ctx, m.width, m.height, frame);
    // Levels until every column has one row; level k is w x ceil(h / 2^k)
    std::size_t texels = 0;
    m.levels = 1;
    for (int h = m.height;; h = (h + 1) / 2, ++m.levels) {
        texels += static_cast<std::size_t>(m.width) * static_cast<std::size_t>(h);
        if (h == 1) break;
    }
    std::vector<float> pyramid(texels * static_cast<std::size_t>(m.channels), 0.0f);
    std::vector<float> pyramid_valid(texels, 0.0f);
    std::copy(colour.data.begin(), colour.data.end(), pyramid.begin());
    std::copy(valid.data.begin(), valid.data.end(), pyramid_valid.begin());
    ctx.dispatch("vp_resolve_mips", {host(pyramid), host(pyramid_valid), host(rows)}, &m, sizeof m,
                 static_cast<std::uint32_t>(m.width), 1);
    Image result{m.screen_width, m.screen_height, m.channels,
                 std::vector<float>(static_cast<std::size_t>(m.screen_width) * m.screen_height *
                                        static_cast<std::size_t>(m.channels),
                                    0.0f)};
    decisions.assign(static_cast<std::size_t>(m.screen_width) * m.screen_height * 4, 0.0f);
    mip = m.mip != 0;
    ctx.dispatch(
        "vp_resolve",
        {host(pyramid), host(pyramid_valid), host(rows), host(result.data), host(decisions)}, &m,
        sizeof m, groups(m.screen_width, 8), groups(m.screen_height, 8));
    return result;
}

int run(PassContext& ctx) {
    ctx.notes["precise"] =
        "P(u)'s Horner, the forward map's rho, r = sqrt(dx^2 + dy^2), the pyramid's running mean "
        "and every lerp a + t (b - a): not contracted to FMA, as the oracle";
    int frames = 0;
    for (const json& frame : ctx.frames()) {
        const std::string output = PassContext::output_of(frame, "resolve");
        if (output.empty() || !PassContext::has(frame, "vp_color")) continue;
        std::vector<float> decisions;
        bool mip = false;
        const Image result =
            resolve_frame(ctx, frame.at("frame").get<int>(), ctx.read(frame, "vp_color"),
                          ctx.read(frame, "vp_valid"), decisions, mip);
        ctx.write(frame.at("frame").get<int>(), output, result);
        ctx.write_resolve_decisions(frame.at("frame").get<int>(), decisions, mip ? 2 : 0);
        ++frames;
    }
    if (frames == 0)
        throw std::runtime_error(
            "vp_resolve: the bundle has no Visual-Polar resolve stage (vp_color and resolve)");
    return frames;
}

const bool registered = register_pass(
    {"vp_resolve",
     "the Visual-Polar resolve (phi mips or bilinear): vp_color, vp_valid -> the resolve stage's "
     "buffer",
     "phi clamped like rho instead of wrapped at 2 pi: atan's (-pi, pi] kept, rows clamped to the "
     "edge (the lookup's taps, the pyramid's odd-row pairing)",
     run});

}  // namespace
}  // namespace fovref_client
