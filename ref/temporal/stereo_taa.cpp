#include "ref/temporal/stereo_taa.h"

#include <array>
#include <memory>
#include <optional>
#include <utility>

#include "ref/image/image.h"
#include "ref/log_polar/probe.h"
#include "ref/temporal/stages.h"
#include "ref/temporal/taa_foveated.h"
#include "ref/temporal/taa_probe.h"

namespace fovref {

namespace {

struct StereoTaaSourceState : StageState {
    StereoStage shared;
    TaaSettings taa;
    std::array<std::optional<ForwardTable>, 2> eye_forward;  ///< each eye's map
    std::array<TaaSourceTable, 2> eye_sources;               ///< kept while each eye's map repeats
};

struct StereoTaaState : StageState {
    StereoStage shared;
    TaaSettings taa;
    std::array<TaaState, 2> eye_history;  ///< each eye's own history
};

// Eye e's history when the render resumes: the previous frame's halves from its dumped buffers.
TaaState resumed_eye_history(const FrameContext& ctx, int x0, int eye_width,
                             const Camera& previous) {
    const TaaState whole = resumed_taa_state(ctx, "final", "taa_view_depth");
    return next_taa_state(image_columns(whole.history, x0, eye_width),
                          image_columns(whole.age, x0, eye_width),
                          image_columns(whole.depth, x0, eye_width), previous);
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

}  // namespace

void stereo_taa_source_stage(FrameContext& ctx) {
    StereoTaaSourceState& state = ctx.state<StereoTaaSourceState>();
    const std::array<LogPolarMap, 2> maps = state.shared.frames->maps(ctx);
    const int w = maps[0].width, eye_width = maps[0].screen_width;
    const bool boxes = state.taa.mode == TaaMode::clamp_buffer;
    Image depth(ctx.settings->width, ctx.settings->height, 1, 0.0f), bounds;
    if (boxes) bounds = Image(ctx.settings->width, ctx.settings->height, 6, 0.0f);
    for (int e = 0; e < 2; ++e) {
        const auto eye = static_cast<std::size_t>(e);
        std::optional<ForwardTable>& table = state.eye_forward[eye];
        if (!table || !(table->map == maps[eye])) table = forward_table(maps[eye]);
        const Image valid = image_columns(ctx.input("lp_valid"), e * w, w);
        const Image lp_depth = image_columns(ctx.input("lp_depth"), e * w, w);
        // The colours only for clamp-buffer's boxes.
        const Image lp_color = boxes ? image_columns(ctx.input("lp_color"), e * w, w) : Image();
        const Image screen =
            boxes ? image_columns(ctx.input("resolved"), e * eye_width, eye_width) : Image();
        const TaaBoxColors colors{lp_color, nullptr, screen};
        const TaaBufferInputs in{maps[eye], *table, valid, nullptr};
        TaaSourceTable& sources = state.eye_sources[eye];
        if (!taa_source_table_fits(sources, in)) sources = taa_source_table(in);
        const TaaSourceOutputs out =
            taa_source_pass(in, lp_depth, nullptr, boxes ? &colors : nullptr, &sources);
        set_image_columns(depth, e * eye_width, out.depth);
        if (boxes) set_image_columns(bounds, e * eye_width, out.bounds);
    }
    ctx.note = "per eye: the texel pass 2 sampled (nearest traced tap)";
    ctx.output("depth", BufferKind::depth, {"z"}, std::move(depth));
    if (boxes)
        ctx.output("bounds", BufferKind::scalar,
                   {"min_r", "min_g", "min_b", "max_r", "max_g", "max_b"}, std::move(bounds));
}

StageDef stereo_taa_source_stage_def(const StereoStage& shared, const TaaSettings& taa) {
    auto state = std::make_shared<StereoTaaSourceState>();
    state->shared = shared;
    state->taa = taa;
    std::vector<Port> outputs = {{"depth", "taa_view_depth"}};
    if (taa.mode == TaaMode::clamp_buffer) outputs.emplace_back("bounds", "taa_bounds");
    return {"taa_source",
            {{"lp_depth", "lp_gbuffer_view_depth"}, "lp_valid", "lp_color", "resolved"},
            outputs,
            stereo_taa_source_stage,
            state};
}

void stereo_taa_stage(FrameContext& ctx) {
    StereoTaaState& state = ctx.state<StereoTaaState>();
    const StereoFrames& frames = *state.shared.frames;
    const std::array<LogPolarMap, 2> maps = frames.maps(ctx);
    const int eye_width = maps[0].screen_width;
    const std::array<Camera, 2> cameras = frames.cameras(ctx);
    const std::array<Camera, 2> previous = frames.cameras(ctx, true);
    const bool boxes = state.taa.mode == TaaMode::clamp_buffer;
    Image out(ctx.settings->width, ctx.settings->height, 3, 0.0f);
    // The age only when wanted (the eyes' histories keep their own): as the taa stage
    const bool ages = ctx.wants("age");
    Image age = ages ? Image(ctx.settings->width, ctx.settings->height, 1, 0.0f) : Image();
    TaaStats stats;
    for (int e = 0; e < 2; ++e) {
        const auto eye = static_cast<std::size_t>(e);
        const auto x0 = e * eye_width;
        const Image color = image_columns(ctx.input("color"), x0, eye_width);
        const Image depth = image_columns(ctx.input("depth"), x0, eye_width);
        const Image bounds = boxes ? image_columns(ctx.input("bounds"), x0, eye_width) : Image();
        TaaState& history = state.eye_history[eye];
        if (!history.valid && ctx.has_previous)
            history = resumed_eye_history(ctx, x0, eye_width, previous[eye]);
        const TaaInputs in{color, depth, cameras[eye], maps[eye].gaze, boxes ? &bounds : nullptr};
        Image eye_out, eye_age;
        debugger_position.eye = e;  // the eye's taa_pixel calls, for a debugger's conditions
        taa(state.taa.params, in, history, eye_out, eye_age, stats);
        debugger_position.eye = -1;
        set_image_columns(out, x0, eye_out);
        if (ages) set_image_columns(age, x0, eye_age);
        history = next_taa_state(std::move(eye_out), std::move(eye_age), depth, cameras[eye]);
    }
    add_taa_counters(ctx, state.taa, stats);
    ctx.note = std::string(taa_mode_name(state.taa.mode)) + ", each eye on its own";
    ctx.output("output", BufferKind::color, {"r", "g", "b"}, std::move(out));
    if (ages) ctx.output("age", BufferKind::scalar, {"age"}, std::move(age));
}

StageDef stereo_taa_stage_def(const StereoStage& shared, const TaaSettings& taa) {
    auto state = std::make_shared<StereoTaaState>();
    state->shared = shared;
    state->taa = taa;
    std::vector<Port> inputs = {{"color", "resolved"}, {"depth", "taa_view_depth"}};
    if (taa.mode == TaaMode::clamp_buffer) inputs.emplace_back("bounds", "taa_bounds");
    return {"taa", inputs, {{"output", "final"}, {"age", "taa_age"}}, stereo_taa_stage, state};
}

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
    const glm::vec2 gaze =
        stereo_maps(params, *c.scene, c.camera, c.settings->width, c.settings->height,
                    c.frame->frame)[static_cast<std::size_t>(eye)]
            .gaze;
    explain_taa(local, taa_probe_inputs(current, taa, gaze), report);
    report.sections.back().title += "; eye " + std::to_string(eye) + ", pixel (" +
                                    std::to_string(local.x) + ", " + std::to_string(c.y) +
                                    ") of its half, with its own camera and history";
}

}  // namespace fovref
