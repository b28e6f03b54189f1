#include "ref/bvh/bvh_cache.h"

namespace fovref {

const Bvh& BvhCache::get(const Scene& scene, Counters& counters) {
    if (!bvh) {
        bvh = build_bvh(scene.positions);
        counters.add("bvh_built_nodes", bvh->stats.nodes);
        counters.add("bvh_built_leaves", bvh->stats.leaves);
    }
    return *bvh;
}

void add_trace_counters(Counters& counters, const std::string& kind, const TraceStats& stats) {
    counters.add("rays_" + kind, stats.rays);
    counters.add(kind + "_nodes_visited", stats.nodes_visited);
    counters.add(kind + "_triangles_tested", stats.triangles_tested);
    counters.add(kind + "_hits", stats.hits);
}

}  // namespace fovref
