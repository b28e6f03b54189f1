#include "ref/modes/log_polar.h"

#include <algorithm>
#include <cmath>
#include <memory>

#include "ref/core/error.h"
#include "ref/filters/stages.h"
#include "ref/frustum/stages.h"
#include "ref/log_polar/deferred_sample.h"
#include "ref/log_polar/probe.h"
#include "ref/log_polar/stages.h"
#include "ref/raster/stages.h"
#include "ref/temporal/stages.h"
#include "ref/temporal/stereo_taa.h"
#include "ref/trace/stages.h"

namespace fovref {

namespace {

// The buffers' G-buffers (traced, or sampled from the rasterized screen), their shading and the
// buffer-space filter.
void add_buffer_stages(Pipeline& p, const LogPolarStage& lp, const FrustumSettings& frustum) {
    const FoveatedParams& params = lp.frames->params;
    const bool composite = params.map.gaze_angle > 0.0f;
    if (params.deferred)
        p.add(rasterize_stage_def(
                  "gbuffer_raster", params.raster,
                  params.jitter_raster ? lp.jitter : std::function<Offset2(const FrameContext&)>{}))
            .add(lp_sample_stage_def(lp));
    else
        p.add(lp_trace_stage_def(lp));
    if (composite) p.add(gaze_trace_stage_def(lp));
    if (frustum.enabled) {
        // Lund's tile frustum culling over the gaze buffer's window: tiles from its corner,
        // the pixels inside the gaze circle checked (docs/frustum.md)
        const auto frames = lp.frames;
        p.add(frustum_cull_stage_def(
            frustum, lp.bvh, "gaze_frustum_", [frames](const FrameContext& ctx) {
                const LogPolarMap map = frames->map(ctx);
                const ScreenWindow w = gaze_window(map);
                return FrustumRegion{w.x0, w.y0, w.width, w.height, [map](glm::vec2 centre) {
                                         return inside_gaze_circle(map, centre);
                                     }};
            }));
    }
    p.add(shade_stage_def("lp_shade", "lp_gbuffer_", "lp_color", lp.bvh));
    if (composite)
        p.add(shade_stage_def("gaze_shade", "gaze_gbuffer_", "gaze_color", lp.bvh,
                              {gaze_window_of(lp.frames), {}}));
    if (params.internal_aa) p.add(internal_aa_stage_def("lp_color", "lp_valid", "lp_color_aa"));
}

// Meng's post-AA around the frame's gaze, out to the map's R.
std::function<PostAaGeometry(const FrameContext&)> post_aa_geometry_of(
    std::shared_ptr<LogPolarFrames> frames) {
    return [frames](const FrameContext& ctx) {
        const LogPolarMap map = frames->map(ctx);
        return PostAaGeometry{map.gaze, map.radius_max};
    };
}

// Pass 2, TAA, then the screen-space filters (SPEC §6), each reading the buffer the one before
// wrote: screen_chain (resolved, taa_color, lerp_filtered, ..., the last named final).
void add_screen_stages(Pipeline& p, const LogPolarStage& lp, const TaaSettings& taa) {
    const FoveatedParams& params = lp.frames->params;
    const std::vector<std::string> chain = screen_chain(params, taa.enabled());
    const std::string color = resolve_color_name(params);
    p.add(resolve_stage_def(lp, color, chain[0]));
    std::size_t link = 0;
    if (taa.enabled()) {
        // The texel pass 2 sampled: the depth (kfr has its full-resolution G-buffer's) and, for
        // clamp-buffer, the box in the buffer.
        const bool boxes = taa.mode == TaaMode::clamp_buffer;
        if (!params.deferred || boxes) p.add(taa_source_stage_def(lp, taa, color, chain[0]));
        const std::string depth = params.deferred ? "gbuffer_view_depth" : "taa_view_depth";
        p.add(taa_stage_def(taa, {chain[0], depth, boxes ? "taa_bounds" : "", chain[1]},
                            gaze_of(lp.frames)));
        ++link;
    }
    if (params.gaussian_lerp) {
        p.add(gaussian_lerp_stage_def(chain[link], chain[link + 1], gaze_of(lp.frames)));
        ++link;
    }
    if (params.post_aa)
        p.add(post_aa_stage_def(chain[link], chain[link + 1], post_aa_geometry_of(lp.frames)));
}

Pipeline foveated_pipeline(const std::string& preset, const Scene* scene,
                           const RenderSettings& settings) {
    LogPolarStage lp;
    lp.frames = std::make_shared<LogPolarFrames>();
    lp.frames->params = parse_foveated_params(settings.params, find_foveation_preset(preset));
    // Validate the map's parameters now (the buffer size, a_G), not in the first stage.
    log_polar_buffer_size(lp.frames->params.map, settings.width, settings.height);
    const TaaSettings taa = parse_taa_params(settings.params);
    lp.bvh = std::make_shared<BvhCache>();
    lp.jitter = taa_frame_jitter(taa);
    const FrustumSettings frustum = parse_frustum_params(settings.params);
    if (frustum.enabled && !(lp.frames->params.map.gaze_angle > 0.0f))
        throw Error(
            "parameter 'frustum': the log-polar modes cull the tiles of the gaze buffer, which "
            "needs gaze_angle > 0 (cfov, ckfov); for the screen's tiles use mode basic");
    if (frustum.enabled && frustum.shadow && scene)  // the light checked before any work
        shadow_light(*scene, frustum.light, "parameter 'frustum_light'",
                     "parameter 'frustum_shadow'");
    Pipeline p;
    add_buffer_stages(p, lp, frustum);
    add_screen_stages(p, lp, taa);
    p.add(ray_positions_stage_def(lp));
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> foveated_pixel_functions(const std::string& preset,
                                                    const Params& params) {
    const FoveatedParams p = parse_foveated_params(params, find_foveation_preset(preset));
    const bool composite = p.map.gaze_angle > 0.0f;
    const PixelArgs texel = PixelArgs::texel;
    std::vector<PixelFunction> functions;
    if (p.deferred) {
        // The G-buffer pixels' attributes are made in lp_sample (write_rasterized_pixel), not by
        // the raster stage's attribute pass, which a render without dumps skips.
        functions = raster_pixel_functions("gbuffer_raster", "gbuffer_",
                                           "the G-buffer pixels lp_sample samples", false);
        functions.push_back({"lp_sample", "fovref::deferred_gbuffer_texel",
                             "makes the sampled pixel's channels again (write_rasterized_pixel)",
                             texel, "lp_"});
    } else {
        functions.push_back({"lp_trace", "fovref::lp_gbuffer_texel", "", texel, "lp_"});
    }
    if (composite)
        functions.push_back({"gaze_trace", "fovref::gaze_gbuffer_pixel",
                             "x, y: the screen pixel inside the gaze buffer's window",
                             PixelArgs::screen, "gaze_"});
    functions.push_back({"lp_shade", "fovref::shade_basic_pixel", "", texel, "lp_"});
    if (composite)
        functions.push_back({"gaze_shade", "fovref::shade_basic_pixel", "", texel, "gaze_"});
    if (p.internal_aa)
        functions.push_back({"internal_aa", "fovref::internal_aa_texel", "", texel, "lp_"});
    functions.push_back(
        {"resolve", p.mip_resolve ? "fovref::resolve_mip_pixel" : "fovref::resolve_pixel", ""});
    if (parse_taa_params(params).enabled()) functions.push_back({"taa", "fovref::taa_pixel", ""});
    if (p.gaussian_lerp) functions.push_back({"gaussian_lerp", "fovref::gaussian_lerp_pixel", ""});
    if (p.post_aa)
        functions.push_back({"post_aa", "fovref::post_aa_cached_pixel", "post_aa_pixel's bits"});
    return functions;
}

void explain_foveated_taa(const ProbeContext& c, ProbeReport& report) {
    const FoveatedParams params =
        parse_foveated_params(c.settings->params, find_foveation_preset(report.mode));
    explain_with_taa(c, report, explain_foveated,
                     gaze_point(params, c.settings->width, c.settings->height, c.frame->frame));
}

// ---- stereo-lp ------------------------------------------------------------------------------

Pipeline stereo_pipeline(const Scene*, const RenderSettings& settings) {
    StereoStage s;
    s.frames = std::make_shared<StereoFrames>();
    s.frames->params = parse_stereo_params(settings.params);
    const TaaSettings taa = parse_taa_params(settings.params);
    if (taa.enabled() && s.frames->params.barrel)
        throw Error(std::string("parameter 'taa': ") + taa_mode_name(taa.mode) +
                    " with barrel=on is not supported yet (TAA would have to run before the "
                    "distortion that pass 2 applies): use barrel=off");
    log_polar_buffer_size(s.frames->params.eye.map, stereo_eye_width(settings.width),
                          settings.height);
    s.bvh = std::make_shared<BvhCache>();
    s.jitter = taa_frame_jitter(taa);
    const auto eye_cameras = [frames = s.frames](const FrameContext& ctx) {
        return frames->cameras(ctx);
    };
    Pipeline p;
    p.add(stereo_trace_stage_def(s));
    p.add(shade_stage_def("stereo_shade", "lp_gbuffer_", "lp_color", s.bvh, {{}, eye_cameras}));
    if (s.frames->params.blur) p.add(stereo_internal_aa_stage_def());
    p.add(stereo_resolve_stage_def(s, taa.enabled() ? "resolved" : "final"));
    if (taa.enabled()) p.add(stereo_taa_source_stage_def(s, taa)).add(stereo_taa_stage_def(s, taa));
    p.add(stereo_ray_positions_stage_def(s));
    p.final_outputs = {"final"};
    return p;
}

std::vector<PixelFunction> stereo_pixel_functions(const Params& params) {
    std::vector<PixelFunction> functions = {
        {"stereo_trace", "fovref::stereo_gbuffer_texel", "x: the column in both eyes' buffer",
         PixelArgs::texel, "lp_"},
        {"stereo_shade", "fovref::shade_basic_pixel", "x: the column in both eyes' buffer",
         PixelArgs::texel, "lp_"},
        {"resolve", "fovref::resolve_stereo_pixel", ""}};
    if (parse_taa_params(params).enabled())
        functions.push_back(
            {"taa", "fovref::taa_pixel", "x, y: the pixel within its eye", PixelArgs::eye_pixel});
    return functions;
}

// The frame's camera (the camera path at the frame's time).
Camera frame_camera(const Scene& scene, const RenderSettings& settings, int frame) {
    return camera_at(scene, settings.time_start + static_cast<float>(frame) * settings.time_step);
}

// Meng's deferred variant: the rasterized G-buffer pixels that lp_sample copies into `texels`
// (each texel's screen point after the frame's jitter, floored), as family "gbuffer_".
std::vector<TexelRead> deferred_sampled_pixels(const LogPolarMap& map, glm::vec2 offset,
                                               const std::vector<TexelRead>& texels) {
    const LpInverseTable table = lp_inverse_table(map, Offset2{}, offset);
    std::vector<TexelRead> pixels;
    for (const TexelRead& read : texels) {
        glm::vec2 p{0.0f};
        if (read.family != "lp_" ||
            lp_texel_status(map, table, read.texel.x, read.texel.y, p) != TexelStatus::traced)
            continue;
        const TexelRead pixel{
            "gbuffer_", {static_cast<int>(std::floor(p.x)), static_cast<int>(std::floor(p.y))}};
        if (std::find(pixels.begin(), pixels.end(), pixel) == pixels.end()) pixels.push_back(pixel);
    }
    return pixels;
}

std::vector<TexelRead> foveated_pixel_texels(const std::string& preset, const Scene& scene,
                                             const RenderSettings& settings, int frame, int x,
                                             int y) {
    const FoveatedParams params =
        parse_foveated_params(settings.params, find_foveation_preset(preset));
    const Camera camera = frame_camera(scene, settings, frame);
    const LogPolarMap map =
        foveated_map(params, scene, camera, settings.width, settings.height, frame);
    bool from_gaze = false;
    std::vector<TexelRead> reads;
    for (const glm::ivec2& texel : resolve_pixel_taps(map, x, y, from_gaze))
        reads.push_back({from_gaze ? "gaze_" : "lp_", texel});
    if (params.deferred) {
        // The frame's jitter, as the stage computes it (taa_frame_jitter): frame f's previous
        // camera is frame f - 1's
        const Camera previous = frame > 0 ? frame_camera(scene, settings, frame - 1) : camera;
        const Offset2 jitter =
            taa_jitter(parse_taa_params(settings.params), frame, !(camera == previous));
        for (TexelRead& pixel : deferred_sampled_pixels(
                 map, deferred_sample_offset(params.jitter_raster, jitter), reads))
            reads.push_back(std::move(pixel));
    }
    return reads;
}

std::vector<TexelRead> stereo_pixel_texels(const Scene& scene, const RenderSettings& settings,
                                           int frame, int x, int y) {
    const StereoParams params = parse_stereo_params(settings.params);
    std::vector<TexelRead> reads;
    for (const glm::ivec2& texel :
         stereo_pixel_taps(params,
                           stereo_maps(params, scene, frame_camera(scene, settings, frame),
                                       settings.width, settings.height, frame),
                           x, y))
        reads.push_back({"lp_", texel});
    return reads;
}

}  // namespace

ModeInfo foveated_mode(const std::string& preset_name, const std::string& what) {
    const FoveationPreset& preset = find_foveation_preset(preset_name);
    ModeInfo m;
    m.name = preset_name;
    m.description = what + " (" + preset.source + ")";
    m.params = foveated_param_specs(preset);
    for (ParamSpec& spec : taa_param_specs()) m.params.push_back(std::move(spec));
    for (ParamSpec& spec : frustum_param_specs()) m.params.push_back(std::move(spec));
    m.build = [preset_name](const Scene* scene, const RenderSettings& settings) {
        return foveated_pipeline(preset_name, scene, settings);
    };
    m.explain = explain_foveated_taa;
    m.explains_texels = true;
    m.pixel_functions = [preset_name](const Params& params) {
        return foveated_pixel_functions(preset_name, params);
    };
    m.buffer_families = {{"lp_", BufferSpace::texel}, {"gaze_", BufferSpace::screen_window}};
    m.pixel_texels = [preset_name](const Scene& scene, const RenderSettings& settings, int frame,
                                   int x, int y) {
        return foveated_pixel_texels(preset_name, scene, settings, frame, x, y);
    };
    return m;
}

ModeInfo stereo_mode() {
    ModeInfo m;
    m.name = "stereo-lp";
    m.description =
        "both eyes side by side in one pass, each with its own camera (+-IPD/2), gaze and "
        "log-polar buffer; optional barrel distortion (Gupta 2019)";
    m.params = stereo_param_specs();
    for (ParamSpec& spec : taa_param_specs()) m.params.push_back(std::move(spec));
    m.build = stereo_pipeline;
    m.explain = explain_stereo_taa;
    m.explains_texels = true;
    m.pixel_functions = stereo_pixel_functions;
    m.buffer_families = {{"lp_", BufferSpace::stereo_texel}};
    m.pixel_texels = stereo_pixel_texels;
    return m;
}

}  // namespace fovref
