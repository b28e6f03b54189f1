// Tile frustum culling as a stage (docs/frustum.md): for the frame's camera, each screen tile's
// culled view of the BVH, and the check that it loses no primary-ray hit; optionally the same for
// each tile's shadow rays towards a point light.
//
//   frustum_cull  (nothing) -> frustum_tiles (one texel per tile: nodes kept, leaves kept,
//                  triangles kept, entry node, entry depth, nodes tested; binary32, exact up to
//                  2^24, the entry node of a tree of more than 16.7 M nodes rounded),
//                  frustum_hit_lost (1 where the pixel-centre primary ray's closest hit
//                  through its tile's culled tree differs from the whole BVH's); with
//                  frustum_shadow=on also frustum_shadow_tiles (the same channels for the
//                  tile's shadow frustum; entry 0 and the whole tree's counts for a tile
//                  traced unculled, 0 for a tile without shadow rays) and
//                  frustum_shadow_lost (1 where the pixel's shadow ray's
//                  occlusion through the culled tree differs from the whole BVH's)
//
// The stage covers a region of the screen: the whole screen (basic), or the composite modes'
// gaze window with only the pixels inside the gaze circle (prefix gaze_frustum_: the buffers
// gaze_frustum_tiles, gaze_frustum_hit_lost, ..., window-sized). Tiles start at the region's
// corner.
//
// Counters (with the stage's prefix): <prefix>tiles, <prefix>nodes_tested, <prefix>nodes_kept,
// <prefix>triangles_kept, <prefix>hits_lost, <prefix>rays (the checked primary rays),
// <prefix>visits_culled and <prefix>visits_unculled (BVH2 nodes those rays visit through their
// tiles' culled trees and through the whole BVH2, trace_culled); with shadow frusta
// <prefix>shadow_rays,
// <prefix>shadow_tiles_unculled, <prefix>shadow_nodes_kept, <prefix>shadow_lost.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "ref/bvh/bvh_cache.h"
#include "ref/frustum/tile_frustum.h"
#include "ref/stage/params.h"
#include "ref/stage/pipeline.h"

namespace fovref {

struct FrustumSettings {
    bool enabled = false;  ///< `frustum` = lund or exact
    int tile_size = 32;    ///< `tile_size` pixels (1280x720: 40 x 23 = 920 tiles, Lund's ~960)
    CullOptions options;   ///< `frustum` = exact, `frustum_trim`, `frustum_entry`, `frustum_bridge`
    bool shadow = false;   ///< `frustum_shadow=on`: a shadow frustum per tile towards a point light
    int light = -1;        ///< `frustum_light`: that light's index in the scene (-1: the first
                           ///< point light)
};

/// The pixels a frustum stage covers: the window [x0, x0 + width) x [y0, y0 + height) of the
/// screen, its pixels whose centre (screen coordinates) `traced` accepts (empty: every one).
struct FrustumRegion {
    int x0 = 0, y0 = 0, width = 0, height = 0;
    std::function<bool(glm::vec2 centre)> traced;
};

/// The point light whose shadow rays are culled: light `light` (it must be a point light), or
/// with -1 the scene's first point light. Throws fovref::Error naming `light_option` or, without
/// a point light, `shadow_option`.
int shadow_light(const Scene& scene, int light, const std::string& light_option,
                 const std::string& shadow_option);

/// The shadow ray of primary hit `hit` (seen from `eye`) towards point light `light`, as
/// shade_direct casts it: origin offset along the geometric normal turned to the viewer by
/// shadow_epsilon_scale x the scene's scale, towards the light, t in [0, shadow_t_max]. False
/// when the surface faces away from the light geometrically or sits on it (no shadow ray).
bool shadow_ray_of(const Scene& scene, const Hit& hit, glm::vec3 eye, glm::vec3 light, Ray& ray);

/// frustum, tile_size, frustum_trim, frustum_entry, frustum_bridge, frustum_shadow, frustum_light.
std::vector<ParamSpec> frustum_param_specs();
/// Throws fovref::Error naming the parameter.
FrustumSettings parse_frustum_params(const Params& params);

/// The stage `<prefix>cull` writing <prefix>tiles, <prefix>hit_lost (and the shadow buffers)
/// over `region` (empty: the whole screen).
StageDef frustum_cull_stage_def(const FrustumSettings& settings, std::shared_ptr<BvhCache> bvh,
                                const std::string& prefix = "frustum_",
                                std::function<FrustumRegion(const FrameContext&)> region = {});
void frustum_cull_stage(FrameContext& context);

}  // namespace fovref
