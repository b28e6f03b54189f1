// `fovref bench rays` (issue 3, point 7): BVH build time and ray throughput of the reference on
// the procedural scenes, optionally side by side with Embree (tools/cli/bench/embree.h). A
// benchmark, not a test: it prints figures and checks nothing but the agreement it reports.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct BenchRaysOptions {
    std::vector<std::string> scenes;  ///< empty: every procedural scene
    int width = 1280;                 ///< primary rays: one through each pixel centre
    int height = 720;
    int repeats = 3;  ///< each timing is the fastest of this many runs
    /// The ray rows' timings this many times in turn (fovref's, then Embree's, then fovref's
    /// again, ...), each figure the fastest over all rounds: a slow spell of a shared machine
    /// then spoils one round, not one side of a ratio.
    int rounds = 1;
    bool quiet = false;  ///< only the table
    /// With Embree: list up to this many hit/miss disagreements per row after the table, each
    /// with the ray, both answers, the brute force's and how close the hit is to an edge.
    int explain = 0;
};

/// Registers the command's options on `command`.
void add_bench_rays_options(CLI::App& command, BenchRaysOptions& options);

/// Runs the benchmark and prints its table on stdout. Returns 0; throws fovref::Error for an
/// unknown scene or a bad size.
int run_bench_rays(const BenchRaysOptions& options);

}  // namespace fovref
