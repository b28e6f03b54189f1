#include "ref/log_polar/params.h"

#include <algorithm>
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

// Meng's KFR (Meng ch. 3-4; SPEC §12): w = W/sigma, h = H/sigma, R from the corners, the
// rasterized G-buffer sampled per texel, internal AA, mip resolve, post-AA.
FoveationPreset kfr_preset() {
    FoveationPreset p = preset("kfr", 1.8f, 4.0f, 0.0f, 0.0f);
    p.source = "Meng 2018, KFR";
    p.map.radius = RadiusMode::corners;
    p.primary = "raster";
    p.resolve = "mip";
    p.filters = "internal_aa,post_aa";
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
        kfr_preset(),
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
        {"kernel", "power",
         "kernel family: 'power' (x^alpha, or the polynomial of 'beta'), 'sine' (sin(x pi/2)) or "
         "'exp' ((e^x - 1)/(e - 1)): Meng's other two kernels (§2.1); docs/foveation.md"},
        {"lp_aspect", number_text(m.lp_aspect),
         "buffer aspect w/h (Lund eq. 3.6); 0: w = W/sigma, h = H/sigma"},
        {"L", m.radius == RadiusMode::diagonal ? "diagonal" : "corners",
         "radius R of the last column, L = ln(1 + R): 'diagonal' (sqrt(W^2 + H^2)) or 'corners' "
         "(farthest screen corner from the gaze)"},
        {"gaze_angle", number_text(m.gaze_angle),
         "a_G in radians: the gaze buffer's angular radius (composite foveation); 0: none"},
        {"lp_widen", "off",
         "Lund §3.3.5: 'on' widens the buffer (L=diagonal) by the share of its columns that a "
         "centred gaze leaves off screen (not traced), so as many columns cover the screen as "
         "without it; 'off'"},
        gaze_param_specs()[0],
        gaze_param_specs()[1],
        {"primary", preset.primary,
         "the buffer's G-buffer: 'ray' (a ray per texel) or 'raster' (Meng's deferred variant: "
         "the rasterized full-resolution G-buffer sampled per texel)"},
        {"fill_rule", "d3d", "rasterizer fill rule (primary=raster): 'd3d' or 'gl'"},
        {"raster_jitter", "raster",
         "TAA's jitter with primary=raster: 'raster' (the rasterizer samples at the jittered "
         "point, as Meng/Karis: a static camera supersamples) or 'lookup' (the texels' points "
         "shifted instead: whole pixels)"},
        {"resolve", preset.resolve,
         "pass 2's filter: 'bilinear' or 'mip' (a pyramid of the buffer, trilinear; Meng §5.1)"},
        {"filters", preset.filters,
         "comma-separated: 'internal_aa' (Meng, buffer space), 'lerp' (Lund §3.5), 'post_aa' "
         "(Meng eq. 2.14); empty: none"},
    };
}

namespace {

// The kernel: x^alpha, Meng's polynomial (beta) or one of his named kernels (kernel=sine|exp).
Kernel parse_kernel(const Params& params, const std::vector<ParamSpec>& specs) {
    const std::vector<float> beta = params.get_float_list(specs, "beta");
    const std::string family = params.get_string(specs, "kernel");
    params.get_choice(specs, "kernel", {"power", "sine", "exp"});  // validates
    if (family != "power") {
        if (params.given("alpha") || !beta.empty())
            throw Error("parameter 'kernel' = '" + family +
                        "' takes no 'alpha' or 'beta' (they shape the power kernel)");
        return named_kernel(family == "sine" ? KernelKind::sine : KernelKind::exponential);
    }
    if (!beta.empty()) {
        if (params.given("alpha"))
            throw Error(
                "parameters 'alpha' and 'beta' both given: a kernel is x^alpha or a "
                "polynomial, not both");
        return polynomial_kernel(beta, "parameter 'beta'");
    }
    return power_kernel(params.get_float(specs, "alpha", 1.0f, 64.0f), "parameter 'alpha'");
}

// The comma-separated filters: internal_aa, lerp, post_aa.
void parse_filters(const std::string& filters, FoveatedParams& parsed) {
    std::size_t start = 0;
    while (start < filters.size()) {
        const std::size_t comma = std::min(filters.find(',', start), filters.size());
        const std::string name = filters.substr(start, comma - start);
        if (name == "internal_aa")
            parsed.internal_aa = true;
        else if (name == "lerp")
            parsed.gaussian_lerp = true;
        else if (name == "post_aa")
            parsed.post_aa = true;
        else
            throw Error("parameter 'filters': '" + name +
                        "' is not a filter (internal_aa, lerp, post_aa)");
        start = comma + 1;
    }
}

}  // namespace

