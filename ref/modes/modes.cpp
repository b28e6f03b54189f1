#include "ref/modes/modes.h"

#include "ref/bmfr/bmfr_params.h"
#include "ref/core/error.h"
#include "ref/image/image.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/probe.h"
#include "ref/log_polar/stereo.h"
#include "ref/modes/building_blocks.h"
#include "ref/modes/log_polar.h"
#include "ref/modes/ray_tracing.h"
#include "ref/modes/taa_stage.h"
#include "ref/modes/visual_polar.h"
#include "ref/modes/vp_probe.h"
#include "ref/temporal/taa_params.h"
#include "ref/temporal/taa_probe.h"
#include "ref/trace/basic_params.h"
#include "ref/trace/trace_probe.h"

namespace fovref {

namespace {

void explain_basic_taa(const ProbeContext& c, ProbeReport& report) {
    explain_with_taa(c, report, explain_basic,
                     {static_cast<float>(c.settings->width) * 0.5f,
                      static_cast<float>(c.settings->height) * 0.5f});
}

void explain_foveated_taa(const ProbeContext& c, ProbeReport& report) {
    const FoveatedParams params =
        parse_foveated_params(c.settings->params, find_foveation_preset(report.mode));
    explain_with_taa(c, report, explain_foveated,
                     gaze_point(params, c.settings->width, c.settings->height, c.frame->frame));
}

// The TAA buffers of one eye's half of a stereo frame, as the frame of that eye's TAA.
FrameResult stereo_eye_frame(const FrameResult& frame, const Camera& camera, int eye, float ipd,
                             int eye_width) {
    FrameResult out;
    out.frame = frame.frame;
    out.camera = eye_camera(camera, eye, ipd);
    for (const char* name : {"resolved", "taa_view_depth", "taa_bounds", "final", "taa_age"})
        if (const Buffer* b = frame.find(name))
            out.add(name, b->kind, b->channel_names,
                    image_columns(b->image, eye * eye_width, eye_width));
    return out;
}

// stereo-lp: the ray generation at the frame's jitter, then the TAA of the pixel's eye, explained
// on that eye's half of the screen (its camera, gaze and history).
void explain_stereo_taa(const ProbeContext& c, ProbeReport& report) {
    const ProbeContext jittered = probe_at_jitter(c);
    explain_stereo(jittered, report);
    const TaaSettings taa = parse_taa_params(c.settings->params);
    if (!taa.enabled() || c.texel || !c.frame->find("taa_age")) return;
    const StereoParams params = parse_stereo_params(c.settings->params);
    const int eye_width = stereo_eye_width(c.settings->width);
    const int eye = c.x / eye_width;
    const FrameResult current = stereo_eye_frame(*c.frame, c.camera, eye, params.ipd, eye_width);
    std::optional<FrameResult> previous;
    if (c.previous_frame && c.previous_frame->camera)
        previous = stereo_eye_frame(*c.previous_frame, *c.previous_frame->camera, eye, params.ipd,
                                    eye_width);
    ProbeContext local = jittered;
    local.frame = &current;
    local.previous_frame = previous ? &*previous : nullptr;
    local.camera = *current.camera;
    local.x = c.x - eye * eye_width;
    const glm::vec2 gaze = stereo_maps(params, *c.scene, c.camera, c.settings->width,
                                       c.settings->height, c.frame->frame)[eye]
                               .gaze;
    explain_taa(local, taa_probe_inputs(current, taa, gaze), report);
    report.sections.back().title += "; eye " + std::to_string(eye) + ", pixel (" +
                                    std::to_string(local.x) + ", " + std::to_string(c.y) +
                                    ") of its half, with its own camera and history";
}

ModeInfo mode(std::string name, std::string description,
              Pipeline (*build)(const Scene*, const RenderSettings&)) {
    ModeInfo m;
    m.name = std::move(name);
    m.description = std::move(description);
    m.build = build;
    return m;
}

std::vector<ModeInfo> make_modes() {
    ModeInfo basic = mode("basic",
                          "one ray per pixel centre, Lambertian shading with one shadow ray "
                          "per light (Lund §3.1)",
                          basic_pipeline);
    basic.params = basic_param_specs();
    for (ParamSpec& spec : taa_param_specs()) basic.params.push_back(std::move(spec));
    basic.explain = explain_basic_taa;
    basic.pixel_functions = basic_pixel_functions;
    ModeInfo ground_truth = mode(
        "ground-truth", "16 Halton(2,3) rays per pixel, shaded as basic, box-filtered (Lund §3.2)",
        ground_truth_pipeline);
    ground_truth.explain = explain_ground_truth;
    ground_truth.pixel_functions = ground_truth_pixel_functions;
    ModeInfo pathtrace =
        mode("pathtrace",
             "1-spp path tracing from the rasterized G-buffer: next-event estimation to one "
             "light, one cosine-weighted secondary ray, NEE at its hit (Koskela §2.4; SPEC §8)",
             pathtrace_pipeline);
    pathtrace.params = pathtrace_param_specs();
    pathtrace.pixel_functions = pathtrace_pixel_functions;
    pathtrace.stateless = true;  // unless denoise=bmfr (carries_state)
    ModeInfo reference = mode("pathtrace-reference",
                              "the converged reference of pathtrace: N jittered samples per pixel "
                              "averaged, a standard-error image, resumable sums (SPEC §8)",
                              pathtrace_reference_pipeline);
    reference.params = pathtrace_reference_param_specs();
    reference.resume_same_frame = true;
    ModeInfo rng = mode("rng", "rand(frame, pixel, d) for d = 0..2 (SPEC §0)", rng_pipeline);
    rng.needs_scene = false;
    ModeInfo halton = mode("halton", "the 16 Halton(2,3) points, raw and scaled (Lund eq. 3.11)",
                           halton_pipeline);
    halton.needs_scene = false;
    const auto foveated = [](const std::string& name, const char* what,
                             Pipeline (*build)(const Scene*, const RenderSettings&)) {
        const FoveationPreset& preset = find_foveation_preset(name);
        ModeInfo m = mode(name, std::string(what) + " (" + preset.source + ")", build);
        m.params = foveated_param_specs(preset);
        for (ParamSpec& spec : taa_param_specs()) m.params.push_back(std::move(spec));
        m.pixel_functions = foveated_pixel_functions;
        m.explain = explain_foveated_taa;
        m.explains_texels = true;
        return m;
    };
    ModeInfo stereo =
        mode("stereo-lp",
             "both eyes side by side in one pass, each with its own camera (+-IPD/2), "
             "gaze and log-polar buffer; optional barrel distortion (Gupta 2019)",
             stereo_pipeline);
    stereo.params = stereo_param_specs();
    for (ParamSpec& spec : taa_param_specs()) stereo.params.push_back(std::move(spec));
    stereo.pixel_functions = stereo_pixel_functions;
    stereo.explain = explain_stereo_taa;
    stereo.explains_texels = true;
    ModeInfo vp = mode("visual-polar",
                       "path tracing in Visual-Polar space: one path per traced texel, BMFR on "
                       "the buffer (wrap on phi, staircase blocks), phi-mip resolve, blur ramp "
                       "(Koskela P5)",
                       visual_polar_pipeline);
    vp.params = visual_polar_param_specs(true);
    vp.pixel_functions = visual_polar_pixel_functions;
    vp.parameters_carry_state = [](const Params& p) {  // BMFR by default
        return parse_bmfr_params(p, "bmfr").enabled;
    };
    vp.explain = explain_visual_polar;
    vp.explains_texels = true;
    ModeInfo vp_basic = mode("visual-polar-basic",
                             "the basic ray tracer's shading in Visual-Polar space, phi-mip "
                             "resolve, blur ramp (for comparison with the log-polar modes)",
                             visual_polar_basic_pipeline);
    vp_basic.params = visual_polar_param_specs(false);
    vp_basic.pixel_functions = visual_polar_basic_pixel_functions;
    vp_basic.explain = explain_visual_polar;
    vp_basic.explains_texels = true;
    ModeInfo falloff = mode("linear-falloff",
                            "1-spp path tracing of pixels drawn with the linear fall-off "
                            "probability L(e), push-pull fill, optional BMFR (Weier et al.; "
                            "Koskela eq. 4.1)",
                            linear_falloff_pipeline);
    falloff.params = linear_falloff_param_specs();
    ModeInfo acuity = mode("acuity",
                           "N path-traced samples per frame placed by the acuity model's "
                           "inverse CDF, progressive mean, unsampled pixels black (Koskela P3/P4)",
                           acuity_pipeline);
    acuity.params = acuity_param_specs();
    acuity.parameters_carry_state = [](const Params& p) {  // progressive by default
        return p.get_bool(acuity_param_specs(), "progressive");
    };
    return {
        basic,
        ground_truth,
        foveated("fov", "log-polar foveated ray tracing, shaded as basic", fov_pipeline),
        foveated("kfov", "kernel log-polar foveated ray tracing, K(x) = x^alpha", kfov_pipeline),
        foveated("cfov", "log-polar foveation with a ray-traced gaze buffer (composite)",
                 cfov_pipeline),
        foveated("ckfov", "kernel log-polar foveation with a gaze buffer", ckfov_pipeline),
        foveated(
            "kfr",
            "kernel foveated rendering: deferred shading in the log-polar buffer, internal "
            "AA, mip resolve, post-AA; TAA with jitter after the inverse transform (Meng 2018)",
            kfr_pipeline),
        stereo,
        pathtrace,
        reference,
        vp,
        vp_basic,
        falloff,
        acuity,
        mode("splat",
             "centroid splat of every triangle with headlight shading (a trivial pass that "
             "pins scene, materials, textures and camera path)",
             splat_pipeline),
        mode("camera-rays", "primary ray direction through every pixel centre (SPEC §1)",
             camera_rays_pipeline),
        mode("geometry", "the scene's triangles, normals, uvs and material ids as buffers",
             geometry_pipeline),
        rng,
        halton,
    };
}

}  // namespace

const std::vector<ModeInfo>& render_modes() {
    static const std::vector<ModeInfo> modes = make_modes();
    return modes;
}

bool carries_state(const ModeInfo& mode, const Params& params) {
    const auto on = [&](const char* key, const char* off) {
        const auto it = params.values().find(key);
        return it != params.values().end() && it->second != off;
    };
    if (mode.parameters_carry_state && mode.parameters_carry_state(params)) return true;
    return !mode.stateless || on("taa", "off") || on("denoise", "none");
}

const ModeInfo& find_mode(const std::string& name) {
    for (const ModeInfo& mode : render_modes())
        if (mode.name == name) return mode;
    std::vector<std::string> names;
    for (const ModeInfo& mode : render_modes()) names.push_back(mode.name);
    throw Error("unknown mode '" + name + "' (modes: " + join_names(names) + ")");
}

std::vector<std::string> render_each(const Scene* scene, const std::string& mode,
                                     const RenderSettings& settings,
                                     const std::function<void(FrameResult&)>& on_frame) {
    return render_each(scene, find_mode(mode), settings, on_frame);
}

std::vector<FrameResult> render(const Scene* scene, const std::string& mode,
                                const RenderSettings& settings) {
    return render(scene, find_mode(mode), settings);
}

ProbeReport probe_pixel(const Scene* scene, const std::string& mode, const RenderSettings& settings,
                        int frame, int x, int y, std::optional<glm::ivec2> texel, int eye) {
    return probe_pixel(scene, find_mode(mode), settings, frame, x, y, texel, eye);
}

std::vector<FrameResult> render_golden_case(const GoldenCase& golden_case, const Scene* scene,
                                            const std::vector<std::string>& requested,
                                            const std::function<void(double)>& progress) {
    return render(scene, golden_case.mode, case_settings(golden_case, requested, progress));
}

}  // namespace fovref
