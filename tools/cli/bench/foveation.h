// `fovref bench foveation` (issue 13, point 9): single-thread stage times of the foveated modes
// against the basic ray tracer measured in the same run, on the procedural scenes, with the share
// of W x H dispatched and traced. A benchmark, not a test: it prints figures (docs/foveation.md
// has a measured table).
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct BenchFoveationOptions {
    std::vector<std::string> scenes;  ///< empty: every procedural scene
    int width = 1280;
    int height = 720;
    /// Frames timed per mode after a first one (which builds the BVH and is left out); each
    /// stage's time is the fastest over them.
    int repeats = 3;
    /// Times every row this many times in turn (basic, each mode, then basic again, ...) and
    /// keeps each figure's fastest over all of them: on a shared machine a slow spell then spoils
    /// one round, not one side of a speed-up.
    int rounds = 1;
    /// empty: fov, kfov, cfov, ckfov, kfr, stereo-lp and cfov with filters=lerp
    std::vector<std::string> modes;
    /// Also print each stage's own fastest time under its mode's row (where the time goes).
    bool stages = false;
    /// A gaze track (`gaze_track=FILE` of the foveated modes): the gaze moves from frame to
    /// frame, so the maps and pass 2's tables are made again each frame; empty: the centre.
    std::string gaze_track;
    bool quiet = false;
};

void add_bench_foveation_options(CLI::App& command, BenchFoveationOptions& options);

/// Runs the benchmark and prints its tables. Returns 0; throws fovref::Error for an unknown scene
/// or mode, or a bad size.
int run_bench_foveation(const BenchFoveationOptions& options);

}  // namespace fovref
