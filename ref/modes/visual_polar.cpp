#include "ref/modes/visual_polar.h"

#include <memory>

#include "ref/bmfr/probe.h"
#include "ref/bmfr/stages.h"
#include "ref/filters/stages.h"
#include "ref/trace/stages.h"
#include "ref/visual_polar/probe.h"
#include "ref/visual_polar/stages.h"

namespace fovref {

namespace {

std::vector<ParamSpec> visual_polar_param_specs(bool path_traced) {
    std::vector<ParamSpec> specs =
        sparse_param_specs(path_traced ? "visual-polar" : "visual-polar-basic");
    if (path_traced)
        specs = concat_specs(concat_specs(specs, path_param_specs()), bmfr_param_specs("bmfr"));
    return specs;
}

// ---- visual-polar, visual-polar-basic --------------------------------------------------------

Pipeline vp_pipeline(const RenderSettings& settings, bool path_traced) {
    std::shared_ptr<SparseFrames> frames =
        sparse_frames(settings.params, path_traced ? "visual-polar" : "visual-polar-basic");
    // Validate the map now (buffer size, gaze), not in the first stage
    sparse_vp_map(frames->params, settings.width, settings.height, 0);
    auto bvh = std::make_shared<BvhCache>();
    Pipeline p;
    p.add(vp_trace_stage_def(frames, bvh));
    if (path_traced)
        add_polar_path_tracing(
            p, settings.params, visual_polar_param_specs(true), "vp",
            [frames](const FrameContext& ctx, int frame) { return frames->map(ctx, frame); }, bvh);
    else
        p.add(shade_stage_def("vp_shade", "vp_gbuffer_", "vp_color", bvh));
    const SparseParams& params = frames->params;
    p.add(vp_resolve_stage_def(frames, params.blur ? "resolved" : "final"));
    if (params.blur)
        for (StageDef& stage :
             blur_ramp_stage_defs(params.ramp, "resolved", "final", blur_geometry_of(frames)))
            p.add(std::move(stage));
    p.final_outputs = {"final"};
    return p;
}

// The cell of frame `frame`'s Visual-Polar BMFR grid that covers texel `texel`.
glm::ivec2 vp_bmfr_block(const RenderSettings& settings, int frame, glm::ivec2 texel) {
    const VisualPolarMap map = sparse_vp_map(parse_sparse_params(settings.params, "visual-polar"),
                                             settings.width, settings.height, frame);
    return bmfr_grid(map.width, map.height, frame, &map,
                     parse_bmfr_params(settings.params, "bmfr").params.block_size)
        .cell_of(texel.x, texel.y);
}

std::vector<PixelFunction> vp_pixel_functions(bool path_traced, const Params& params) {
    std::vector<PixelFunction> functions = {
        {"vp_trace", "fovref::vp_gbuffer_texel", "", PixelArgs::texel, "vp_"}};
    if (!path_traced) {
        functions.push_back({"vp_shade", "fovref::shade_basic_pixel", "", PixelArgs::texel, "vp_"});
    } else {
        functions.push_back(
            {"vp_pathtrace", "fovref::pathtrace_pixel", "", PixelArgs::texel, "vp_"});
        if (parse_bmfr_params(params, "bmfr").enabled)
            for (PixelFunction& f : bmfr_pixel_functions("vp_", vp_bmfr_block))
                functions.push_back(std::move(f));
    }
    functions.push_back({"resolve", "fovref::resolve_vp_pixel", ""});
    if (parse_sparse_params(params, path_traced ? "visual-polar" : "visual-polar-basic").blur) {
        functions.push_back({"blur_horizontal", "fovref::blur_ramp_pixel", "vertical = false"});
        functions.push_back({"blur_vertical", "fovref::blur_ramp_pixel", "vertical = true"});
    }
    return functions;
}

// visual-polar's probe: the Visual-Polar explanation and, for a traced texel of a frame BMFR
// denoised, the block that denoised it.
void explain_visual_polar_bmfr(const ProbeContext& c, ProbeReport& report) {
    explain_visual_polar(c, report);
    if (!c.texel || !c.frame->find("bmfr_weights")) return;
    const SparseParams params = parse_sparse_params(c.settings->params, report.mode);
    const VisualPolarMap m =
        sparse_vp_map(params, c.settings->width, c.settings->height, c.frame->frame);
    glm::vec2 point{0.0f};
    if (vp_texel_status(m, c.texel->x, c.texel->y, point) == VpTexel::traced)
        explain_bmfr_block(c, m, c.texel->x, c.texel->y, report);
}

std::vector<TexelRead> vp_pixel_texels(const Scene&, const RenderSettings& settings, int frame,
                                       int x, int y, const std::string& mode) {
    const VisualPolarMap map = sparse_vp_map(parse_sparse_params(settings.params, mode),
                                             settings.width, settings.height, frame);
    std::vector<TexelRead> reads;
    for (const glm::ivec2& texel : vp_resolve_taps(map, x, y)) reads.push_back({"vp_", texel});
    return reads;
}

ModeInfo sparse_mode(std::string name, std::string description) {
    ModeInfo m;
    m.name = std::move(name);
    m.description = std::move(description);
    return m;
}

}  // namespace

void add_polar_path_tracing(Pipeline& p, const Params& params, const std::vector<ParamSpec>& specs,
                            const std::string& family,
                            std::function<VisualPolarMap(const FrameContext&, int frame)> map,
                            std::shared_ptr<BvhCache> bvh) {
    PathTraceStage trace;
    trace.name = family + "_pathtrace";
    trace.gbuffer = family + "_gbuffer_";
    trace.mask = family + "_valid";
    trace.path = parse_path_params(params, specs);
    trace.bvh = std::move(bvh);
    const BmfrSettings bmfr = parse_bmfr_params(params, "bmfr");
    trace.radiance = family + (bmfr.enabled ? "_radiance" : "_color");
    if (bmfr.enabled) trace.emission = family + "_emission";
    p.add(pathtrace_stage_def(trace));
    if (!bmfr.enabled) return;
    BmfrWiring wiring{bmfr, family + "_radiance", family + "_emission", family + "_color"};
    wiring.gbuffer = family + "_gbuffer_";
    wiring.valid = family + "_valid";
    wiring.map = std::move(map);
    add_bmfr_stages(p, wiring);
}

ModeInfo visual_polar_mode() {
    ModeInfo m = sparse_mode("visual-polar",
                             "path tracing in Visual-Polar space: one path per traced texel, BMFR "
                             "on the buffer (wrap on phi, staircase blocks), phi-mip resolve, blur "
                             "ramp (Koskela P5)");
    m.params = visual_polar_param_specs(true);
    m.build = [](const Scene*, const RenderSettings& s) { return vp_pipeline(s, true); };
    m.pixel_functions = [](const Params& params) { return vp_pixel_functions(true, params); };
    m.parameters_carry_state = [](const Params& p) {  // BMFR by default
        return parse_bmfr_params(p, "bmfr").enabled;
    };
    m.explain = explain_visual_polar_bmfr;
    m.explains_texels = true;
    m.buffer_families = {{"vp_", BufferSpace::texel}};
    m.pixel_texels = [](const Scene& scene, const RenderSettings& s, int frame, int x, int y) {
        return vp_pixel_texels(scene, s, frame, x, y, "visual-polar");
    };
    return m;
}

ModeInfo visual_polar_basic_mode() {
    ModeInfo m = sparse_mode("visual-polar-basic",
                             "the basic ray tracer's shading in Visual-Polar space, phi-mip "
                             "resolve, blur ramp (for comparison with the log-polar modes)");
    m.params = visual_polar_param_specs(false);
    m.build = [](const Scene*, const RenderSettings& s) { return vp_pipeline(s, false); };
    m.pixel_functions = [](const Params& params) { return vp_pixel_functions(false, params); };
    m.explain = explain_visual_polar;
    m.explains_texels = true;
    m.buffer_families = {{"vp_", BufferSpace::texel}};
    m.pixel_texels = [](const Scene& scene, const RenderSettings& s, int frame, int x, int y) {
        return vp_pixel_texels(scene, s, frame, x, y, "visual-polar-basic");
    };
    return m;
}

}  // namespace fovref
