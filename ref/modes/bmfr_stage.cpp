#include "ref/modes/bmfr_stage.h"

#include <utility>

#include "ref/core/error.h"
#include "ref/modes/mode_common.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};

// The history of a frame rendered after frame 0 with nothing rendered before it: the previous
// frame's dumped buffers.
BmfrHistory resumed_bmfr_history(const FrameContext& ctx) {
    const BmfrModeState& s = ctx.mode_state<BmfrModeState>();
    BmfrHistory h;
    h.valid = true;
    h.view_projection =
        view_projection(ctx.previous_camera, ctx.settings->width, ctx.settings->height);
    std::optional<glm::ivec2> size;  // the buffer's (the screen's unless Visual-Polar)
    if (!s.bmfr_valid.empty()) {
        h.map = s.bmfr_map(ctx, ctx.frame - 1);
        size = glm::ivec2(h.map->width, h.map->height);
        h.valid_texels = resumed_buffer(ctx, s.bmfr_valid, 1, "BMFR", size);
    }
    const auto get = [&](const std::string& name, int channels) {
        return resumed_buffer(ctx, name, channels, "BMFR", size);
    };
    h.world_position = get(s.bmfr_gbuffer + "world_position", 3);
    h.normal = get(s.bmfr_gbuffer + "shading_normal", 3);
    h.accumulated_noisy = get("bmfr_accumulated_noisy", 3);
    h.spp = get("bmfr_spp", 1);
    h.accumulated_filtered = get("bmfr_accumulated_filtered", 3);
    h.taa = get("bmfr_taa", 3);
    return h;
}

// The mode's BMFR state at this frame: the first BMFR stage of a frame moves what the previous
// frame handed on into the history.
BmfrModeState& bmfr_state(FrameContext& ctx) {
    BmfrModeState& s = ctx.mode_state<BmfrModeState>();
    if (s.bmfr_frame != ctx.frame) {
        if (s.bmfr_frame == ctx.frame - 1 && s.bmfr_frame >= 0)
            s.bmfr_history = std::move(s.bmfr_next);
        else
            s.bmfr_history = ctx.has_previous ? resumed_bmfr_history(ctx) : BmfrHistory{};
        s.bmfr_next = BmfrHistory{};
        s.bmfr_frame = ctx.frame;
    }
    return s;
}

// The directly seen emission when it is kept out of the fit, else an empty image.
const Image& emission_input(const FrameContext& ctx, const BmfrModeState& s) {
    static const Image none;
    return s.bmfr.params.separate_emission ? ctx.input(s.bmfr_emission) : none;
}

// Where this frame's BMFR runs: the screen, or the Visual-Polar buffer with its map and masks.
BmfrSpace frame_space(const FrameContext& ctx, const BmfrModeState& s) {
    BmfrSpace space;
    if (s.bmfr_valid.empty()) return space;
    space.map = s.bmfr_map(ctx, ctx.frame);
    space.valid = &ctx.input(s.bmfr_valid);
    if (!s.bmfr_history.valid_texels.empty()) space.previous_valid = &s.bmfr_history.valid_texels;
    return space;
}

const Image& gbuffer(const FrameContext& ctx, const BmfrModeState& s, const char* channel) {
    return ctx.input(s.bmfr_gbuffer + channel);
}

void add_stats(FrameContext& ctx, const BmfrStats& stats) {
    add_bmfr_counters(ctx.result->counters, stats);
}

// The stages' buffers, one function per stage so that the stages and add_bmfr_buffers name them
// alike.
void add_accumulation(FrameResult& r, BmfrAccumulation a) {
    r.add("bmfr_accumulated_noisy", BufferKind::color, rgb, std::move(a.accumulated));
    r.add("bmfr_spp", BufferKind::scalar, {"spp"}, std::move(a.spp));
    r.add("bmfr_accept", BufferKind::scalar, {"mask"}, std::move(a.accept));
    r.add("bmfr_previous_pixel", BufferKind::scalar, {"x", "y"}, std::move(a.previous_pixel));
}

void add_fit(FrameResult& r, Image weights, Image feature_range) {
    std::vector<std::string> weight_names, range_names;
    for (const char* ch : {"r", "g", "b"})
        for (int i = 0; i < bmfr_feature_count; ++i)
            weight_names.push_back(std::string(ch) + "_w" + std::to_string(i));
    for (const char* bound : {"min", "max"})
        for (int k = 0; k < bmfr_scaled_count; ++k)
            range_names.push_back(std::string(bound) + "_t" +
                                  std::to_string(bmfr_scaled_first + k));
    r.add("bmfr_weights", BufferKind::scalar, weight_names, std::move(weights));
    r.add("bmfr_feature_range", BufferKind::scalar, range_names, std::move(feature_range));
}

}  // namespace

