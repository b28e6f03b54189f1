#include "ref/trace/stages.h"

#include <cstdio>
#include <utility>

#include "ref/core/error.h"
#include "ref/trace/ground_truth.h"
#include "ref/trace/pathtrace_reference.h"
#include "ref/trace/raycast_gbuffer.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};

struct RaycastState : StageState {
    std::shared_ptr<BvhCache> bvh;
    FrameJitter jitter;
};

struct ShadeState : StageState {
    std::shared_ptr<BvhCache> bvh;
    ShadeView view;
};

struct SupersampleState : StageState {
    std::shared_ptr<BvhCache> bvh;
};

struct PathTraceState : StageState {
    PathTraceStage config;
};

struct ReferenceState : StageState {
    PathTraceParams path;
    int spp = 1024;
    ReferenceJitter jitter = ReferenceJitter::per_pixel;
    std::shared_ptr<BvhCache> bvh;
};

// The BVH when shading needs one: no lights, no shadow rays, so no BVH is built for shading.
const Bvh* shading_bvh(FrameContext& ctx, BvhCache& bvh) {
    return ctx.scene->lights.empty() ? nullptr : &bvh.get(*ctx.scene, ctx.result->counters);
}

// "max_bounces N" and whether shadow rays were traced: the path tracer's stage note.
std::string path_note(const Scene& scene, const PathTraceParams& path) {
    return "max_bounces " + std::to_string(path.max_bounces) +
           (scene.lights.empty() ? ", no lights: no shadow rays" : "");
}

// The sums of an earlier run of the same frame (`fovref render --resume DIR`), or none.
PathReferenceSums resumed_reference_sums(const FrameContext& ctx) {
    const int width = ctx.settings->width, height = ctx.settings->height;
    PathReferenceSums sums = empty_reference_sums(width, height);
    const auto find = [&](const std::string& name) -> const Image* {
        for (const Buffer& b : ctx.settings->state_buffers)
            if (b.name == name) return &b.image;
        return nullptr;
    };
    const Image* count = find("reference_count");
    if (!count) return sums;
    const auto get = [&](const std::string& name) {
        const Image* image = find(name);
        if (!image || image->width != width || image->height != height || image->channels != 3)
            throw Error("--resume: buffer '" + name + "' is missing or not " +
                        std::to_string(width) + "x" + std::to_string(height) + "x3");
        return *image;
    };
    sums.sum = get("reference_sum");
    sums.compensation = get("reference_compensation");
    sums.squares = get("reference_squares");
    if (count->data.size() != 1 || !(count->data[0] >= 1.0f) || count->data[0] > 65536.0f ||
        count->data[0] != static_cast<float>(static_cast<int>(count->data[0])))
        throw Error("--resume: buffer 'reference_count' must hold one sample count in 1..65536");
    sums.count = static_cast<int>(count->data[0]);
    return sums;
}

// The reference's outputs and its note: the mean, its standard error, the running sums.
void output_reference(FrameContext& ctx, PathReferenceSums sums, int resumed) {
    Image mean, error;
    reference_estimate(sums, mean, error);
    double total = 0.0;
    for (float v : error.data) total += v;
    const double mean_error = total / static_cast<double>(error.data.size());
    char text[160];
    std::snprintf(text, sizeof text,
                  "%d samples per pixel (%d resumed), mean standard error %.3g (linear radiance)",
                  sums.count, resumed, mean_error);
    ctx.note = text;
    // the mean standard error in units of 1e-9, for scripts that read counters
    ctx.result->counters.add("reference_mean_standard_error_e9",
                             static_cast<std::int64_t>(mean_error * 1e9));
    ctx.output("final", BufferKind::color, rgb, std::move(mean));
    ctx.output("standard_error", BufferKind::scalar, rgb, std::move(error));
    ctx.output("reference_sum", BufferKind::scalar, rgb, std::move(sums.sum));
    ctx.output("reference_compensation", BufferKind::scalar, rgb, std::move(sums.compensation));
    ctx.output("reference_squares", BufferKind::scalar, rgb, std::move(sums.squares));
    ctx.output("reference_count", BufferKind::scalar, {"n"},
               Image(1, 1, 1, static_cast<float>(sums.count)));
}

}  // namespace

