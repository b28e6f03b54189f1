// `fovref bench frustum` (issue 32, docs/frustum.md): Lund's tile frustum culling measured on the
// CPU. For each scene, tile size and test (Lund's, exact): the culling time per frame, the culled
// trees' nodes, triangles and memory, and every pixel-centre primary ray traced through its
// tile's culled BVH2 against the same BVH2 unculled (nodes visited, triangles tested, time), with
// the production BVH4 traversal's time beside them and the hits culling lost. A benchmark, not a
// test: it prints figures, next to Lund's Tables 5.5-5.6 (no gain on DXR).
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct BenchFrustumOptions {
    std::vector<std::string> scenes = {"cornell", "sphere-grid", "checker-room", "glossy-floor",
                                       "million"};
    int width = 1280, height = 720;
    std::vector<int> tile_sizes = {16, 32, 64};
    bool quiet = false;
};

void add_bench_frustum_options(CLI::App& command, BenchFrustumOptions& options);

/// Runs the benchmark and prints its table. Returns 0; throws fovref::Error for a bad option.
int run_bench_frustum(const BenchFrustumOptions& options);

}  // namespace fovref
