#include "ref/visual_polar/stages.h"

#include <cstdio>
#include <utility>

#include "ref/core/simd.h"
#include "ref/log_polar/stages.h"
#include "ref/trace/stages.h"
#include "ref/visual_polar/resolve_decisions.h"
#include "ref/visual_polar/sparse_sampling.h"
#include "ref/visual_polar/trace.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};

struct SparseState : StageState {
    std::shared_ptr<SparseFrames> frames;
    std::shared_ptr<BvhCache> bvh;
};

// acuity with progressive=on: the sums so far.
struct AccumulateState : SparseState {
    Image sum, count;
    int frame = -1;  ///< the frame the sums belong to
};

std::shared_ptr<SparseState> sparse_state(std::shared_ptr<SparseFrames> frames,
                                          std::shared_ptr<BvhCache> bvh = nullptr) {
    auto state = std::make_shared<SparseState>();
    state->frames = std::move(frames);
    state->bvh = std::move(bvh);
    return state;
}

// A buffer's G-buffer and mask (prefix "vp_", "acuity_"), plus `extra` named prefix + extra.
std::vector<Port> traced_outputs(const std::string& prefix, const std::string& extra) {
    std::vector<Port> ports = gbuffer_ports(prefix + "gbuffer_");
    ports.emplace_back("valid", prefix + "valid");
    ports.emplace_back(extra, prefix + extra);
    return ports;
}

void add_vp_trace_counters(FrameContext& ctx, const VpTraceStats& stats) {
    Counters& counters = ctx.result->counters;
    counters.add("texels_traced", stats.texels_traced);
    counters.add("texels_clipped", stats.texels_clipped);
    counters.add("texels_off_screen", stats.texels_off_screen);
    add_trace_counters(counters, "primary", stats.rays.primary);
}

// The acuity samples of a frame (their screen points).
std::vector<glm::vec2> frame_acuity_points(const FrameContext& ctx, const SparseParams& params) {
    const int width = ctx.settings->width, height = ctx.settings->height;
    return acuity_samples(static_cast<std::uint32_t>(ctx.frame),
                          acuity_samples_per_frame(params, width, height),
                          sparse_gaze(params, width, height, ctx.frame),
                          sparse_eccentricity(params, *ctx.scene, ctx.camera, width, height));
}

// The progressive sums the frame starts from: the previous frame's, or (resumed) its dump's.
void starting_sums(const FrameContext& ctx, AccumulateState& s, Image& sum, Image& count) {
    if (!s.frames->params.progressive) return;
    if (s.frame == ctx.frame - 1 && s.frame >= 0) {
        sum = s.sum;
        count = s.count;
    } else if (ctx.has_previous) {
        sum = ctx.resumed("acuity_sum", 3, "progressive acuity sampling");
        count = ctx.resumed("acuity_count", 1, "progressive acuity sampling");
    }
}

}  // namespace

VisualPolarMap SparseFrames::map(const FrameContext& ctx, int frame) const {
    return sparse_vp_map(params, ctx.settings->width, ctx.settings->height, frame);
}

std::shared_ptr<SparseFrames> sparse_frames(const Params& params, const std::string& mode) {
    auto frames = std::make_shared<SparseFrames>();
    frames->params = parse_sparse_params(params, mode);
    return frames;
}

std::function<BlurRampGeometry(const FrameContext&)> blur_geometry_of(
    std::shared_ptr<SparseFrames> frames) {
    return [frames](const FrameContext& ctx) {
        return blur_ramp_geometry(frames->map(ctx, ctx.frame));
    };
}

void vp_trace_stage(FrameContext& ctx) {
    const SparseState& s = ctx.state<SparseState>();
    SparseFrames& frames = *s.frames;
    const VisualPolarMap map = frames.map(ctx, ctx.frame);
    Counters& counters = ctx.result->counters;
    VpTraceStats stats;
    Image points;
    // The texels' statuses and points from a table, made again when the forward map changes (a
    // moving gaze: every frame, with each row count's angles once, VpRowAngles) and kept while
    // it does not (a static gaze, BMFR's staircase moving or not; the fovea's columns follow the
    // staircase: trace_vp_gbuffer). Not under `--scalar`: vp_gbuffer_texel then runs for every
    // texel, where a debugger's breakpoint stops.
    const VpTexelTable* table = nullptr;
    if (simd_allowed()) {
        if (!frames.texels || !frames.texels->map.same_forward(map))
            frames.texels = vp_texel_table(map);
        table = &*frames.texels;
    }
    MaskedGBuffer vp = trace_vp_gbuffer(map, primary_view(ctx, *s.bvh), points, stats, table);
    counters.add("buffer_width", map.width);
    counters.add("buffer_height", map.height);
    counters.add("fovea_columns", map.fovea_columns);
    add_vp_trace_counters(ctx, stats);
    char text[192];
    std::snprintf(text, sizeof text,
                  "gaze (%.9g, %.9g), %dx%d texels, i_f = %d, s = %.6g px/deg: %lld traced, %lld "
                  "clipped, %lld off screen",
                  static_cast<double>(map.gaze.x), static_cast<double>(map.gaze.y), map.width,
                  map.height, map.fovea_columns, static_cast<double>(map.scale),
                  static_cast<long long>(stats.texels_traced),
                  static_cast<long long>(stats.texels_clipped),
                  static_cast<long long>(stats.texels_off_screen));
    ctx.note = text;
    output_gbuffer(ctx, std::move(vp.gbuffer));
    ctx.output("valid", BufferKind::id, {"valid"}, std::move(vp.valid));
    ctx.output("screen_point", BufferKind::scalar, {"x", "y"}, std::move(points));
}

