#include "ref/filters/stages.h"

#include <memory>
#include <optional>
#include <utility>

#include "ref/core/simd.h"
#include "ref/filters/gaussian_lerp.h"
#include "ref/filters/internal_aa.h"
#include "ref/filters/post_aa.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};

struct LerpState : StageState {
    FrameGaze gaze;
};

struct PostAaState : StageState {
    std::function<PostAaGeometry(const FrameContext&)> geometry;
    PostAaSizes sizes;  ///< the kernel sizes, kept while the gaze and R stay the same
};

struct BlurState : StageState {
    BlurRamp ramp;
    FrameBlurGeometry geometry;
    // The table of each pixel's sigma and exp for the last geometry seen: made by a frame's
    // first pass whose geometry differs (a moving gaze: every frame; its exps eight at a time),
    // read by its second pass and kept while the gaze is static, with the passes' plan added
    // by the first pass of a later frame that keeps it
    std::optional<BlurRampTable> table;
    /// The table for this frame's geometry, made if it was made for another; none under
    /// `--scalar` (only the AVX groups read it).
    const BlurRampTable* table_for(const BlurRampGeometry& g, bool vertical, bool& made) {
        made = false;
        if (!simd_allowed()) return nullptr;
        made = !table || !table->made_for(ramp, g);
        if (made)
            table = blur_ramp_table(ramp, g);
        else if (!vertical)
            add_blur_ramp_plan(*table);
        return &*table;
    }
};

// Either blur pass as a stage: the frame's geometry, the table kept while it repeats.
void run_blur_pass(FrameContext& ctx, bool vertical) {
    BlurState& state = ctx.state<BlurState>();
    const BlurRampGeometry g = state.geometry(ctx);
    bool made = false;
    const BlurRampTable* table = state.table_for(g, vertical, made);
    ctx.note = !table         ? "sigma and exp per pixel computed"
               : made         ? "sigma and exp per pixel computed (kept)"
               : !table->plan ? "sigma and exp per pixel kept"
                              : "sigma and exp per pixel kept, with the groups' plan";
    const Image& input = ctx.input("input");
    // The pass writes every value (AVX; the scalar reference copies the image first): an
    // earlier frame's storage saves the zero fill
    Image storage = ctx.recycled("output", input.width, input.height, input.channels);
    ctx.output("output", BufferKind::color, rgb,
               vertical
                   ? blur_ramp_vertical(state.ramp, g, input, true, table, std::move(storage))
                   : blur_ramp_horizontal(state.ramp, g, input, true, table, std::move(storage)));
}

std::shared_ptr<BlurState> blur_state(const BlurRamp& ramp, FrameBlurGeometry geometry) {
    auto state = std::make_shared<BlurState>();
    state->ramp = ramp;
    state->geometry = std::move(geometry);
    return state;
}

}  // namespace

void internal_aa_stage(FrameContext& ctx) {
    ctx.output("output", BufferKind::color, rgb,
               internal_aa(ctx.input("color"), ctx.input("valid")));
}

StageDef internal_aa_stage_def(const std::string& color, const std::string& valid,
                               const std::string& output) {
    return {"internal_aa",
            {{"color", color}, {"valid", valid}},
            {{"output", output}},
            internal_aa_stage,
            nullptr};
}

void gaussian_lerp_stage(FrameContext& ctx) {
    const glm::vec2 gaze = ctx.state<LerpState>().gaze(ctx);
    const Image& input = ctx.input("input");
    // The filter writes every pixel: an earlier frame's storage saves the zero fill
    ctx.output("output", BufferKind::color, rgb,
               gaussian_lerp(input, gaze,
                             ctx.recycled("output", input.width, input.height, input.channels)));
}

StageDef gaussian_lerp_stage_def(const std::string& input, const std::string& output,
                                 FrameGaze gaze) {
    auto state = std::make_shared<LerpState>();
    state->gaze = std::move(gaze);
    return {"gaussian_lerp", {{"input", input}}, {{"output", output}}, gaussian_lerp_stage, state};
}

void post_aa_stage(FrameContext& ctx) {
    const PostAaGeometry g = ctx.state<PostAaState>().geometry(ctx);
    PostAaState& state = ctx.state<PostAaState>();
    const Image& input = ctx.input("input");
    // The filter writes every pixel: an earlier frame's storage saves the zero fill
    ctx.output("output", BufferKind::color, rgb,
               post_aa(input, g.gaze, g.radius_max, true, &state.sizes,
                       ctx.recycled("output", input.width, input.height, input.channels)));
}

StageDef post_aa_stage_def(const std::string& input, const std::string& output,
                           std::function<PostAaGeometry(const FrameContext&)> geometry) {
    auto state = std::make_shared<PostAaState>();
    state->geometry = std::move(geometry);
    return {"post_aa", {{"input", input}}, {{"output", output}}, post_aa_stage, state};
}

void blur_horizontal_stage(FrameContext& ctx) { run_blur_pass(ctx, false); }

void blur_vertical_stage(FrameContext& ctx) { run_blur_pass(ctx, true); }

std::vector<StageDef> blur_ramp_stage_defs(const BlurRamp& ramp, const std::string& input,
                                           const std::string& output, FrameBlurGeometry geometry) {
    const std::shared_ptr<BlurState> state = blur_state(ramp, std::move(geometry));
    return {{"blur_horizontal",
             {{"input", input}},
             {{"output", "blur_horizontal"}},
             blur_horizontal_stage,
             state},
            {"blur_vertical",
             {{"input", "blur_horizontal"}},
             {{"output", output}},
             blur_vertical_stage,
             state}};
}

}  // namespace fovref
