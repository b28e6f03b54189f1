// Pass 2 of Gupta's stereo (shaders/stereo_resolve.comp): the side-by-side lp_color and lp_valid
// (2w x h) in, the resolve stage's buffer (`final`, or `resolved` before TAA) out, on every frame
// that has it; with `barrel=on` Gupta's barrel distortion (k1, k2; defaults 0.22, 0.24). Both
// eyes share one map on the W/2 x H sub-screen (log_polar_map_block of passes/resolve.cpp: the
// gaze in eye coordinates, default the eye's centre; R, L computed once on the host). The dump
// also holds the decisions each pixel took, resolve_tap (the first tap, side-by-side columns;
// -1 outside the lens), and its lookup, fNNN_<output>_lookup.f32 (u, v, 0, source).
#include <cstdlib>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"
#include "tools/clients/vulkan/passes/lp_map.h"

namespace fovref_client {

namespace {

struct StereoParameters {
    std::int32_t screen_width, screen_height, channels, barrel;
    float k1, k2;
};

/// The barrel distortion's switch and coefficients from the case's parameters.
void read_barrel(const PassContext& ctx, StereoParameters& push) {
    const std::string barrel = ctx.param("barrel", "off");
    if (barrel != "on" && barrel != "off")
        throw std::runtime_error("parameter barrel '" + barrel + "' is neither on nor off");
    push.barrel = barrel == "on";
    const std::string k1 = ctx.param("k1", "0.22"), k2 = ctx.param("k2", "0.24");
    char *end1 = nullptr, *end2 = nullptr;
    push.k1 = std::strtof(k1.c_str(), &end1);
    push.k2 = std::strtof(k2.c_str(), &end2);
    if (k1.empty() || *end1 != '\0' || k2.empty() || *end2 != '\0')
        throw std::runtime_error("parameters k1 '" + k1 + "', k2 '" + k2 + "': not numbers");
}

/// Pass 2 of both eyes in one frame: writes `output` and its lookups.
void resolve_frame(PassContext& ctx, const json& frame, const std::string& output) {
    const Image colour = ctx.read(frame, "lp_color");
    const Image valid = ctx.read(frame, "lp_valid");
    if (colour.channels > 4) throw std::runtime_error("more than 4 channels in the buffer");
    if (valid.width != colour.width || valid.height != colour.height || valid.channels != 1)
        throw std::runtime_error("lp_valid is not a mask of the colour buffer's size");
    if (ctx.width() % 2 != 0 || colour.width % 2 != 0)
        throw std::runtime_error("the screen (" + std::to_string(ctx.width()) +
                                 ") or the buffer (" + std::to_string(colour.width) +
                                 ") is not two eyes wide");
    std::vector<std::uint32_t> map = log_polar_map_block(ctx, frame, ctx.width() / 2, ctx.height(),
                                                         colour.width / 2, colour.height);
    StereoParameters push{ctx.width(), ctx.height(), colour.channels, 0, 0.0f, 0.0f};
    read_barrel(ctx, push);
    const std::size_t pixels = static_cast<std::size_t>(ctx.width()) * ctx.height();
    Image result{ctx.width(), ctx.height(), colour.channels,
                 std::vector<float>(pixels * colour.channels, 0.0f)};
    Image lookups{ctx.width(), ctx.height(), 4, std::vector<float>(pixels * 4, 0.0f)};
    std::vector<float> colours = colour.data, mask = valid.data;
    std::vector<float> decisions(pixels * 4, 0.0f);
    ctx.dispatch("stereo_resolve",
                 {host(map), host(colours), host(mask), host(result.data), host(lookups.data),
                  host(decisions)},
                 &push, sizeof push, groups(ctx.width(), 8), groups(ctx.height(), 8));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, output, result);
    ctx.write(index, output + "_lookup", lookups);
    ctx.write_resolve_decisions(index, decisions, 0);
    ctx.notes["barrel"] = push.barrel ? "on" : "off";
}

int run(PassContext& ctx) {
    if (ctx.manifest.at("case").at("mode") != "stereo-lp")
        throw std::runtime_error("the bundle is not stereo-lp's (its pass 2 is the resolve pass)");
    const int frames = ctx.each_frame(
        "resolve",
        [&](const json& frame, const std::string& output) { resolve_frame(ctx, frame, output); },
        "the bundle has no resolve stage (pass 2)");
    ctx.notes["precise"] =
        "lp_map.glsl: x' x' + y' y'; lp_bilinear.glsl's lerps; the barrel's |q|^2 and "
        "1 + k1 |q|^2 + k2 |q|^4 and c + (W/4) q s";
    return frames;
}

const bool registered = register_pass(
    {"stereo_resolve",
     "pass 2 of Gupta's stereo, with or without the barrel distortion: the side-by-side "
     "lp_color, lp_valid -> the resolve stage's buffer",
     "the barrel distortion applied the wrong way (q divided by the factor, not multiplied)", run});

}  // namespace
}  // namespace fovref_client
