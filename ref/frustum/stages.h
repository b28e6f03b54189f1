// Tile frustum culling as a stage (docs/frustum.md): for the frame's camera, each screen tile's
// culled view of the BVH, and the check that it loses no primary-ray hit.
//
//   frustum_cull  (nothing) -> frustum_tiles (one texel per tile: nodes kept, leaves kept,
//                  triangles kept, entry node, entry depth, nodes tested; binary32, exact up to
//                  2^24, the entry node of a tree of more than 16.7 M nodes rounded),
//                  frustum_hit_lost (W x H: 1 where the pixel-centre primary ray's closest hit
//                  through its tile's culled tree differs from the whole BVH's)
//
// Counters: frustum_tiles, frustum_nodes_tested, frustum_nodes_kept, frustum_triangles_kept,
// frustum_hits_lost.
#pragma once

#include <memory>

#include "ref/bvh/bvh_cache.h"
#include "ref/frustum/tile_frustum.h"
#include "ref/stage/params.h"
#include "ref/stage/pipeline.h"

namespace fovref {

struct FrustumSettings {
    bool enabled = false;  ///< `frustum` = lund or exact
    int tile_size = 32;    ///< `tile_size` pixels (1280x720: 40 x 23 = 920 tiles, Lund's ~960)
    CullOptions options;   ///< `frustum` = exact, `frustum_trim`, `frustum_entry`, `frustum_bridge`
};

/// frustum, tile_size, frustum_trim, frustum_entry, frustum_bridge.
std::vector<ParamSpec> frustum_param_specs();
/// Throws fovref::Error naming the parameter.
FrustumSettings parse_frustum_params(const Params& params);

StageDef frustum_cull_stage_def(const FrustumSettings& settings, std::shared_ptr<BvhCache> bvh);
void frustum_cull_stage(FrameContext& context);

}  // namespace fovref
