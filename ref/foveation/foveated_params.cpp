#include "ref/foveation/foveated_params.h"

#include <cstdio>

#include "ref/core/error.h"

namespace fovref {

namespace {

FoveationPreset preset(std::string name, float sigma, float alpha, float gaze_angle,
                       float lp_aspect) {
    FoveationPreset p;
    p.name = std::move(name);
    p.source = "Lund Table 5.1";
    p.map.sigma = sigma;
    p.map.kernel = power_kernel(alpha);
    p.map.gaze_angle = gaze_angle;
    p.map.lp_aspect = lp_aspect;
    p.map.radius = RadiusMode::diagonal;
    return p;
}

std::string number_text(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(value));
    return text;
}

}  // namespace

const std::vector<FoveationPreset>& foveation_presets() {
    static const std::vector<FoveationPreset> presets = {
        preset("fov", 0.75f, 1.0f, 0.0f, 1.2f),
        preset("kfov", 1.0f, 3.0f, 0.0f, 0.70f),
        preset("cfov", 1.4f, 1.0f, 0.20f, 0.33f),
        preset("ckfov", 1.3f, 2.0f, 0.15f, 0.35f),
    };
    return presets;
}

const FoveationPreset& find_foveation_preset(const std::string& name) {
    std::vector<std::string> names;
    for (const FoveationPreset& p : foveation_presets()) {
        if (p.name == name) return p;
        names.push_back(p.name);
    }
    throw Error("unknown foveation preset '" + name + "' (presets: " + join_names(names) + ")");
}

std::vector<ParamSpec> foveated_param_specs(const FoveationPreset& preset) {
    const LogPolarParams& m = preset.map;
    return {
        {"sigma", number_text(m.sigma),
         "buffer reduction sigma: the log-polar buffer has about W H / sigma^2 texels"},
        {"alpha", number_text(m.kernel.alpha),
         "kernel exponent: K(x) = x^alpha, alpha in [1, 64] (1: classic log-polar)"},
        {"beta", "",
         "polynomial kernel K(x) = sum beta_i x^i instead of x^alpha: beta_0..beta_n, comma-"
         "separated (beta_0 = 0, sum 1, K' >= 0 on [0, 1])"},
        {"lp_aspect", number_text(m.lp_aspect),
         "buffer aspect w/h (Lund eq. 3.6); 0: w = W/sigma, h = H/sigma"},
        {"L", m.radius == RadiusMode::diagonal ? "diagonal" : "corners",
         "radius R of the last column, L = ln(1 + R): 'diagonal' (sqrt(W^2 + H^2)) or 'corners' "
         "(farthest screen corner from the gaze)"},
        {"gaze_angle", number_text(m.gaze_angle),
         "a_G in radians: the gaze buffer's angular radius (composite foveation); 0: none"},
        {"gaze", "", "gaze point X,Y in screen pixels (any finite point); empty: the centre"},
        {"gaze_track", "",
         "CSV file of 'frame,x,y' lines: the gaze of each frame (held until the next sample)"},
        {"filters", "", "screen-space filters after pass 2: '' (none) or 'lerp' (Lund §3.5)"},
        {"resolve", "bilinear", "pass 2's filter: 'bilinear' (SPEC §6)"},
    };
}

FoveatedParams parse_foveated_params(const Params& params, const FoveationPreset& preset) {
    const std::vector<ParamSpec> specs = foveated_param_specs(preset);
    FoveatedParams parsed;
    LogPolarParams& m = parsed.map;
    m.sigma = params.get_float(specs, "sigma", 0.01f, 1024.0f);
    m.lp_aspect = params.get_float(specs, "lp_aspect", 0.0f, 1000.0f);
    m.gaze_angle = params.get_float(specs, "gaze_angle", 0.0f, 1.5f);
    const std::vector<float> beta = params.get_float_list(specs, "beta");
    if (!beta.empty()) {
        if (params.given("alpha"))
            throw Error(
                "parameters 'alpha' and 'beta' both given: a kernel is x^alpha or a "
                "polynomial, not both");
        m.kernel = polynomial_kernel(beta, "parameter 'beta'");
    } else {
        m.kernel = power_kernel(params.get_float(specs, "alpha", 1.0f, 64.0f), "parameter 'alpha'");
    }
    const std::string radius = params.get_string(specs, "L");
    if (radius == "diagonal")
        m.radius = RadiusMode::diagonal;
    else if (radius == "corners")
        m.radius = RadiusMode::corners;
    else
        throw Error("parameter 'L': '" + radius + "' is neither 'diagonal' nor 'corners'");
    const std::vector<float> gaze = params.get_float_list(specs, "gaze");
    if (gaze.size() == 2)
        parsed.gaze = glm::vec2(gaze[0], gaze[1]);
    else if (!gaze.empty())
        throw Error("parameter 'gaze': expected X,Y (two numbers), got " +
                    std::to_string(gaze.size()));
    const std::string track = params.get_string(specs, "gaze_track");
    if (!track.empty()) {
        if (parsed.gaze) throw Error("parameters 'gaze' and 'gaze_track' both given: give one");
        parsed.gaze_track = read_gaze_track(track);
    }
    const std::string filters = params.get_string(specs, "filters");
    if (filters == "lerp")
        parsed.gaussian_lerp = true;
    else if (!filters.empty())
        throw Error("parameter 'filters': '" + filters + "' is not a filter ('' or 'lerp')");
    const std::string resolve = params.get_string(specs, "resolve");
    if (resolve != "bilinear")
        throw Error("parameter 'resolve': '" + resolve + "' is not a resolve filter ('bilinear')");
    return parsed;
}

glm::vec2 gaze_point(const FoveatedParams& params, int width, int height, int frame) {
    if (!params.gaze_track.empty()) return gaze_at_frame(params.gaze_track, frame);
    if (params.gaze) return *params.gaze;
    return {static_cast<float>(width) * 0.5f, static_cast<float>(height) * 0.5f};
}

LogPolarMap foveated_map(const FoveatedParams& params, const Scene& scene, const Camera& camera,
                         int width, int height, int frame) {
    const float d_px = display_distance_px(scene.display, width, height, camera.vfov_deg);
    return make_log_polar_map(params.map, width, height, gaze_point(params, width, height, frame),
                              d_px);
}

}  // namespace fovref