void add_bmfr_counters(Counters& counters, const BmfrStats& s) {
    counters.add("bmfr_nonfinite_inputs", s.nonfinite_inputs);
    counters.add("bmfr_history_accepted", s.history_accepted);
    counters.add("bmfr_history_rejected", s.history_rejected);
    counters.add("bmfr_history_off_screen", s.history_off_screen);
    counters.add("bmfr_blocks", s.blocks);
    counters.add("bmfr_pivots_zeroed", s.pivots_zeroed);
    counters.add("bmfr_reflections_skipped", s.reflections_skipped);
    counters.add("bmfr_fit_nonfinite", s.fit_nonfinite);
    counters.add("bmfr_taa_history_used", s.taa_history_used);
}

void bmfr_demodulate_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    BmfrStats stats;
    Image out = bmfr_demodulate(s.bmfr.params, ctx.input(s.bmfr_radiance),
                                gbuffer(ctx, s, "albedo"), emission_input(ctx, s), stats);
    add_stats(ctx, stats);
    ctx.result->add("bmfr_illumination", BufferKind::color, rgb, std::move(out));
}

void bmfr_accumulate_noisy_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    const Image& world = gbuffer(ctx, s, "world_position");
    const Image& normal = gbuffer(ctx, s, "shading_normal");
    const BmfrSpace space = frame_space(ctx, s);
    BmfrStats stats;
    BmfrAccumulation a = bmfr_accumulate_noisy(s.bmfr.params, ctx.input("bmfr_illumination"), world,
                                               normal, s.bmfr_history, stats, space);
    add_stats(ctx, stats);
    ctx.note = !s.bmfr_history.valid
                   ? "first frame: no history"
                   : std::to_string(stats.history_accepted) + " pixels with history";
    s.bmfr_next.valid = true;
    s.bmfr_next.view_projection =
        view_projection(ctx.camera, ctx.settings->width, ctx.settings->height);
    s.bmfr_next.map = space.map;
    if (space.valid) s.bmfr_next.valid_texels = *space.valid;
    s.bmfr_next.world_position = world;
    s.bmfr_next.normal = normal;
    s.bmfr_next.accumulated_noisy = a.accumulated;
    s.bmfr_next.spp = a.spp;
    add_accumulation(*ctx.result, std::move(a));
}

void bmfr_fit_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    BmfrStats stats;
    const BmfrSpace space = frame_space(ctx, s);
    BmfrFit fit = bmfr_fit(s.bmfr.params, ctx.input("bmfr_accumulated_noisy"),
                           gbuffer(ctx, s, "world_position"), gbuffer(ctx, s, "shading_normal"),
                           ctx.frame, stats, space);
    add_stats(ctx, stats);
    ctx.note = std::to_string(fit.grid.cells_x) + "x" + std::to_string(fit.grid.cells_y) +
               " blocks, offset (" + std::to_string(fit.grid.offset.x) + ", " +
               std::to_string(fit.grid.offset.y) + "), " +
               (s.bmfr.params.storage == BmfrStorage::half ? "binary16" : "binary32") + " storage" +
               (space.map ? ", Visual-Polar: " + std::to_string(stats.blocks) +
                                " blocks below the staircase, rows wrap"
                          : "");
    add_fit(*ctx.result, std::move(fit.weights), std::move(fit.feature_range));
}

void bmfr_weighted_sum_stage(FrameContext& ctx) {
    const BmfrModeState& s = bmfr_state(ctx);
    const Image& world = gbuffer(ctx, s, "world_position");
    const BmfrSpace space = frame_space(ctx, s);
    BmfrFit fit;
    fit.grid = bmfr_grid(world.width, world.height, ctx.frame, space.map ? &*space.map : nullptr);
    fit.weights = ctx.input("bmfr_weights");
    fit.feature_range = ctx.input("bmfr_feature_range");
    BmfrStats stats;
    Image out =
        bmfr_weighted_sum(fit, world, gbuffer(ctx, s, "shading_normal"), stats, space.valid);
    add_stats(ctx, stats);
    ctx.result->add("bmfr_fitted", BufferKind::color, rgb, std::move(out));
}

void bmfr_accumulate_filtered_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    Image out = bmfr_accumulate_filtered(
        s.bmfr.params, ctx.input("bmfr_fitted"), ctx.input("bmfr_spp"), ctx.input("bmfr_accept"),
        ctx.input("bmfr_previous_pixel"), s.bmfr_history.accumulated_filtered, frame_space(ctx, s));
    s.bmfr_next.accumulated_filtered = out;
    ctx.result->add("bmfr_accumulated_filtered", BufferKind::color, rgb, std::move(out));
}

