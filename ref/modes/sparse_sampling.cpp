#include "ref/modes/sparse_sampling.h"

#include <memory>

#include "ref/bmfr/probe.h"
#include "ref/bmfr/stages.h"
#include "ref/filters/stages.h"
#include "ref/raster/stages.h"
#include "ref/trace/stages.h"
#include "ref/visual_polar/stages.h"

namespace fovref {

namespace {

std::vector<ParamSpec> linear_falloff_param_specs() {
    std::vector<ParamSpec> specs =
        concat_specs(sparse_param_specs("linear-falloff"), path_param_specs());
    specs.push_back({"fill_rule", "d3d", "rasterizer fill rule of the primary visibility"});
    return concat_specs(specs, bmfr_param_specs());
}

std::vector<ParamSpec> acuity_param_specs() {
    return concat_specs(sparse_param_specs("acuity"), path_param_specs());
}

// ---- linear fall-off ------------------------------------------------------------------------

Pipeline linear_falloff_pipeline(const Scene*, const RenderSettings& settings) {
    std::shared_ptr<SparseFrames> frames = sparse_frames(settings.params, "linear-falloff");
    const std::vector<ParamSpec> specs = linear_falloff_param_specs();
    PathTraceStage trace;
    trace.mask = "sample_mask";
    trace.radiance = "sparse_radiance";
    trace.path = parse_path_params(settings.params, specs);
    trace.bvh = std::make_shared<BvhCache>();
    RasterSettings raster;
    raster.fill_rule =
        parse_fill_rule(settings.params.get_string(specs, "fill_rule"), "parameter 'fill_rule'");
    const BmfrSettings bmfr = parse_bmfr_params(settings.params);
    const bool separate = bmfr.enabled && bmfr.params.separate_emission;
    if (separate) trace.emission = "sparse_emission";
    // P5's linear fall-off with blur: the ramp on the image the fill (or BMFR) makes
    const bool blur = frames->params.blur;
    const std::string image = blur ? "unblurred" : "final";
    Pipeline p;
    p.add(rasterize_stage_def("primary_visibility", raster)).add(falloff_mask_stage_def(frames));
    p.add(pathtrace_stage_def(trace));
    p.add(fill_stage_def(frames, bmfr.enabled ? "filled" : image, separate));
    if (bmfr.enabled) add_bmfr_stages(p, {bmfr, "filled", "filled_emission", image});
    if (blur)
        for (StageDef& stage :
             blur_ramp_stage_defs(frames->params.ramp, image, "final", blur_geometry_of(frames)))
            p.add(std::move(stage));
    p.final_outputs = {"final"};
    return p;
}

// ---- acuity ---------------------------------------------------------------------------------

Pipeline acuity_pipeline(const Scene*, const RenderSettings& settings) {
    std::shared_ptr<SparseFrames> frames = sparse_frames(settings.params, "acuity");
    PathTraceStage trace;
    trace.name = "acuity_shade";
    trace.gbuffer = "acuity_gbuffer_";
    trace.mask = "acuity_valid";
    trace.radiance = "acuity_radiance";
    trace.path = parse_path_params(settings.params, acuity_param_specs());
    trace.bvh = std::make_shared<BvhCache>();
    acuity_samples_per_frame(frames->params, settings.width, settings.height);  // validated now
    Pipeline p;
    p.add(acuity_trace_stage_def(frames, trace.bvh)).add(pathtrace_stage_def(trace));
    p.add(acuity_accumulate_stage_def(frames)).add(acuity_resolve_stage_def(frames));
    p.final_outputs = {"final"};
    return p;
}

}  // namespace

ModeInfo linear_falloff_mode() {
    ModeInfo m;
    m.name = "linear-falloff";
    m.description =
        "1-spp path tracing of pixels drawn with the linear fall-off probability L(e), push-pull "
        "fill, optional BMFR (Weier et al.; Koskela eq. 4.1)";
    m.params = linear_falloff_param_specs();
    m.build = linear_falloff_pipeline;
    m.explain = explain_bmfr_pixel;  // the BMFR phases (nothing without denoise=bmfr)
    return m;
}

ModeInfo acuity_mode() {
    ModeInfo m;
    m.name = "acuity";
    m.description =
        "N path-traced samples per frame placed by the acuity model's inverse CDF, progressive "
        "mean, unsampled pixels black (Koskela P3/P4)";
    m.params = acuity_param_specs();
    m.build = acuity_pipeline;
    m.parameters_carry_state = [](const Params& p) {  // progressive by default
        return p.get_bool(acuity_param_specs(), "progressive");
    };
    m.buffer_families = {{"acuity_gbuffer_", BufferSpace::samples},
                         {"acuity_valid", BufferSpace::samples},
                         {"acuity_point", BufferSpace::samples},
                         {"acuity_radiance", BufferSpace::samples}};
    return m;
}

}  // namespace fovref
