// log-polar-pathtrace: Koskela P5 §4.3's log-polar method, against which P5 measures
// Visual-Polar space: 1-spp path tracing directly in Meng's kernel log-polar buffer with his
// parameters (sigma = 1.8, alpha = 4, R from the corners), denoised by BMFR on the buffer, then
// pass 2 to the screen. The buffer is handed to BMFR as a polar buffer (vp_log_polar_map):
// every column has all h rows, the rows (the angle) wrap around, the reprojection goes through
// the previous screen and the previous frame's lp_forward (docs/bmfr.md, "Log-polar space").
#include <algorithm>
#include <iterator>
#include <memory>

#include "ref/bmfr/probe.h"
#include "ref/bmfr/stages.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/stages.h"
#include "ref/modes/log_polar.h"
#include "ref/modes/visual_polar.h"
#include "ref/trace/pathtrace.h"
#include "ref/visual_polar/map.h"

namespace fovref {

namespace {

FoveationPreset lp_pathtrace_preset() {
    FoveationPreset p = find_foveation_preset("kfr");  // Meng's map: sigma 1.8, alpha 4, corners
    p.name = "log-polar-pathtrace";
    p.source = "Koskela P5 §4.3 with Meng 2018's parameters";
    p.primary = "ray";
    p.resolve = "bilinear";
    p.filters = "";
    return p;
}

// The log-polar parameters this mode does not take: no gaze buffer, no rasterized G-buffer, no
// buffer- or screen-space filters (BMFR denoises).
const char* const fixed_params[] = {"gaze_angle", "primary", "fill_rule", "raster_jitter",
                                    "filters"};

std::vector<ParamSpec> lp_pathtrace_param_specs() {
    std::vector<ParamSpec> specs;
    for (ParamSpec& spec : foveated_param_specs(lp_pathtrace_preset()))
        if (std::find(std::begin(fixed_params), std::end(fixed_params), spec.name) ==
            std::end(fixed_params))
            specs.push_back(std::move(spec));
    return concat_specs(concat_specs(specs, path_param_specs()), bmfr_param_specs("bmfr"));
}

// The log-polar map of frame `frame` as BMFR's polar buffer (no gaze buffer: the display
// distance does not enter).
VisualPolarMap polar_map(const FoveatedParams& params, int width, int height, int frame) {
    return vp_log_polar_map(make_log_polar_map(params.map, width, height,
                                               gaze_point(params, width, height, frame), 0.0f));
}

Pipeline lp_pathtrace_pipeline(const Scene*, const RenderSettings& settings) {
    LogPolarStage lp;
    lp.frames = std::make_shared<LogPolarFrames>();
    lp.frames->params = parse_foveated_params(settings.params, lp_pathtrace_preset());
    log_polar_buffer_size(lp.frames->params.map, settings.width, settings.height);  // validates
    lp.bvh = std::make_shared<BvhCache>();
    Pipeline p;
    p.add(lp_trace_stage_def(lp));
    add_polar_path_tracing(
        p, settings.params, lp_pathtrace_param_specs(), "lp",
        [frames = lp.frames](const FrameContext& ctx, int frame) {
            return polar_map(frames->params, ctx.settings->width, ctx.settings->height, frame);
        },
        lp.bvh);
    p.add(resolve_stage_def(lp, "lp_color", "final"));
    p.add(ray_positions_stage_def(lp));
    p.final_outputs = {"final"};
    return p;
}

// The cell of frame `frame`'s BMFR grid on the buffer that covers texel `texel`.
glm::ivec2 lp_bmfr_block(const RenderSettings& settings, int frame, glm::ivec2 texel) {
    const FoveatedParams params = parse_foveated_params(settings.params, lp_pathtrace_preset());
    const VisualPolarMap map = polar_map(params, settings.width, settings.height, frame);
    return bmfr_grid(map.width, map.height, frame, &map,
                     parse_bmfr_params(settings.params, "bmfr").params.block_size)
        .cell_of(texel.x, texel.y);
}

std::vector<PixelFunction> lp_pathtrace_pixel_functions(const Params& params) {
    std::vector<PixelFunction> functions = {
        {"lp_trace", "fovref::lp_gbuffer_texel", "", PixelArgs::texel, "lp_"},
        {"lp_pathtrace", "fovref::pathtrace_pixel", "", PixelArgs::texel, "lp_"}};
    if (parse_bmfr_params(params, "bmfr").enabled)
        for (PixelFunction& f : bmfr_pixel_functions("lp_", lp_bmfr_block))
            functions.push_back(std::move(f));
    functions.push_back({"resolve", "fovref::resolve_pixel", ""});
    return functions;
}

std::vector<TexelRead> lp_pathtrace_pixel_texels(const Scene&, const RenderSettings& settings,
                                                 int frame, int x, int y) {
    const FoveatedParams params = parse_foveated_params(settings.params, lp_pathtrace_preset());
    const VisualPolarMap map = polar_map(params, settings.width, settings.height, frame);
    bool from_gaze = false;
    std::vector<TexelRead> reads;
    for (const glm::ivec2& texel : resolve_pixel_taps(*map.log_polar, x, y, from_gaze))
        reads.push_back({"lp_", texel});
    return reads;
}

// probe --texel: the BMFR block that denoised a traced texel, with its fit checked bit for bit.
void explain_lp_pathtrace(const ProbeContext& c, ProbeReport& report) {
    if (!c.texel || !c.frame->find("bmfr_weights")) return;
    const FoveatedParams params = parse_foveated_params(c.settings->params, lp_pathtrace_preset());
    const VisualPolarMap m =
        polar_map(params, c.settings->width, c.settings->height, c.frame->frame);
    const Buffer* valid = c.frame->find("lp_valid");
    if (valid && c.texel->x < valid->image.width && c.texel->y < valid->image.height &&
        valid->image.at(c.texel->x, c.texel->y) != 0.0f)
        explain_bmfr_block(c, m, c.texel->x, c.texel->y, report);
}

}  // namespace

ModeInfo log_polar_pathtrace_mode() {
    ModeInfo m;
    m.name = "log-polar-pathtrace";
    m.description =
        "path tracing in Meng's kernel log-polar buffer (sigma 1.8, alpha 4): one path per "
        "traced texel, BMFR on the buffer (the angle wraps), bilinear resolve (Koskela P5 "
        "§4.3's log-polar method)";
    m.params = lp_pathtrace_param_specs();
    m.build = lp_pathtrace_pipeline;
    m.pixel_functions = lp_pathtrace_pixel_functions;
    m.explain = explain_lp_pathtrace;
    m.explains_texels = true;
    m.parameters_carry_state = [](const Params& p) {  // BMFR by default
        return parse_bmfr_params(p, "bmfr").enabled;
    };
    m.buffer_families = {{"lp_", BufferSpace::texel}};
    m.pixel_texels = lp_pathtrace_pixel_texels;
    return m;
}

}  // namespace fovref
