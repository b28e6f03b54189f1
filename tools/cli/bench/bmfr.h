// `fovref bench bmfr` (issue 15, point 7): the single-thread time per frame of the path tracer
// and of each BMFR phase at 1280x720, and on a moving sequence the error of the noisy 1-spp
// image and of the denoised one against the converged reference (pathtrace-reference), in the
// style of Koskela P2 Tables 2-3 (RMSE, SSIM, temporal error). A benchmark, not a test: it
// prints figures (docs/bmfr.md has a measured table).
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct BenchBmfrOptions {
    std::string scene = "cornell";
    int width = 1280, height = 720;             ///< the cost part
    int repeats = 3;                            ///< timed frames after an untimed first one
    int error_width = 320, error_height = 180;  ///< the error part
    int frames = 12;                            ///< frames of the error sequence
    int every = 4;                              ///< compare every K-th frame (K - 1, 2K - 1, ...)
    int reference_spp = 256;                    ///< samples per pixel of the reference
    bool skip_cost = false, skip_error = false;
    std::string input;                ///< --input DIR: time external buffers only
    std::vector<std::string> params;  ///< with --input: BMFR parameters
    bool demodulated = false;         ///< with --input: the colour is already demodulated
    bool quiet = false;
};

void add_bench_bmfr_options(CLI::App& command, BenchBmfrOptions& options);

/// Runs the benchmark and prints its tables. Returns 0; throws fovref::Error for a bad option.
int run_bench_bmfr(const BenchBmfrOptions& options);

}  // namespace fovref