void bmfr_remodulate_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    Image out = bmfr_remodulate(s.bmfr.params, ctx.input("bmfr_accumulated_filtered"),
                                gbuffer(ctx, s, "albedo"), emission_input(ctx, s));
    ctx.note = std::string("display space: clamp(x^(1/2.2), 0, 1)") +
               (s.bmfr.params.separate_emission ? ", emission added back" : "");
    ctx.result->add("bmfr_display", BufferKind::scalar, rgb, std::move(out));
}

void bmfr_taa_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    BmfrStats stats;
    Image out = bmfr_taa(s.bmfr.params, ctx.input("bmfr_display"), ctx.input("bmfr_previous_pixel"),
                         s.bmfr_history.taa, stats, frame_space(ctx, s));
    add_stats(ctx, stats);
    s.bmfr_next.taa = out;
    ctx.result->add("bmfr_taa", BufferKind::scalar, rgb, std::move(out));
}

void bmfr_output_stage(FrameContext& ctx) {
    BmfrModeState& s = bmfr_state(ctx);
    ctx.note = "linear: bmfr_taa^2.2";
    ctx.result->add(s.bmfr_output, BufferKind::color, rgb, bmfr_linearize(ctx.input("bmfr_taa")));
}

void add_bmfr_buffers(FrameResult& r, BmfrFrame f, const std::string& output) {
    r.add("bmfr_illumination", BufferKind::color, rgb, std::move(f.illumination));
    add_accumulation(r, std::move(f.accumulation));
    add_fit(r, std::move(f.fit.weights), std::move(f.fit.feature_range));
    r.add("bmfr_fitted", BufferKind::color, rgb, std::move(f.fitted));
    r.add("bmfr_accumulated_filtered", BufferKind::color, rgb, std::move(f.filtered));
    r.add("bmfr_display", BufferKind::scalar, rgb, std::move(f.display));
    r.add("bmfr_taa", BufferKind::scalar, rgb, std::move(f.taa));
    r.add(output, BufferKind::color, rgb, std::move(f.output));
}

void add_bmfr_stages(Pipeline& p, BmfrModeState& state, const std::string& radiance,
                     const std::string& emission, const std::string& output) {
    state.bmfr_radiance = radiance;
    state.bmfr_emission = emission;
    state.bmfr_output = output;
    const std::string world = state.bmfr_gbuffer + "world_position",
                      normal = state.bmfr_gbuffer + "shading_normal",
                      albedo = state.bmfr_gbuffer + "albedo";
    std::vector<std::string> demodulate_inputs = {radiance, albedo};
    std::vector<std::string> remodulate_inputs = {"bmfr_accumulated_filtered", albedo};
    if (state.bmfr.params.separate_emission) {
        demodulate_inputs.push_back(emission);
        remodulate_inputs.push_back(emission);
    }
    // Visual-Polar: the stages that address the buffer read its validity mask too
    const auto with_valid = [&](std::vector<std::string> inputs) {
        if (!state.bmfr_valid.empty()) inputs.push_back(state.bmfr_valid);
        return inputs;
    };
    p.stages.push_back(
        {"bmfr_demodulate", demodulate_inputs, {"bmfr_illumination"}, bmfr_demodulate_stage});
    p.stages.push_back(
        {"bmfr_accumulate_noisy",
         with_valid({"bmfr_illumination", world, normal}),
         {"bmfr_accumulated_noisy", "bmfr_spp", "bmfr_accept", "bmfr_previous_pixel"},
         bmfr_accumulate_noisy_stage});
    p.stages.push_back({"bmfr_fit",
                        with_valid({"bmfr_accumulated_noisy", world, normal}),
                        {"bmfr_weights", "bmfr_feature_range"},
                        bmfr_fit_stage});
    p.stages.push_back({"bmfr_weighted_sum",
                        with_valid({"bmfr_weights", "bmfr_feature_range", world, normal}),
                        {"bmfr_fitted"},
                        bmfr_weighted_sum_stage});
    p.stages.push_back(
        {"bmfr_accumulate_filtered",
         with_valid({"bmfr_fitted", "bmfr_spp", "bmfr_accept", "bmfr_previous_pixel"}),
         {"bmfr_accumulated_filtered"},
         bmfr_accumulate_filtered_stage});
    p.stages.push_back(
        {"bmfr_remodulate", remodulate_inputs, {"bmfr_display"}, bmfr_remodulate_stage});
    p.stages.push_back({"bmfr_taa",
                        with_valid({"bmfr_display", "bmfr_previous_pixel"}),
                        {"bmfr_taa"},
                        bmfr_taa_stage});
    p.stages.push_back({"bmfr_output", {"bmfr_taa"}, {output}, bmfr_output_stage});
}

}  // namespace fovref
