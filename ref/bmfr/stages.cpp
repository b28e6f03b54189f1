#include "ref/bmfr/stages.h"

#include <memory>
#include <utility>

#include "ref/core/error.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};

/// The state the eight BMFR stages share.
struct BmfrState : StageState {
    BmfrSettings settings;
    std::function<VisualPolarMap(const FrameContext&, int frame)> map;     ///< empty: the screen
    std::function<ViewProjection(const FrameContext&, int frame)> camera;  ///< empty: ctx's
    std::function<glm::vec2(const FrameContext&)> pixel_offset;            ///< empty: centres
    /// What the previous frame handed on. Its accumulated_noisy, spp, accumulated_filtered and
    /// taa are not kept in `next`: they are the previous frame's output buffers themselves,
    /// which the pipeline hands back to the stages that wrote them (FrameContext::carried), so that
    /// no frame copies them.
    BmfrHistory history;
    BmfrHistory next;  ///< what this frame hands on (filled by the stages)
    /// The storage of the carried buffers of the frame before last, once this frame's passes
    /// have read them as history: written over by the next frame's passes (which write every
    /// value), so that no zero fill precedes them.
    BmfrHistory spare;
    int frame = -1;  ///< the frame `next` belongs to
};

/// Where a stage's buffer goes: its output slot (the BMFR buffers' slots are their names).
using AddBuffer =
    std::function<void(const std::string& name, BufferKind, std::vector<std::string>, Image)>;

AddBuffer to_outputs(const FrameContext& ctx) {
    return [&ctx](const std::string& name, BufferKind kind, std::vector<std::string> channels,
                  Image image) { ctx.output(name, kind, std::move(channels), std::move(image)); };
}

// The view-projection of frame `frame` (the current or the previous one): the wiring's matrices,
// else the frame's camera.
ViewProjection frame_view_projection(const FrameContext& ctx, const BmfrState& s, int frame) {
    if (s.camera) return s.camera(ctx, frame);
    return view_projection(frame == ctx.frame ? ctx.camera : ctx.previous_camera,
                           ctx.settings->width, ctx.settings->height);
}

// The parameters of this frame's phase I: the wiring's pixel offset, if any.
BmfrParams frame_params(const FrameContext& ctx, const BmfrState& s) {
    BmfrParams params = s.settings.params;
    if (s.pixel_offset) params.pixel_offset = s.pixel_offset(ctx);
    return params;
}

// The history of a frame rendered after frame 0 with nothing rendered before it: the previous
// frame's dumped buffers (read by phase I, which holds the G-buffer's and the mask's ports).
BmfrHistory resumed_history(const FrameContext& ctx, const BmfrState& s) {
    BmfrHistory h;
    h.valid = true;
    h.view_projection = frame_view_projection(ctx, s, ctx.frame - 1);
    std::optional<glm::ivec2> size;  // the buffer's (the screen's unless Visual-Polar)
    if (s.map) {
        h.map = s.map(ctx, ctx.frame - 1);
        size = glm::ivec2(h.map->width, h.map->height);
        h.valid_texels = ctx.resumed(ctx.buffer_of("valid"), 1, "BMFR", size);
    }
    const auto get = [&](const std::string& name, int channels) {
        return ctx.resumed(name, channels, "BMFR", size);
    };
    h.world_position = get(ctx.buffer_of("world_position"), 3);
    h.normal = get(ctx.buffer_of("shading_normal"), 3);
    h.accumulated_noisy = get("bmfr_accumulated_noisy", 3);
    h.spp = get("bmfr_spp", 1);
    h.accumulated_filtered = get("bmfr_accumulated_filtered", 3);
    h.taa = get("bmfr_taa", 3);
    return h;
}

// Phase I starts a frame: what the previous frame handed on becomes the history.
void start_frame(const FrameContext& ctx, BmfrState& s) {
    if (s.frame == ctx.frame) return;
    if (s.frame == ctx.frame - 1 && s.frame >= 0)
        s.history = std::move(s.next);
    else
        s.history = ctx.has_previous ? resumed_history(ctx, s) : BmfrHistory{};
    s.next = BmfrHistory{};
    s.frame = ctx.frame;
}

// The directly seen emission when it is kept out of the fit, else an empty image.
const Image& emission_input(const FrameContext& ctx, const BmfrState& s) {
    static const Image none;
    return s.settings.params.separate_emission ? ctx.input("emission") : none;
}