StageDef vp_trace_stage_def(std::shared_ptr<SparseFrames> frames, std::shared_ptr<BvhCache> bvh) {
    return {"vp_trace",
            {},
            traced_outputs("vp_", "screen_point"),
            vp_trace_stage,
            sparse_state(std::move(frames), std::move(bvh))};
}

void vp_resolve_stage(FrameContext& ctx) {
    SparseFrames& frames = *ctx.state<SparseState>().frames;
    const VisualPolarMap map = frames.map(ctx, ctx.frame);
    const Image& color = ctx.input("color");
    const Image& valid = ctx.input("valid");
    // The table holds (u, r, theta), which BMFR's staircase does not change: kept when only the
    // clip moved, with the frame's map
    const bool reused = frames.forward && frames.forward->map.same_forward(map);
    if (!reused) frames.forward = vp_forward_table(map);
    frames.forward->map = map;
    ResolveStats stats;
    const bool mip = frames.params.mip_resolve;
    // Every pixel is written: an earlier frame's storage saves the zero fill
    Image out = resolve_visual_polar(
        map, color, valid, stats, mip, &*frames.forward,
        ctx.recycled("output", map.screen_width, map.screen_height, color.channels),
        &frames.packed);
    ctx.result->counters.add("screen_pixels_untraced_taps", stats.pixels_untraced_taps);
    ctx.note = (mip ? "phi mips, trilinear (" + std::to_string(vp_mip_levels(map)) + " levels)"
                    : std::string("bilinear")) +
               (reused ? ", forward map reused" : ", forward map computed");
    ctx.output("output", BufferKind::color, rgb, std::move(out));
    if (wants_resolve_decisions(ctx))
        output_resolve_decisions(ctx, vp_resolve_decisions(*frames.forward, mip));
}

StageDef vp_resolve_stage_def(std::shared_ptr<SparseFrames> frames, std::string output) {
    std::vector<Port> outputs = {{"output", std::move(output)}};
    for (Port& port : resolve_decision_ports(frames->params.mip_resolve))
        outputs.push_back(std::move(port));
    return {"resolve",
            {{"color", "vp_color"}, {"valid", "vp_valid"}},
            outputs,
            vp_resolve_stage,
            sparse_state(std::move(frames))};
}

void falloff_mask_stage(FrameContext& ctx) {
    const SparseParams& params = ctx.state<SparseState>().frames->params;
    const int width = ctx.settings->width, height = ctx.settings->height;
    std::int64_t sampled = 0;
    Image mask = linear_falloff_mask(
        params.falloff, width, height, sparse_gaze(params, width, height, ctx.frame),
        sparse_eccentricity(params, *ctx.scene, ctx.camera, width, height),
        static_cast<std::uint32_t>(ctx.frame), sampled);
    ctx.result->counters.add("pixels_sampled", sampled);
    ctx.result->counters.add("pixels_unsampled",
                             static_cast<std::int64_t>(width) * height - sampled);
    char text[96];
    std::snprintf(text, sizeof text, "%lld of %lld pixels sampled (%.2f%%)",
                  static_cast<long long>(sampled), static_cast<long long>(width) * height,
                  100.0 * static_cast<double>(sampled) / (static_cast<double>(width) * height));
    ctx.note = text;
    ctx.output("mask", BufferKind::id, {"sampled"}, std::move(mask));
}

StageDef falloff_mask_stage_def(std::shared_ptr<SparseFrames> frames) {
    return {"falloff_mask",
            {},
            {{"mask", "sample_mask"}},
            falloff_mask_stage,
            sparse_state(std::move(frames))};
}

void fill_stage(FrameContext& ctx) {
    const bool fill = ctx.state<SparseState>().frames->params.fill;
    const Image& mask = ctx.input("mask");
    ctx.note = fill ? "push-pull" : "black where unsampled";
    ctx.output("output", BufferKind::color, rgb,
               fill ? push_pull(ctx.input("radiance"), mask) : ctx.input("radiance"));
    if (ctx.has_input("emission"))
        ctx.output("emission", BufferKind::color, rgb,
                   fill ? push_pull(ctx.input("emission"), mask) : ctx.input("emission"));
}

