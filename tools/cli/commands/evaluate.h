// `fovref evaluate` (issue 4; Lund §5.3.4, SPEC §10): renders modes (or reads rendered frames)
// over a camera path, compares every k-th frame with the ground-truth renderer in error ranges
// around the gaze point, averages each ring's statistic over the evaluated frames, and writes
// CSV, JSON, an SVG plot like Lund Fig. 5.7-5.11 and error heatmaps. docs/probe-evaluate.md
// ("evaluate") describes the options and the outputs.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct EvaluateOptions {
    std::string scene;
    std::vector<std::string> modes;       ///< render modes compared with the reference
    std::vector<std::string> frame_dirs;  ///< or: directories of rendered frames (f000_final.*)
    std::string reference_mode = "ground-truth";
    std::vector<std::string> params;  ///< key=value, applied to every mode that knows the key
    int width = 320, height = 180, frames = 20, every = 1;
    /// Renders of each mode: stage times are the median over them (the images of every repeat
    /// must be the same bits, checked).
    int repeats = 1;
    float time_start = 0.0f, time_step = 1.0f / 30;
    std::string gaze;  ///< X,Y pixels; default the centre
    int rings = 20;
    float max_range = 1.0f;
    bool linear = false;  ///< compare stored values instead of display space (SPEC §10)
    bool flip = false;    ///< also LDR-FLIP per evaluated frame (slow: seconds per megapixel)
    std::string out_dir;
    /// Read the reference frames from this directory when it holds them for these settings,
    /// else render them and store them there (shared by the jobs of a sweep).
    std::string reference_dir;
    bool quiet = false;
};

void add_evaluate_options(CLI::App& command, EvaluateOptions& options);

/// Throws fovref::Error for usage and input errors. Returns 0.
int run_evaluate(const EvaluateOptions& options);

/// Only the reference frames of `options` into options.reference_dir (rendered unless the
/// directory already holds them): a sweep's reference job. Throws fovref::Error.
void store_evaluation_reference(const EvaluateOptions& options);

}  // namespace fovref
