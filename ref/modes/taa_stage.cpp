#include "ref/modes/taa_stage.h"

#include "ref/core/error.h"
#include "ref/modes/mode_common.h"
#include "ref/temporal/taa_probe.h"

namespace fovref {

namespace {

// Halton point index of this frame, -1 when the jitter is off.
int jitter_index(const FrameContext& ctx, const TaaSettings& taa) {
    if (!taa.enabled() || !(ctx.camera == ctx.previous_camera)) return -1;
    return (ctx.frame + taa.jitter_start) % 16;
}

}  // namespace

TaaState resumed_taa_state(const FrameContext& ctx, const std::string& output,
                           const std::string& depth) {
    TaaState s;
    s.valid = true;
    s.history = resumed_buffer(ctx, output, 3, "TAA");
    s.age = resumed_buffer(ctx, "taa_age", 1, "TAA");
    s.depth = resumed_buffer(ctx, depth, 1, "TAA");
    s.camera = ctx.previous_camera;
    return s;
}

void add_taa_counters(FrameContext& ctx, const TaaStats& stats) {
    const TaaModeState& state = ctx.mode_state<TaaModeState>();
    Counters& counters = ctx.result->counters;
    counters.add("taa_history_kept", stats.kept);
    counters.add("taa_history_rejected", stats.rejected);
    counters.add("taa_history_clamped", stats.clamped);
    counters.add("taa_periphery_kept", stats.periphery_kept);
    counters.add("taa_reprojection_skipped", stats.reprojection_skipped);
    counters.add("taa_history_nonfinite", stats.nonfinite_history);
    counters.add("taa_jitter_index", jitter_index(ctx, state.taa));
}

Offset2 frame_jitter(const FrameContext& ctx) {
    const TaaModeState& state = ctx.mode_state<TaaModeState>();
    return taa_jitter(state.taa, ctx.frame, !(ctx.camera == ctx.previous_camera));
}

void taa_stage(FrameContext& ctx) {
    TaaModeState& state = ctx.mode_state<TaaModeState>();
    const Image& color = ctx.input(state.color_input);
    const Image& depth = ctx.input(state.depth_input);
    const Image* bounds = state.bounds_input.empty() ? nullptr : &ctx.input(state.bounds_input);
    if (!state.history.valid && ctx.has_previous)
        state.history = resumed_taa_state(ctx, state.output, state.depth_input);
    const glm::vec2 gaze = state.gaze ? state.gaze(ctx)
                                      : glm::vec2(static_cast<float>(color.width) * 0.5f,
                                                  static_cast<float>(color.height) * 0.5f);
    const TaaInputs in{color, depth, ctx.camera, gaze, bounds};
    Image out, age;
    TaaStats stats;
    taa(state.taa.params, in, state.history, out, age, stats);
    add_taa_counters(ctx, stats);
    const int index = jitter_index(ctx, state.taa);
    ctx.note = std::string(taa_mode_name(state.taa.mode)) +
               (!state.history.valid                 ? ", first frame"
                : ctx.camera == state.history.camera ? ", stationary camera: no reprojection"
                                                     : ", reprojected") +
               (index < 0 ? ", no jitter" : ", Halton point " + std::to_string(index));
    state.history = next_taa_state(out, age, depth, ctx.camera);
    ctx.result->add(state.output, BufferKind::color, {"r", "g", "b"}, std::move(out));
    ctx.result->add("taa_age", BufferKind::scalar, {"age"}, std::move(age));
}

ProbeContext probe_at_jitter(const ProbeContext& c) {
    const TaaSettings taa = parse_taa_params(c.settings->params);
    ProbeContext jittered = c;
    const Camera previous =
        c.previous_frame && c.previous_frame->camera ? *c.previous_frame->camera : c.camera;
    jittered.jitter = taa_jitter(taa, c.frame->frame, !(c.camera == previous));
    return jittered;
}

void explain_with_taa(const ProbeContext& c, ProbeReport& report,
                      void (*explain)(const ProbeContext&, ProbeReport&), glm::vec2 gaze) {
    const TaaSettings taa = parse_taa_params(c.settings->params);
    const ProbeContext jittered = probe_at_jitter(c);
    explain(jittered, report);
    if (taa.enabled() && !c.texel && c.frame->find("taa_age"))
        explain_taa(jittered, taa_probe_inputs(*c.frame, taa, gaze), report);
}

void add_taa_stage(Pipeline& pipeline, TaaModeState& state, const std::string& color,
                   const std::string& depth, const std::string& bounds, const std::string& output) {
    state.color_input = color;
    state.depth_input = depth;
    state.bounds_input = bounds;
    state.output = output;
    std::vector<std::string> inputs = {color, depth};
    if (!bounds.empty()) inputs.push_back(bounds);
    pipeline.stages.push_back({"taa", inputs, {output, "taa_age"}, taa_stage});
}

}  // namespace fovref
