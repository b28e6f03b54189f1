// The filters as stages (SPEC §6; docs/foveation.md, docs/visual-polar.md): each reads one image
// and writes one, wired by the mode into its chain of buffers.
//
//   internal_aa       color, valid -> output   Meng's internal AA on the buffer (before pass 2)
//   gaussian_lerp     input -> output          Lund's Gaussian lerp around the frame's gaze
//   post_aa           input -> output          Meng's post-AA around the frame's gaze
//   blur_horizontal, blur_vertical  input -> output   P5's blur ramp, one separable pass each
//
// The per-frame values a filter needs from its mode (the gaze, the log-polar map's R, the blur
// ramp's geometry) come from functions the mode gives when it wires the stage.
#pragma once

#include <functional>
#include <string>

#include <glm/glm.hpp>

#include "ref/filters/blur_ramp.h"
#include "ref/stage/pipeline.h"

namespace fovref {

/// Meng's internal anti-aliasing (internal_aa.h) of `color` over its traced texels (`valid`).
StageDef internal_aa_stage_def(const std::string& color, const std::string& valid,
                               const std::string& output);
void internal_aa_stage(FrameContext& context);

/// The frame's gaze point, in screen pixels.
using FrameGaze = std::function<glm::vec2(const FrameContext&)>;

/// Lund's Gaussian lerp (gaussian_lerp.h) of `input` around the frame's gaze.
StageDef gaussian_lerp_stage_def(const std::string& input, const std::string& output,
                                 FrameGaze gaze);
void gaussian_lerp_stage(FrameContext& context);

/// Where Meng's post-AA is measured from in a frame: the gaze and R (the log-polar map's).
struct PostAaGeometry {
    glm::vec2 gaze{0.0f};
    float radius_max = 1.0f;
};
/// Meng's post-AA (post_aa.h) of `input`.
StageDef post_aa_stage_def(const std::string& input, const std::string& output,
                           std::function<PostAaGeometry(const FrameContext&)> geometry);
void post_aa_stage(FrameContext& context);

/// P5's blur ramp (blur_ramp.h) measured from the frame's geometry: its horizontal pass
/// (`input` to "blur_horizontal") and its vertical pass (to `output`), which share the table of
/// each pixel's sigma and exp (made by the first pass when the geometry changes, kept while it
/// does not).
using FrameBlurGeometry = std::function<BlurRampGeometry(const FrameContext&)>;
std::vector<StageDef> blur_ramp_stage_defs(const BlurRamp& ramp, const std::string& input,
                                           const std::string& output, FrameBlurGeometry geometry);
void blur_horizontal_stage(FrameContext& context);
void blur_vertical_stage(FrameContext& context);

}  // namespace fovref
