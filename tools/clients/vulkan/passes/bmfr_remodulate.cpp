// BMFR's remodulation and tone mapping (shaders/bmfr_remodulate.comp; docs/bmfr.md,
// "Remodulation and tone mapping"), stage-isolated: per frame that has the bmfr_remodulate
// stage, the golden's bmfr_accumulated_filtered and gbuffer_albedo in, and with
// bmfr_emission=separate its `emission`; bmfr_display out.
#include <cstdint>
#include <stdexcept>
#include <string>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

// The display exponent (bmfr_gamma): the authors' 0.454545 (default) or 1/2.2.
float display_exponent(const PassContext& ctx) {
    const std::string gamma = ctx.param("bmfr_gamma", "0.454545");
    if (gamma != "0.454545" && gamma != "1/2.2")
        throw std::runtime_error("bmfr_gamma must be '0.454545' or '1/2.2', got '" + gamma + "'");
    return gamma == "0.454545" ? 0.454545f : 1.0f / 2.2f;
}

// max(albedo, floor) multiplies: 0.01 (bmfr_remodulate=floor, default) or 0 (albedo).
float remodulation_floor(const PassContext& ctx) {
    const std::string remodulate = ctx.param("bmfr_remodulate", "floor");
    if (remodulate != "floor" && remodulate != "albedo")
        throw std::runtime_error("bmfr_remodulate must be 'floor' or 'albedo', got '" + remodulate +
                                 "'");
    return remodulate == "floor" ? 0.01f : 0.0f;
}

struct RemodulatePush {
    std::int32_t width, height, separate_emission;
    float albedo_floor, inverse_gamma;
};

// Whether the case keeps the emission out of the fit (bmfr_emission, default include).
bool separate_emission(const PassContext& ctx) {
    const std::string emission = ctx.param("bmfr_emission", "include");
    if (emission != "include" && emission != "separate")
        throw std::runtime_error(
            "bmfr_remodulate: bmfr_emission: expected 'include' or 'separate', got " + emission);
    return emission == "separate";
}

// Remodulates one frame and writes bmfr_display.
void remodulate_frame(PassContext& ctx, const json& frame, bool separate) {
    Image filtered = ctx.read(frame, "bmfr_accumulated_filtered");
    Image albedo = ctx.read(frame, "gbuffer_albedo");
    Image emission = separate ? ctx.read(frame, "emission") : Image{1, 1, 3, {0, 0, 0}};
    const auto same_shape = [&](const Image& image) {
        return image.width == filtered.width && image.height == filtered.height &&
               image.channels == 3;
    };
    if (!same_shape(filtered) || !same_shape(albedo) || (separate && !same_shape(emission)))
        throw std::runtime_error(
            "bmfr_remodulate: the albedo or emission does not match bmfr_accumulated_filtered");
    Image display{filtered.width, filtered.height, 3,
                  std::vector<float>(filtered.data.size(), 0.0f)};
    const RemodulatePush push{filtered.width, filtered.height, separate ? 1 : 0,
                              remodulation_floor(ctx), display_exponent(ctx)};
    ctx.dispatch("bmfr_remodulate",
                 {host(filtered.data), host(albedo.data), host(emission.data), host(display.data)},
                 &push, sizeof push, groups(filtered.width, 8), groups(filtered.height, 8));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, "bmfr_display", display);
}

int run(PassContext& ctx) {
    const bool separate = separate_emission(ctx);
    ctx.notes["precise"] = "x max(albedo, 0.01) and + e (binary32, no contraction)";
    ctx.notes["bmfr_remodulate_pow"] = "GLSL pow (the oracle: dm::pow_fast)";
    return ctx.each_frame(
        "bmfr_remodulate",
        [&](const json& frame, const std::string&) { remodulate_frame(ctx, frame, separate); },
        "the bundle has no bmfr_remodulate stage (bmfr_display)");
}

const bool registered = register_pass(
    {"bmfr_remodulate",
     "BMFR's remodulation and tone mapping: bmfr_accumulated_filtered, gbuffer_albedo (and "
     "emission with bmfr_emission=separate) -> bmfr_display",
     "the albedo's floor 0.01 left out (x albedo)", run});

}  // namespace
}  // namespace fovref_client