// Where this frame's BMFR runs: the screen, or the Visual-Polar buffer with its map and masks.
BmfrSpace frame_space(const FrameContext& ctx, const BmfrState& s) {
    BmfrSpace space;
    if (!s.map) return space;
    space.map = s.map(ctx, ctx.frame);
    space.valid = &ctx.input("valid");
    if (!s.history.valid_texels.empty()) space.previous_valid = &s.history.valid_texels;
    space.previous_map = s.history.map;
    return space;
}

void add_stats(FrameContext& ctx, const BmfrStats& stats) {
    add_bmfr_counters(ctx.result->counters, stats);
}

// The buffers of the stages with several outputs (names, kinds, channel names).
void add_accumulation(const AddBuffer& add, BmfrAccumulation a) {
    add("bmfr_accumulated_noisy", BufferKind::color, rgb, std::move(a.accumulated));
    add("bmfr_spp", BufferKind::scalar, {"spp"}, std::move(a.spp));
    add("bmfr_accept", BufferKind::scalar, {"mask"}, std::move(a.accept));
    add("bmfr_previous_pixel", BufferKind::scalar, {"x", "y"}, std::move(a.previous_pixel));
    if (!a.accept_margin.empty())
        add("bmfr_accept_margin", BufferKind::scalar, {"position", "normal", "taps"},
            std::move(a.accept_margin));
}

void add_fit(const AddBuffer& add, Image weights, Image feature_range) {
    std::vector<std::string> weight_names, range_names;
    for (const char* ch : {"r", "g", "b"})
        for (int i = 0; i < bmfr_feature_count; ++i)
            weight_names.push_back(std::string(ch) + "_w" + std::to_string(i));
    for (const char* bound : {"min", "max"})
        for (int k = 0; k < bmfr_scaled_count; ++k)
            range_names.push_back(std::string(bound) + "_t" +
                                  std::to_string(bmfr_scaled_first + k));
    add("bmfr_weights", BufferKind::scalar, weight_names, std::move(weights));
    add("bmfr_feature_range", BufferKind::scalar, range_names, std::move(feature_range));
}

// What phase I hands on to the next frame.
void hand_on_accumulation(const FrameContext& ctx, BmfrState& s, const BmfrSpace& space,
                          const Image& world, const Image& normal) {
    s.next.valid = true;
    s.next.view_projection = frame_view_projection(ctx, s, ctx.frame);
    s.next.map = space.map;
    if (space.valid) s.next.valid_texels = *space.valid;
    s.next.world_position = world;
    s.next.normal = normal;
    // (its accumulation and counts go to the frame and come back: FrameContext::carried)
}

// The stage's ports: `names` with slot = buffer, plus the G-buffer channels the stage reads (slot
// = channel, buffer = prefix + channel) and, in Visual-Polar space, the mask.
std::vector<Port> ports(std::vector<Port> names, const BmfrWiring& w,
                        std::vector<const char*> gbuffer_channels, bool mask) {
    for (const char* channel : gbuffer_channels) names.emplace_back(channel, w.gbuffer + channel);
    if (mask && !w.valid.empty()) names.emplace_back("valid", w.valid);
    return names;
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
    const BmfrState& s = ctx.state<BmfrState>();
    BmfrStats stats;
    const Image& radiance = ctx.input("radiance");
    // The pass writes every value: an earlier frame's storage saves the zero fill
    Image out = bmfr_demodulate(
        s.settings.params, radiance, ctx.input("albedo"), emission_input(ctx, s), stats,
        ctx.recycled("bmfr_illumination", radiance.width, radiance.height, 3));
    add_stats(ctx, stats);
    ctx.output("bmfr_illumination", BufferKind::color, rgb, std::move(out));
}

void bmfr_accumulate_noisy_stage(FrameContext& ctx) {
    BmfrState& s = ctx.state<BmfrState>();
    start_frame(ctx, s);
    ctx.carried("bmfr_accumulated_noisy", s.history.accumulated_noisy, s.history.valid, "BMFR");
    ctx.carried("bmfr_spp", s.history.spp, s.history.valid, "BMFR");
    const Image& world = ctx.input("world_position");
    const Image& normal = ctx.input("shading_normal");
    const BmfrSpace space = frame_space(ctx, s);
    BmfrStats stats;
    // The pass writes every value of its outputs: the storage of earlier frames' (the carried
    // ones from the frame before last, the others recycled)
    BmfrAccumulation storage;
    storage.accumulated = std::move(s.spare.accumulated_noisy);
    storage.spp = std::move(s.spare.spp);
    storage.accept = ctx.recycled("bmfr_accept", world.width, world.height, 1);
    storage.previous_pixel = ctx.recycled("bmfr_previous_pixel", world.width, world.height, 2);
    // The accept margins only when asked for (diff, probe, --dump all).
    BmfrAccumulation a = bmfr_accumulate_noisy(frame_params(ctx, s), ctx.input("bmfr_illumination"),
                                               world, normal, s.history, stats, space,
                                               ctx.wants("bmfr_accept_margin"), std::move(storage));
    s.spare.accumulated_noisy = std::move(s.history.accumulated_noisy);
    s.spare.spp = std::move(s.history.spp);
    add_stats(ctx, stats);
    ctx.note = !s.history.valid ? "first frame: no history"
                                : std::to_string(stats.history_accepted) + " pixels with history";
    hand_on_accumulation(ctx, s, space, world, normal);
    add_accumulation(to_outputs(ctx), std::move(a));
}

