// The scene's BVH as the stages of one render share it, and the traversal counters every stage
// that traces rays adds to its frame (their names are read by scripts and recorded in golden
// manifests).
#pragma once

#include <optional>
#include <string>

#include "ref/bvh/bvh.h"
#include "ref/scene/scene.h"
#include "ref/stage/frame.h"

namespace fovref {

/// The scene's BVH, built when a stage first traces a ray and kept for later frames; its build
/// appears in the counters of the frame that needed it (bvh_built_nodes, bvh_built_leaves). The
/// stages of a mode that trace hold the same cache.
struct BvhCache {
    std::optional<Bvh> bvh;
    const Bvh& get(const Scene& scene, Counters& counters);
};

/// rays_<kind>, <kind>_nodes_visited, <kind>_triangles_tested, <kind>_hits.
void add_trace_counters(Counters& counters, const std::string& kind, const TraceStats& stats);

}  // namespace fovref
