#include "ref/temporal/stages.h"

#include <memory>
#include <optional>
#include <utility>

#include "ref/temporal/taa_foveated.h"
#include "ref/temporal/taa_probe.h"

namespace fovref {

namespace {

struct TaaStageState : StageState {
    TaaSettings taa;
    std::function<glm::vec2(const FrameContext&)> gaze;
    /// What the previous frame handed on (invalid before the first frame). Its history colour
    /// is not kept here between frames: it is the previous frame's output buffer itself, which
    /// the pipeline hands back (FrameContext::carried), so that no frame copies its output.
    TaaState history;
    /// The output and age storage of the frame before last, recycled for this frame's pass
    /// (which writes every pixel): no zero fill of 4 floats a pixel each frame.
    Image spare_output, spare_age;
};

struct TaaSourceState : StageState {
    LogPolarStage shared;
    TaaSettings taa;
    TaaSourceTable table;  ///< kept while the map repeats
};

// Halton point index of this frame, -1 when the jitter is off.
int jitter_index(const FrameContext& ctx, const TaaSettings& taa) {
    if (!taa.enabled() || !(ctx.camera == ctx.previous_camera)) return -1;
    return (ctx.frame + taa.jitter_start) % 16;
}

// The clamp-buffer boxes of a frame (W x H x 6), as TAA reads them.
void output_bounds(FrameContext& ctx, Image bounds) {
    ctx.output("bounds", BufferKind::scalar, {"min_r", "min_g", "min_b", "max_r", "max_g", "max_b"},
               std::move(bounds));
}

}  // namespace

FrameJitter taa_frame_jitter(const TaaSettings& taa) {
    return [taa](const FrameContext& ctx) {
        return taa_jitter(taa, ctx.frame, !(ctx.camera == ctx.previous_camera));
    };
}

TaaState resumed_taa_state(const FrameContext& ctx, const std::string& output,
                           const std::string& depth) {
    TaaState s;
    s.valid = true;
    s.history = ctx.resumed(output, 3, "TAA");
    s.age = ctx.resumed("taa_age", 1, "TAA");
    s.depth = ctx.resumed(depth, 1, "TAA");
    s.camera = ctx.previous_camera;
    return s;
}

void add_taa_counters(FrameContext& ctx, const TaaSettings& taa, const TaaStats& stats) {
    Counters& counters = ctx.result->counters;
    counters.add("taa_history_kept", stats.kept);
    counters.add("taa_history_rejected", stats.rejected);
    counters.add("taa_history_clamped", stats.clamped);
    counters.add("taa_periphery_kept", stats.periphery_kept);
    counters.add("taa_reprojection_skipped", stats.reprojection_skipped);
    counters.add("taa_history_nonfinite", stats.nonfinite_history);
    counters.add("taa_jitter_index", jitter_index(ctx, taa));
}

void taa_stage(FrameContext& ctx) {
    TaaStageState& state = ctx.state<TaaStageState>();
    const Image& color = ctx.input("color");
    const Image& depth = ctx.input("depth");
    const Image* bounds = ctx.has_input("bounds") ? &ctx.input("bounds") : nullptr;
    if (!state.history.valid && ctx.has_previous)
        state.history = resumed_taa_state(ctx, ctx.buffer_of("output"), ctx.buffer_of("depth"));
    // The previous frame's output, handed back (a resumed history is already here)
    ctx.carried("output", state.history.history, state.history.valid, "TAA");
    const glm::vec2 gaze = state.gaze ? state.gaze(ctx)
                                      : glm::vec2(static_cast<float>(color.width) * 0.5f,
                                                  static_cast<float>(color.height) * 0.5f);
    const TaaInputs in{color, depth, ctx.camera, gaze, bounds};
    Image out = std::move(state.spare_output), age = std::move(state.spare_age), margin;
    TaaStats stats;
    // The decision margins only when asked for (diff, probe, --dump all): a pass of its own.
    const bool margins = ctx.wants("margin");
    taa(state.taa.params, in, state.history, out, age, stats, margins ? &margin : nullptr);
    add_taa_counters(ctx, state.taa, stats);
    const int index = jitter_index(ctx, state.taa);
    ctx.note = std::string(taa_mode_name(state.taa.mode)) +
               (!state.history.valid                 ? ", first frame"
                : ctx.camera == state.history.camera ? ", stationary camera: no reprojection"
                                                     : ", reprojected") +
               (index < 0 ? ", no jitter" : ", Halton point " + std::to_string(index));
    // The output goes to the frame, which hands it back as the next frame's history; the state
    // keeps the age and a copy of the depth, and the previous history's storage becomes the
    // next frame's output. (Before ctx.output, which may move `depth`.) The age is copied only
    // when wanted (`--dump all`, a request naming it): a plain render reads only the output.
    const bool ages = ctx.wants("age");
    Image frame_age = ages ? age : Image();
    state.spare_output = std::move(state.history.history);
    state.spare_age = std::move(state.history.age);
    state.history = next_taa_state(Image(), std::move(age), depth, ctx.camera);
    ctx.output("output", BufferKind::color, {"r", "g", "b"}, std::move(out));
    if (ages) ctx.output("age", BufferKind::scalar, {"age"}, std::move(frame_age));
    if (margins)
        ctx.output("margin", BufferKind::scalar, {"depth", "reprojection"}, std::move(margin));
}

StageDef taa_stage_def(const TaaSettings& taa, const TaaPorts& ports,
                       std::function<glm::vec2(const FrameContext&)> gaze) {
    auto state = std::make_shared<TaaStageState>();
    state->taa = taa;
    state->gaze = std::move(gaze);
    std::vector<Port> inputs = {{"color", ports.color}, {"depth", ports.depth}};
    if (!ports.bounds.empty()) inputs.emplace_back("bounds", ports.bounds);
    return {"taa",
            inputs,
            {{"output", ports.output}, {"age", "taa_age"}, {"margin", "taa_margin"}},
            taa_stage,
            state};
}

void taa_source_stage(FrameContext& ctx) {
    TaaSourceState& state = ctx.state<TaaSourceState>();
    LogPolarFrames& frames = *state.shared.frames;
    const LogPolarMap map = frames.map(ctx);
    const int levels = frames.forward ? frames.forward->mip_levels : 0;
    const TaaBufferInputs in{map, frames.forward_table(map, levels), ctx.input("lp_valid"),
                             map.has_gaze_buffer() ? &ctx.input("gaze_valid") : nullptr};
    const bool boxes = state.taa.mode == TaaMode::clamp_buffer;
    std::optional<TaaBoxColors> colors;
    if (boxes)
        colors.emplace(TaaBoxColors{ctx.input("lp_color"),
                                    in.gaze_valid ? &ctx.input("gaze_color") : nullptr,
                                    ctx.input("resolved")});
    if (!taa_source_table_fits(state.table, in)) state.table = taa_source_table(in);
    // The pass writes every value of its outputs: an earlier frame's storage saves their zero
    // fill (kfr's depth is not output, so not recycled).
    const bool deferred = frames.params.deferred;
    TaaSourceOutputs storage;
    if (!deferred) storage.depth = ctx.recycled("depth", map.screen_width, map.screen_height, 1);
    if (boxes) storage.bounds = ctx.recycled("bounds", map.screen_width, map.screen_height, 6);
    TaaSourceOutputs out = taa_source_pass(
        in, ctx.input("lp_depth"), in.gaze_valid ? &ctx.input("gaze_depth") : nullptr,
        colors ? &*colors : nullptr, &state.table, std::move(storage));
    ctx.note = std::string("the texel pass 2 sampled (nearest traced tap): ") +
               (deferred ? "its 3x3 box in the buffer"
                : boxes  ? "its view depth and its 3x3 box in the buffer"
                         : "its view depth");
    // kfr reads the depth of its full-resolution G-buffer: its taa_source gives the boxes only.
    if (!deferred) ctx.output("depth", BufferKind::depth, {"z"}, std::move(out.depth));
    if (boxes) output_bounds(ctx, std::move(out.bounds));
}

StageDef taa_source_stage_def(const LogPolarStage& shared, const TaaSettings& taa,
                              const std::string& lp_color, const std::string& resolved) {
    const bool composite = shared.frames->params.map.gaze_angle > 0.0f;
    const bool boxes = taa.mode == TaaMode::clamp_buffer;
    std::vector<Port> inputs = {{"lp_depth", "lp_gbuffer_view_depth"}, {"lp_valid", "lp_valid"}};
    std::vector<Port> outputs;
    if (!shared.frames->params.deferred) outputs.emplace_back("depth", "taa_view_depth");
    if (composite) {
        inputs.emplace_back("gaze_depth", "gaze_gbuffer_view_depth");
        inputs.emplace_back("gaze_valid", "gaze_valid");
    }
    if (boxes) {
        inputs.emplace_back("lp_color", lp_color);
        inputs.emplace_back("resolved", resolved);
        if (composite) inputs.emplace_back("gaze_color", "gaze_color");
        outputs.emplace_back("bounds", "taa_bounds");
    }
    auto state = std::make_shared<TaaSourceState>();
    state->shared = shared;
    state->taa = taa;
    return {"taa_source", inputs, outputs, taa_source_stage, state};
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

}  // namespace fovref
