// `fovref probe` for the TAA stage (docs/temporal.md): the pass's own per-pixel function
// (taa_pixel) rerun on the rendered frame and the previous frame's buffers, with what it did:
// the reprojected position, the history taps and weights, the depths compared, the decision and
// the age, checked against the rendered TAA output.
#pragma once

#include <string>

#include "ref/stage/probe.h"
#include "ref/temporal/taa_params.h"

namespace fovref {

/// The buffers the TAA stage of the probed frame read and wrote, and its gaze.
struct TaaProbeInputs {
    TaaSettings settings;
    std::string color;   ///< pass 2's output ("shaded" in basic, "resolved" in the log-polar modes)
    std::string depth;   ///< the current view depth
    std::string bounds;  ///< clamp-buffer's bounds ("" otherwise)
    std::string output;  ///< the TAA output, which the next frame reads as its history
    glm::vec2 gaze{0.0f};
};

/// The names of a frame's TAA buffers, found in the frame (basic or a log-polar mode).
TaaProbeInputs taa_probe_inputs(const FrameResult& frame, const TaaSettings& settings,
                                glm::vec2 gaze);

/// Appends the [taa] section for pixel (c.x, c.y).
void explain_taa(const ProbeContext& c, const TaaProbeInputs& in, ProbeReport& report);

}  // namespace fovref