PrimaryView primary_view(FrameContext& ctx, BvhCache& bvh) {
    return {*ctx.scene, bvh.get(*ctx.scene, ctx.result->counters), ctx.camera, ctx.previous_camera};
}

ShadeInputs shade_inputs_of(const FrameContext& ctx) {
    return {ctx.input("world_position"), ctx.input("shading_normal"), ctx.input("geometric_normal"),
            ctx.input("albedo"),         ctx.input("material_id"),    ctx.input("primitive_id")};
}

void add_shading_counters(Counters& counters, const ShadingStats& stats) {
    counters.add("pixels_shaded", stats.shaded);
    counters.add("texture_fetches", stats.texture_fetches);
    counters.add("light_samples_facing_away", stats.lights_facing_away);
    counters.add("light_samples_degenerate", stats.light_samples_degenerate);
    counters.add("nonfinite_inputs_replaced", stats.nonfinite_inputs);
    counters.add("invalid_material_ids", stats.invalid_material_ids);
    counters.add("shadow_rays_occluded", stats.shadow_rays_occluded);
    add_trace_counters(counters, "shadow", stats.shadow_trace);
}

std::string shadow_note(const Scene& scene) {
    return scene.lights.empty() ? "no lights: no shadow rays traced" : "";
}

void raycast_stage(FrameContext& ctx) {
    RaycastState& state = ctx.state<RaycastState>();
    RaycastStats stats;
    const Offset2 jitter = state.jitter ? state.jitter(ctx) : Offset2{};
    GBuffer g = raycast_gbuffer(primary_view(ctx, *state.bvh), ctx.settings->width,
                                ctx.settings->height, stats, jitter);
    add_trace_counters(ctx.result->counters, "primary", stats.primary);
    ctx.note = jitter == Offset2{} ? "ray cast"
                                   : "ray cast, jittered to (" + std::to_string(jitter.x) + ", " +
                                         std::to_string(jitter.y) + ") in each pixel";
    output_gbuffer(ctx, std::move(g));
}

StageDef raycast_stage_def(std::shared_ptr<BvhCache> bvh, FrameJitter jitter) {
    auto state = std::make_shared<RaycastState>();
    state->bvh = std::move(bvh);
    state->jitter = std::move(jitter);
    return {"primary_visibility", {}, gbuffer_ports(), raycast_stage, state};
}

void shade_stage(FrameContext& ctx) {
    ShadeState& state = ctx.state<ShadeState>();
    const Scene& scene = *ctx.scene;
    ShadeInputs inputs = shade_inputs_of(ctx);
    std::optional<ScreenWindow> window;
    if (state.view.window) window = state.view.window(ctx);
    inputs.window = window ? &*window : nullptr;
    const Bvh* tree = shading_bvh(ctx, *state.bvh);
    ShadingStats stats;
    Image out = state.view.eye_cameras
                    ? shade_stereo(scene, tree, inputs, state.view.eye_cameras(ctx),
                                   inputs.position.width / 2, ctx.frame, stats)
                    : shade_basic(scene, tree, inputs, ctx.camera, ctx.frame, stats);
    add_shading_counters(ctx.result->counters, stats);
    ctx.note = shadow_note(scene);
    ctx.output("color", BufferKind::color, rgb, std::move(out));
}

StageDef shade_stage_def(std::string name, const std::string& prefix, std::string output,
                         std::shared_ptr<BvhCache> bvh, ShadeView view) {
    auto state = std::make_shared<ShadeState>();
    state->bvh = std::move(bvh);
    state->view = std::move(view);
    return {
        std::move(name), shading_ports(prefix), {{"color", std::move(output)}}, shade_stage, state};
}

void supersample_stage(FrameContext& ctx) {
    const Scene& scene = *ctx.scene;
    TraceStats primary;
    ShadingStats shading;
    Image image = render_ground_truth(
        scene, ctx.state<SupersampleState>().bvh->get(scene, ctx.result->counters), ctx.camera,
        static_cast<std::uint32_t>(ctx.frame), ctx.settings->width, ctx.settings->height, primary,
        shading);
    add_trace_counters(ctx.result->counters, "primary", primary);
    add_shading_counters(ctx.result->counters, shading);
    ctx.note = shadow_note(scene);
    ctx.output("final", BufferKind::color, rgb, std::move(image));
}