void bmfr_fit_stage(FrameContext& ctx) {
    const BmfrState& s = ctx.state<BmfrState>();
    BmfrStats stats;
    const BmfrSpace space = frame_space(ctx, s);
    BmfrFit fit =
        bmfr_fit(s.settings.params, ctx.input("bmfr_accumulated_noisy"),
                 ctx.input("world_position"), ctx.input("shading_normal"), ctx.frame, stats, space);
    add_stats(ctx, stats);
    ctx.note = std::to_string(fit.grid.cells_x) + "x" + std::to_string(fit.grid.cells_y) +
               " blocks, offset (" + std::to_string(fit.grid.offset.x) + ", " +
               std::to_string(fit.grid.offset.y) + "), " +
               (s.settings.params.storage == BmfrStorage::half ? "binary16" : "binary32") +
               " storage" +
               (space.map ? ", Visual-Polar: " + std::to_string(stats.blocks) +
                                " blocks below the staircase, rows wrap"
                          : "");
    add_fit(to_outputs(ctx), std::move(fit.weights), std::move(fit.feature_range));
}

void bmfr_weighted_sum_stage(FrameContext& ctx) {
    const BmfrState& s = ctx.state<BmfrState>();
    const Image& world = ctx.input("world_position");
    const BmfrSpace space = frame_space(ctx, s);
    BmfrFit fit;
    fit.grid = bmfr_grid(world.width, world.height, ctx.frame, space.map ? &*space.map : nullptr,
                         s.settings.params.block_size);
    fit.weights = ctx.input("bmfr_weights");
    fit.feature_range = ctx.input("bmfr_feature_range");
    BmfrStats stats;
    Image out = bmfr_weighted_sum(fit, world, ctx.input("shading_normal"), stats, space.valid);
    add_stats(ctx, stats);
    ctx.output("bmfr_fitted", BufferKind::color, rgb, std::move(out));
}

void bmfr_accumulate_filtered_stage(FrameContext& ctx) {
    BmfrState& s = ctx.state<BmfrState>();
    ctx.carried("bmfr_accumulated_filtered", s.history.accumulated_filtered, s.history.valid,
                "BMFR");
    Image out = bmfr_accumulate_filtered(
        s.settings.params, ctx.input("bmfr_fitted"), ctx.input("bmfr_spp"),
        ctx.input("bmfr_accept"), ctx.input("bmfr_previous_pixel"), s.history.accumulated_filtered,
        frame_space(ctx, s), std::move(s.spare.accumulated_filtered));
    s.spare.accumulated_filtered = std::move(s.history.accumulated_filtered);
    ctx.output("bmfr_accumulated_filtered", BufferKind::color, rgb, std::move(out));
}

void bmfr_remodulate_stage(FrameContext& ctx) {
    const BmfrState& s = ctx.state<BmfrState>();
    const Image& filtered = ctx.input("bmfr_accumulated_filtered");
    Image out =
        bmfr_remodulate(s.settings.params, filtered, ctx.input("albedo"), emission_input(ctx, s),
                        ctx.recycled("bmfr_display", filtered.width, filtered.height, 3));
    ctx.note = std::string("display space: clamp(x^") +
               (s.settings.params.display_exponent == 0.454545f ? "0.454545" : "(1/2.2)") +
               ", 0, 1)" + (s.settings.params.separate_emission ? ", emission added back" : "");
    ctx.output("bmfr_display", BufferKind::scalar, rgb, std::move(out));
}

