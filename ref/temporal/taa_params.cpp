#include "ref/temporal/taa_params.h"

#include "ref/core/error.h"

namespace fovref {

const char* taa_mode_name(TaaMode mode) {
    switch (mode) {
        case TaaMode::off: return "off";
        case TaaMode::depth: return "depth";
        case TaaMode::clamp_screen: return "clamp-screen";
        case TaaMode::clamp_buffer: return "clamp-buffer";
    }
    return "?";
}

std::vector<ParamSpec> taa_param_specs() {
    return {
        {"taa", "off",
         "temporal anti-aliasing after pass 2 (Lund §3.4): 'off', 'depth' (depth-based "
         "rejection), 'clamp-screen' or 'clamp-buffer' (Karis neighbourhood clamping in screen "
         "or buffer space); turns on the Halton jitter of a stationary camera"},
        {"taa_tau", "0.01", "TAA depth rejection: relative tolerance |z' - z_h| <= tau z'"},
        {"taa_age_cap", "20", "TAA: the largest age (Lund eq. 3.12)"},
        {"taa_periphery", "0.333333343",
         "TAA: inconsistent history beyond this x the screen diagonal from the gaze is kept with "
         "age 2 (Lund's flicker rule)"},
        {"taa_jitter_start", "0", "TAA: Halton index of frame 0 (0..15)"}};
}

TaaSettings parse_taa_params(const Params& params) {
    const std::vector<ParamSpec> specs = taa_param_specs();
    TaaSettings s;
    const std::string mode = params.get_string(specs, "taa");
    if (mode == "off")
        s.mode = TaaMode::off;
    else if (mode == "depth")
        s.mode = TaaMode::depth;
    else if (mode == "clamp-screen")
        s.mode = TaaMode::clamp_screen;
    else if (mode == "clamp-buffer")
        s.mode = TaaMode::clamp_buffer;
    else
        throw Error("parameter 'taa': '" + mode +
                    "' is not one of off, depth, clamp-screen, clamp-buffer");
    s.params.rejection = s.mode == TaaMode::depth ? TaaRejection::depth : TaaRejection::clamp;
    s.params.tau = params.get_float(specs, "taa_tau", 0.0f, 1.0f);
    s.params.age_cap = params.get_int(specs, "taa_age_cap", 1, 1000);
    s.params.periphery = params.get_float(specs, "taa_periphery", 0.0f, 100.0f);
    s.jitter_start = params.get_int(specs, "taa_jitter_start", 0, 15);
    if (!s.enabled())
        for (const ParamSpec& spec : specs)
            if (spec.name != "taa" && params.values().count(spec.name) != 0)
                throw Error("parameter '" + spec.name + "' applies to TAA only: add taa=depth, " +
                            "taa=clamp-screen or taa=clamp-buffer");
    return s;
}

Offset2 taa_jitter(const TaaSettings& settings, int frame, bool camera_moves) {
    if (!settings.enabled() || camera_moves) return {};
    return halton_jitter(static_cast<std::uint32_t>(frame),
                         static_cast<std::uint32_t>(settings.jitter_start));
}

}  // namespace fovref