StageDef supersample_stage_def(std::shared_ptr<BvhCache> bvh) {
    auto state = std::make_shared<SupersampleState>();
    state->bvh = std::move(bvh);
    return {"supersample", {}, {"final"}, supersample_stage, state};
}

void pathtrace_stage(FrameContext& ctx) {
    const PathTraceStage& config = ctx.state<PathTraceState>().config;
    const Scene& scene = *ctx.scene;
    PathTraceStats stats;
    Image emission;
    const bool with_emission = !config.emission.empty();
    Image out = pathtrace(scene, config.bvh->get(scene, ctx.result->counters), config.path,
                          shade_inputs_of(ctx), ctx.camera, ctx.frame, stats,
                          with_emission ? &emission : nullptr,
                          config.mask.empty() ? nullptr : &ctx.input("mask"));
    Counters& counters = ctx.result->counters;
    add_shading_counters(counters, stats.shading);
    add_trace_counters(counters, "secondary", stats.secondary);
    counters.add("paths", stats.paths);
    if (config.path_end_counters) {
        counters.add("paths_ended_background", stats.ended_background);
        counters.add("paths_ended_black", stats.ended_black);
        counters.add("paths_ended_roulette", stats.ended_roulette);
        counters.add("paths_ended_below_surface", stats.ended_below);
    }
    ctx.note = path_note(scene, config.path);
    ctx.output("radiance", BufferKind::color, rgb, std::move(out));
    if (with_emission) ctx.output("emission", BufferKind::color, rgb, std::move(emission));
}

StageDef pathtrace_stage_def(PathTraceStage config) {
    std::vector<Port> inputs = shading_ports(config.gbuffer);
    if (!config.mask.empty()) inputs.emplace_back("mask", config.mask);
    std::vector<Port> outputs = {{"radiance", config.radiance}};
    if (!config.emission.empty()) outputs.emplace_back("emission", config.emission);
    auto state = std::make_shared<PathTraceState>();
    std::string name = config.name;
    state->config = std::move(config);
    return {std::move(name), std::move(inputs), std::move(outputs), pathtrace_stage, state};
}

void pathtrace_reference_stage(FrameContext& ctx) {
    const ReferenceState& state = ctx.state<ReferenceState>();
    const Scene& scene = *ctx.scene;
    PathReferenceSums sums = resumed_reference_sums(ctx);
    const int resumed = sums.count;
    if (resumed > state.spp)
        throw Error("--resume: the bundle already holds " + std::to_string(resumed) +
                    " samples, more than spp=" + std::to_string(state.spp));
    TraceStats primary;
    PathTraceStats stats;
    pathtrace_reference(scene, state.bvh->get(scene, ctx.result->counters), state.path, ctx.camera,
                        ctx.frame, state.spp, state.jitter, sums, primary, stats,
                        [&](double f) { ctx.report(f); });
    Counters& counters = ctx.result->counters;
    add_trace_counters(counters, "primary", primary);
    add_shading_counters(counters, stats.shading);
    add_trace_counters(counters, "secondary", stats.secondary);
    counters.add("paths", stats.paths);
    counters.add("reference_samples", sums.count);
    counters.add("reference_samples_resumed", resumed);
    output_reference(ctx, std::move(sums), resumed);
}

StageDef pathtrace_reference_stage_def(PathTraceParams path, int spp, ReferenceJitter jitter,
                                       std::shared_ptr<BvhCache> bvh) {
    auto state = std::make_shared<ReferenceState>();
    state->path = path;
    state->spp = spp;
    state->jitter = jitter;
    state->bvh = std::move(bvh);
    return {"pathtrace_reference",
            {},
            {"final", "standard_error", "reference_sum", "reference_compensation",
             "reference_squares", "reference_count"},
            pathtrace_reference_stage,
            state};
}

}  // namespace fovref