void bmfr_taa_stage(FrameContext& ctx) {
    BmfrState& s = ctx.state<BmfrState>();
    ctx.carried("bmfr_taa", s.history.taa, s.history.valid, "BMFR");
    BmfrStats stats;
    Image out =
        bmfr_taa(s.settings.params, ctx.input("bmfr_display"), ctx.input("bmfr_previous_pixel"),
                 s.history.taa, stats, frame_space(ctx, s), std::move(s.spare.taa));
    s.spare.taa = std::move(s.history.taa);
    add_stats(ctx, stats);
    ctx.output("bmfr_taa", BufferKind::scalar, rgb, std::move(out));
}

void bmfr_output_stage(FrameContext& ctx) {
    ctx.note = "linear: bmfr_taa^2.2";
    const Image& taa = ctx.input("bmfr_taa");
    ctx.output("output", BufferKind::color, rgb,
               bmfr_linearize(taa, ctx.recycled("output", taa.width, taa.height, taa.channels)));
}

void add_bmfr_stages(Pipeline& p, const BmfrWiring& w) {
    auto state = std::make_shared<BmfrState>();
    state->settings = w.settings;
    state->map = w.map;
    state->camera = w.view_projection;
    state->pixel_offset = w.pixel_offset;
    std::vector<Port> demodulate = {{"radiance", w.radiance}};
    std::vector<Port> remodulate = {"bmfr_accumulated_filtered"};
    if (w.settings.params.separate_emission) {
        demodulate.emplace_back("emission", w.emission);
        remodulate.emplace_back("emission", w.emission);
    }
    const std::vector<const char*> world_normal = {"world_position", "shading_normal"};
    p.add({"bmfr_demodulate",
           ports(demodulate, w, {"albedo"}, false),
           {"bmfr_illumination"},
           bmfr_demodulate_stage,
           state});
    p.add({"bmfr_accumulate_noisy",
           ports({"bmfr_illumination"}, w, world_normal, true),
           {"bmfr_accumulated_noisy", "bmfr_spp", "bmfr_accept", "bmfr_previous_pixel",
            "bmfr_accept_margin"},
           bmfr_accumulate_noisy_stage,
           state});
    p.add({"bmfr_fit",
           ports({"bmfr_accumulated_noisy"}, w, world_normal, true),
           {"bmfr_weights", "bmfr_feature_range"},
           bmfr_fit_stage,
           state});
    p.add({"bmfr_weighted_sum",
           ports({"bmfr_weights", "bmfr_feature_range"}, w, world_normal, true),
           {"bmfr_fitted"},
           bmfr_weighted_sum_stage,
           state});
    p.add({"bmfr_accumulate_filtered",
           ports({"bmfr_fitted", "bmfr_spp", "bmfr_accept", "bmfr_previous_pixel"}, w, {}, true),
           {"bmfr_accumulated_filtered"},
           bmfr_accumulate_filtered_stage,
           state});
    p.add({"bmfr_remodulate",
           ports(remodulate, w, {"albedo"}, false),
           {"bmfr_display"},
           bmfr_remodulate_stage,
           state});
    p.add({"bmfr_taa",
           ports({"bmfr_display", "bmfr_previous_pixel"}, w, {}, true),
           {"bmfr_taa"},
           bmfr_taa_stage,
           state});
    p.add({"bmfr_output", {"bmfr_taa"}, {{"output", w.output}}, bmfr_output_stage, state});
}

std::vector<PixelFunction> bmfr_pixel_functions(
    const std::string& family,
    std::function<glm::ivec2(const RenderSettings&, int frame, glm::ivec2 point)> block_of) {
    const PixelArgs args = family.empty() ? PixelArgs::screen : PixelArgs::texel;
    const std::string at;  // the coordinates are named where the breakpoint is listed
    return {{"bmfr_accumulate_noisy", "fovref::bmfr_accumulate_noisy_pixel", at, args, family, {}},
            {"bmfr_fit", "fovref::bmfr_gather_block",
             "cell_x, cell_y: the block (the frame's offset grid); then bmfr_solve_block",
             PixelArgs::block, family, std::move(block_of)},
            {"bmfr_weighted_sum", "fovref::bmfr_weighted_sum_pixel", at, args, family, {}},
            {"bmfr_accumulate_filtered",
             "fovref::bmfr_accumulate_filtered_pixel",
             at,
             args,
             family,
             {}},
            {"bmfr_taa", "fovref::bmfr_taa_pixel", at, args, family, {}}};
}

glm::ivec2 bmfr_screen_block(const RenderSettings& settings, int frame, glm::ivec2 point) {
    return bmfr_grid(settings.width, settings.height, frame, nullptr,
                     parse_bmfr_params(settings.params).params.block_size)
        .cell_of(point.x, point.y);
}

}  // namespace fovref