FoveatedParams parse_foveated_params(const Params& params, const FoveationPreset& preset) {
    const std::vector<ParamSpec> specs = foveated_param_specs(preset);
    FoveatedParams parsed;
    LogPolarParams& m = parsed.map;
    m.sigma = params.get_float(specs, "sigma", 0.01f, 1024.0f);
    m.lp_aspect = params.get_float(specs, "lp_aspect", 0.0f, 1000.0f);
    m.gaze_angle = params.get_float(specs, "gaze_angle", 0.0f, 1.5f);
    m.kernel = parse_kernel(params, specs);
    m.widen = params.get_bool(specs, "lp_widen");
    const std::string radius = params.get_string(specs, "L");
    if (radius == "diagonal")
        m.radius = RadiusMode::diagonal;
    else if (radius == "corners")
        m.radius = RadiusMode::corners;
    else
        throw Error("parameter 'L': '" + radius + "' is neither 'diagonal' nor 'corners'");
    if (m.widen && m.radius != RadiusMode::diagonal)
        throw Error(
            "parameter 'lp_widen': widening applies to L=diagonal (with L=corners every "
            "column is on screen)");
    parse_gaze_params(params, specs, parsed.gaze, parsed.gaze_track);
    parse_filters(params.get_string(specs, "filters"), parsed);
    const std::string resolve = params.get_string(specs, "resolve");
    if (resolve == "mip")
        parsed.mip_resolve = true;
    else if (resolve != "bilinear")
        throw Error("parameter 'resolve': '" + resolve + "' is neither 'bilinear' nor 'mip'");
    const std::string primary = params.get_string(specs, "primary");
    if (primary == "raster")
        parsed.deferred = true;
    else if (primary != "ray")
        throw Error("parameter 'primary': '" + primary + "' is neither 'ray' nor 'raster'");
    parsed.raster.fill_rule =
        parse_fill_rule(params.get_string(specs, "fill_rule"), "parameter 'fill_rule'");
    parsed.jitter_raster = params.get_choice(specs, "raster_jitter", {"raster", "lookup"}) == 0;
    if (!parsed.deferred && params.given("raster_jitter"))
        throw Error("parameter 'raster_jitter' applies to primary=raster only");
    if (!parsed.deferred && params.given("fill_rule"))
        throw Error("parameter 'fill_rule' applies to the rasterizer only: add primary=raster");
    if (parsed.deferred && m.gaze_angle > 0.0f)
        throw Error(
            "parameters 'primary=raster' and 'gaze_angle' > 0: the deferred variant has no "
            "gaze buffer (give gaze_angle=0 or primary=ray)");
    return parsed;
}

glm::vec2 gaze_point(const FoveatedParams& params, int width, int height, int frame) {
    return gaze_of_frame(params.gaze, params.gaze_track, width, height, frame);
}

std::string resolve_color_name(const FoveatedParams& params) {
    return params.internal_aa ? "lp_color_aa" : "lp_color";
}

std::vector<std::string> screen_chain(const FoveatedParams& params, bool taa) {
    std::vector<std::string> chain = {"resolved"};
    if (taa) chain.push_back("taa_color");
    if (params.gaussian_lerp) chain.push_back("lerp_filtered");
    if (params.post_aa) chain.push_back("post_aa_filtered");
    chain.back() = "final";
    return chain;
}

LogPolarMap foveated_map(const FoveatedParams& params, const Scene& scene, const Camera& camera,
                         int width, int height, int frame) {
    const float d_px = display_distance_px(scene.display, width, height, camera.vfov_deg);
    return make_log_polar_map(params.map, width, height, gaze_point(params, width, height, frame),
                              d_px);
}

}  // namespace fovref
