// `fovref bench visual-polar` (Koskela P5): the single-thread cost per frame of path tracing +
// BMFR in screen space (`pathtrace --param denoise=bmfr`) against the same in Visual-Polar space
// (`visual-polar`) at one eye of P5's HMD (1280x1440) and at 1280x720, with the speed-ups next
// to P5's; and on a moving sequence the error of both, and of linear-falloff with BMFR, against
// the converged reference (pathtrace-reference): RMSE, SSIM, RMSE per eccentricity ring and the
// temporal error, with each method's samples per frame. A benchmark, not a test: it prints
// figures.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace fovref {

struct BenchVisualPolarOptions {
    std::string scene = "checker-room";
    /// The cost part: 0 x 0 = the pair 1280x1440 and 1280x720; --width and --height give one size.
    int width = 0, height = 0;
    int repeats = 3;  ///< timed frames after an untimed first one
    /// The cost part times its three methods this many times in turn and keeps each stage's
    /// fastest over all of them (a slow spell of a shared machine spoils one round, not one side
    /// of a ratio).
    int rounds = 1;
    std::string error_size = "320x180";  ///< the error part, WxH
    int frames = 8;                      ///< frames of the error sequence
    int every = 4;                       ///< compare every K-th frame (K - 1, 2K - 1, ...)
    int reference_spp = 64;              ///< samples per pixel of the reference
    int rings = 5;                       ///< eccentricity rings of the ring table
    /// The cost part's gaze for visual-polar and log-polar-pathtrace: a gaze track file
    /// (frame,x,y lines), whose maps and tables are made again each frame; empty: the centre.
    std::string gaze_track;
    bool skip_cost = false, skip_error = false;
    bool quiet = false;
};

void add_bench_visual_polar_options(CLI::App& command, BenchVisualPolarOptions& options);

/// Runs the benchmark and prints its tables. Returns 0; throws fovref::Error for a bad option.
int run_bench_visual_polar(const BenchVisualPolarOptions& options);

}  // namespace fovref