StageDef fill_stage_def(std::shared_ptr<SparseFrames> frames, std::string output, bool emission) {
    std::vector<Port> inputs = {{"radiance", "sparse_radiance"}};
    std::vector<Port> outputs = {{"output", std::move(output)}};
    if (emission) {
        inputs.emplace_back("emission", "sparse_emission");
        outputs.emplace_back("emission", "filled_emission");
    }
    inputs.emplace_back("mask", "sample_mask");
    return {"fill", inputs, outputs, fill_stage, sparse_state(std::move(frames))};
}

void acuity_trace_stage(FrameContext& ctx) {
    const SparseState& s = ctx.state<SparseState>();
    const std::vector<glm::vec2> points = frame_acuity_points(ctx, s.frames->params);
    Counters& counters = ctx.result->counters;
    VpTraceStats stats;
    MaskedGBuffer g = trace_point_gbuffer(points, ctx.settings->width, ctx.settings->height,
                                          primary_view(ctx, *s.bvh), stats);
    counters.add("samples", static_cast<std::int64_t>(points.size()));
    counters.add("samples_traced", stats.texels_traced);
    counters.add("samples_off_screen", stats.texels_off_screen);
    add_trace_counters(counters, "primary", stats.rays.primary);
    ctx.note = std::to_string(points.size()) + " samples, " +
               std::to_string(stats.texels_off_screen) + " off screen (dropped)";
    Image where(static_cast<int>(points.size()), 1, 2);
    for (std::size_t k = 0; k < points.size(); ++k) {
        where.at(static_cast<int>(k), 0, 0) = points[k].x;
        where.at(static_cast<int>(k), 0, 1) = points[k].y;
    }
    output_gbuffer(ctx, std::move(g.gbuffer));
    ctx.output("valid", BufferKind::id, {"valid"}, std::move(g.valid));
    ctx.output("point", BufferKind::scalar, {"x", "y"}, std::move(where));
}

StageDef acuity_trace_stage_def(std::shared_ptr<SparseFrames> frames,
                                std::shared_ptr<BvhCache> bvh) {
    return {"acuity_trace",
            {},
            traced_outputs("acuity_", "point"),
            acuity_trace_stage,
            sparse_state(std::move(frames), std::move(bvh))};
}

void acuity_accumulate_stage(FrameContext& ctx) {
    AccumulateState& s = ctx.state<AccumulateState>();
    const int width = ctx.settings->width, height = ctx.settings->height;
    Image sum(width, height, 3, 0.0f), count(width, height, 1, 0.0f);
    starting_sums(ctx, s, sum, count);
    const Image& points_image = ctx.input("point");
    std::vector<glm::vec2> points;
    for (int k = 0; k < points_image.width; ++k)
        points.emplace_back(points_image.at(k, 0, 0), points_image.at(k, 0, 1));
    splat_samples(points, ctx.input("valid"), ctx.input("radiance"), sum, count);
    s.sum = sum;
    s.count = count;
    s.frame = ctx.frame;
    ctx.note = s.frames->params.progressive ? "progressive: every sample since frame 0"
                                            : "this frame's samples";
    ctx.output("sum", BufferKind::scalar, rgb, std::move(sum));
    ctx.output("count", BufferKind::scalar, {"n"}, std::move(count));
}

StageDef acuity_accumulate_stage_def(std::shared_ptr<SparseFrames> frames) {
    auto state = std::make_shared<AccumulateState>();
    state->frames = std::move(frames);
    return {"acuity_accumulate",
            {{"point", "acuity_point"}, {"valid", "acuity_valid"}, {"radiance", "acuity_radiance"}},
            {{"sum", "acuity_sum"}, {"count", "acuity_count"}},
            acuity_accumulate_stage,
            state};
}

void acuity_resolve_stage(FrameContext& ctx) {
    const bool fill = ctx.state<SparseState>().frames->params.fill;
    Image weight;
    Image mean = sample_mean(ctx.input("sum"), ctx.input("count"), weight);
    std::int64_t empty = 0;
    for (float w : weight.data) empty += w == 0.0f;
    ctx.result->counters.add("pixels_without_sample", empty);
    ctx.note = std::to_string(empty) + " pixels without a sample" +
               (fill ? ", push-pull filled" : ", black");
    ctx.output("final", BufferKind::color, rgb, fill ? push_pull(mean, weight) : std::move(mean));
}

StageDef acuity_resolve_stage_def(std::shared_ptr<SparseFrames> frames) {
    return {"acuity_resolve",
            {{"sum", "acuity_sum"}, {"count", "acuity_count"}},
            {"final"},
            acuity_resolve_stage,
            sparse_state(std::move(frames))};
}

}  // namespace fovref
