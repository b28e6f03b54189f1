// `fovref bench temporal` (issue 14, point 6): the single-thread cost of the TAA stage per frame
// relative to the rest of the frame (basic and the log-polar modes, each TAA variant), and on a
// moving and a static camera sequence the ring errors against the ground truth and the temporal
// error with and without TAA, with depth rejection and with clamping. A benchmark, not a test: it
// prints figures (docs/temporal.md has a measured table).
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace fovref {

struct BenchTemporalOptions {
    std::string scene = "checker-room";
    int width = 1280, height = 720;             ///< the cost part
    int repeats = 3;                            ///< timed frames per row after an untimed first one
    int error_width = 320, error_height = 180;  ///< the error part
    int frames = 24;                            ///< frames of each error sequence
    int every = 4;                              ///< moving camera: compare every K-th frame
    bool skip_cost = false, skip_error = false;
    bool quiet = false;
};

void add_bench_temporal_options(CLI::App& command, BenchTemporalOptions& options);

/// Runs the benchmark and prints its tables. Returns 0; throws fovref::Error for a bad option.
int run_bench_temporal(const BenchTemporalOptions& options);

}  // namespace fovref
