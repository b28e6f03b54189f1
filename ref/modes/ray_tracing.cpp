#include "ref/modes/ray_tracing.h"

#include <memory>

#include "ref/bmfr/probe.h"
#include "ref/bmfr/stages.h"
#include "ref/core/error.h"
#include "ref/frustum/probe.h"
#include "ref/frustum/stages.h"
#include "ref/raster/stages.h"
#include "ref/temporal/stages.h"
#include "ref/trace/basic_params.h"
#include "ref/trace/stages.h"
#include "ref/trace/trace_probe.h"

namespace fovref {

namespace {

// ---- basic --------------------------------------------------------------------------------

// basic with TAA needs jittered rays, which the rasterizer has not, and a screen-space clamp.
void check_basic_taa(const BasicParams& params, const TaaSettings& taa) {
    if (taa.enabled() && params.primary == PrimaryVisibility::raster)
        throw Error(std::string("parameter 'taa': ") + taa_mode_name(taa.mode) +
                    " needs jittered primary rays, and primary=raster has no sub-pixel "
                    "jitter: use primary=ray");
    if (taa.mode == TaaMode::clamp_buffer)
        throw Error(
            "parameter 'taa': clamp-buffer is for the foveated modes; basic's buffer is "
            "the screen: use clamp-screen");
}

Pipeline basic_pipeline(const Scene* scene, const RenderSettings& settings) {
    const BasicParams params = parse_basic_params(settings.params);
    const TaaSettings taa = parse_taa_params(settings.params);
    check_basic_taa(params, taa);
    auto bvh = std::make_shared<BvhCache>();
    Pipeline p;
    if (params.primary == PrimaryVisibility::raster)
        p.add(rasterize_stage_def("primary_visibility", params.raster));
    else
        p.add(raycast_stage_def(bvh, taa_frame_jitter(taa)));
    p.add(shade_stage_def("shade_direct", "gbuffer_", taa.enabled() ? "shaded" : "final", bvh));
    if (taa.enabled()) p.add(taa_stage_def(taa, {"shaded", "gbuffer_view_depth", "", "final"}));
    // Lund's tile frustum culling (docs/frustum.md): its buffers only when asked for
    const FrustumSettings frustum = parse_frustum_params(settings.params);
    if (frustum.enabled && frustum.shadow && scene)  // the light checked before any work
        shadow_light(*scene, frustum.light, "parameter 'frustum_light'",
                     "parameter 'frustum_shadow'");
    if (frustum.enabled) p.add(frustum_cull_stage_def(frustum, bvh));
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> basic_pixel_functions(const Params& params) {
    const bool taa = parse_taa_params(params).enabled();
    std::vector<PixelFunction> functions;
    if (parse_basic_params(params).primary == PrimaryVisibility::raster)
        functions = raster_pixel_functions("primary_visibility");
    else
        functions = {
            {"primary_visibility", "fovref::raycast_gbuffer_pixel", taa ? "jittered (TAA)" : ""}};
    functions.push_back({"shade_direct", "fovref::shade_basic_pixel", ""});
    if (taa) functions.push_back({"taa", "fovref::taa_pixel", ""});
    return functions;
}

void explain_basic_taa(const ProbeContext& c, ProbeReport& report) {
    explain_with_taa(c, report, explain_basic,
                     {static_cast<float>(c.settings->width) * 0.5f,
                      static_cast<float>(c.settings->height) * 0.5f});
    const FrustumSettings frustum = parse_frustum_params(c.settings->params);
    if (frustum.enabled) explain_frustum_pixel(c, frustum, report);
}

// ---- ground truth ---------------------------------------------------------------------------

Pipeline ground_truth_pipeline(const Scene*, const RenderSettings&) {
    auto bvh = std::make_shared<BvhCache>();  // primary visibility and supersampling share it
    Pipeline p;
    // The pixel-centre G-buffer: consumed by nothing here, produced for --dump and golden bundles.
    p.add(raycast_stage_def(bvh)).add(supersample_stage_def(bvh));
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> ground_truth_pixel_functions(const Params&) {
    return {{"primary_visibility", "fovref::raycast_gbuffer_pixel", ""},
            {"supersample", "fovref::ground_truth_pixel", ""}};
}

// ---- path tracing ---------------------------------------------------------------------------

std::vector<ParamSpec> pathtrace_param_specs() {
    std::vector<ParamSpec> specs = {
        {"fill_rule", "d3d", "rasterizer fill rule of the primary visibility: 'd3d' or 'gl'"}};
    for (ParamSpec& spec : path_param_specs()) specs.push_back(std::move(spec));
    for (ParamSpec& spec : bmfr_param_specs()) specs.push_back(std::move(spec));
    return specs;
}

Pipeline pathtrace_pipeline(const Scene*, const RenderSettings& settings) {
    const std::vector<ParamSpec> specs = pathtrace_param_specs();
    RasterSettings raster;
    raster.fill_rule =
        parse_fill_rule(settings.params.get_string(specs, "fill_rule"), "parameter 'fill_rule'");
    PathTraceStage trace;
    trace.path = parse_path_params(settings.params, specs);
    trace.bvh = std::make_shared<BvhCache>();
    trace.path_end_counters = true;
    const BmfrSettings bmfr = parse_bmfr_params(settings.params);
    if (bmfr.enabled) {
        trace.radiance = "radiance";
        trace.emission = "emission";
    }
    Pipeline p;
    p.add(rasterize_stage_def("primary_visibility", raster)).add(pathtrace_stage_def(trace));
    if (bmfr.enabled) add_bmfr_stages(p, {bmfr, "radiance", "emission", "final"});
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> pathtrace_pixel_functions(const Params& params) {
    std::vector<PixelFunction> functions = raster_pixel_functions("primary_visibility");
    functions.push_back({"pathtrace", "fovref::pathtrace_pixel", ""});
    if (parse_bmfr_params(params).enabled)
        for (PixelFunction& f : bmfr_pixel_functions("", bmfr_screen_block))
            functions.push_back(std::move(f));
    return functions;
}

std::vector<ParamSpec> pathtrace_reference_param_specs() {
    return {{"spp", "1024", "samples per pixel (1..65536); --resume DIR continues an earlier run"},
            {"max_bounces", "1", "secondary rays per path, as pathtrace"},
            {"rr", "0.8", "Russian-roulette continuation probability, as pathtrace"},
            {"mis", "off", "multiple importance sampling, as pathtrace"},
            {"reference_jitter", "per-pixel",
             "primary-ray jitter: 'per-pixel' (one sequence rotated per pixel, coverage errors "
             "uncorrelated along edges) or 'shared' (the same jitter in every pixel); "
             "docs/pathtrace.md"}};
}

Pipeline pathtrace_reference_pipeline(const Scene*, const RenderSettings& settings) {
    const std::vector<ParamSpec> specs = pathtrace_reference_param_specs();
    const int spp = settings.params.get_int(specs, "spp", 1, 65536);
    const bool shared_jitter =
        settings.params.get_choice(specs, "reference_jitter", {"per-pixel", "shared"}) == 1;
    Pipeline p;
    p.add(pathtrace_reference_stage_def(
        parse_path_params(settings.params, specs, false), spp,
        shared_jitter ? ReferenceJitter::shared : ReferenceJitter::per_pixel,
        std::make_shared<BvhCache>()));
    p.final_outputs = p.all_outputs();
    return p;
}

}  // namespace

ModeInfo basic_mode() {
    ModeInfo m;
    m.name = "basic";
    m.description =
        "one ray per pixel centre, Lambertian shading with one shadow ray per light (Lund §3.1)";
    m.params = basic_param_specs();
    for (ParamSpec& spec : taa_param_specs()) m.params.push_back(std::move(spec));
    for (ParamSpec& spec : frustum_param_specs()) m.params.push_back(std::move(spec));
    m.build = basic_pipeline;
    m.explain = explain_basic_taa;
    m.pixel_functions = basic_pixel_functions;
    return m;
}

ModeInfo ground_truth_mode() {
    ModeInfo m;
    m.name = "ground-truth";
    m.description = "16 Halton(2,3) rays per pixel, shaded as basic, box-filtered (Lund §3.2)";
    m.build = ground_truth_pipeline;
    m.explain = explain_ground_truth;
    m.pixel_functions = ground_truth_pixel_functions;
    return m;
}

ModeInfo pathtrace_mode() {
    ModeInfo m;
    m.name = "pathtrace";
    m.description =
        "1-spp path tracing from the rasterized G-buffer: next-event estimation to one light, "
        "one cosine-weighted secondary ray, NEE at its hit (Koskela §2.4; SPEC §8)";
    m.params = pathtrace_param_specs();
    m.build = pathtrace_pipeline;
    m.pixel_functions = pathtrace_pixel_functions;
    m.explain = explain_bmfr_pixel;  // the BMFR phases (nothing without denoise=bmfr)
    m.stateless = true;              // unless denoise=bmfr (carries_state)
    return m;
}

ModeInfo pathtrace_reference_mode() {
    ModeInfo m;
    m.name = "pathtrace-reference";
    m.description =
        "the converged reference of pathtrace: N jittered samples per pixel averaged, a "
        "standard-error image, resumable sums (SPEC §8)";
    m.params = pathtrace_reference_param_specs();
    m.build = pathtrace_reference_pipeline;
    m.resume_same_frame = true;
    return m;
}

}  // namespace fovref
