// `fovref probe` (issue 4): one screen pixel of a mode and frame explained stage by stage - its
// buffer coordinates, the ray it came from, the hit, the shading inputs, the values of every
// buffer at the pixel - the path a person would otherwise step through in a debugger. Each mode
// adds its own explanation (ModeInfo::explain); later stages (foveation, TAA, BMFR) extend it.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ref/core/halton.h"
#include "ref/stage/frame.h"
#include "ref/stage/pipeline.h"

namespace fovref {

struct ProbeLine {
    std::string key, value;
};

struct ProbeSection {
    std::string stage;  ///< the stage (or "screen", "buffers") this section explains
    std::string title;
    std::vector<ProbeLine> lines;
    void add(std::string key, std::string value) {
        lines.push_back({std::move(key), std::move(value)});
    }
};

struct ProbeReport {
    std::string mode;
    int frame = 0, x = 0, y = 0;
    /// Set when a buffer texel (i, j) is probed instead of a screen pixel (`--texel`).
    std::optional<glm::ivec2> texel;
    int eye = -1;  ///< the eye of a stereo texel (0 left, 1 right); -1: none given
    /// Where the texel lies in the mode's buffers, when not at (i, j) (stereo: column e w + i of
    /// the side-by-side buffer); set by the mode's explainer, read by the buffer listing.
    std::optional<glm::ivec2> buffer_texel;
    std::vector<ProbeSection> sections;
    /// False when the probe's recomputation differs from the rendered buffer: a bug in the
    /// probe or a nondeterminism in the stage.
    bool consistent = true;
    /// The probed frame with every buffer (what the explanation was checked against).
    std::shared_ptr<const FrameResult> rendered;
};

/// What a mode's explainer sees: the rendered frame (every buffer) and the pixel.
struct ProbeContext {
    const Scene* scene = nullptr;
    const RenderSettings* settings = nullptr;
    const FrameResult* frame = nullptr;
    /// Frame - 1 with every buffer (null for frame 0): what a mode carrying state (TAA) read.
    const FrameResult* previous_frame = nullptr;
    Camera camera;
    int x = 0, y = 0;
    /// A buffer texel (i, j) to explain instead of the pixel (modes with a foveation buffer).
    std::optional<glm::ivec2> texel;
    int eye = -1;  ///< the texel's eye in stereo modes (-1: none given)
    /// The frame's TAA launch offset in a pixel or texel (the centre without TAA; set by the
    /// mode's explainer before it explains the ray generation).
    Offset2 jitter{};
    /// The camera of frame - 1 as the stages saw it (FrameContext::previous_camera): the camera
    /// itself on frame 0.
    Camera previous_camera;
};

/// Renders frames 0 .. frame of `mode` (every buffer of the last), then explains pixel (x, y),
/// or, when `texel` is given, that texel of the mode's buffer (x, y are then ignored; `eye`: the
/// texel's eye in a stereo mode, -1 for none). Throws fovref::Error for a pixel outside the
/// screen, a bad frame number, a texel for a mode without a buffer, or an eye without a texel.
ProbeReport probe_pixel(const Scene* scene, const ModeInfo& mode, const RenderSettings& settings,
                        int frame, int x, int y, std::optional<glm::ivec2> texel = std::nullopt,
                        int eye = -1);

/// Formatting helpers for explainers: "%.9g" floats (round-trip exact), vectors.
std::string probe_float(float v);
std::string probe_vec3(glm::vec3 v);

/// The report as indented text.
std::string probe_text(const ProbeReport& report);

}  // namespace fovref
