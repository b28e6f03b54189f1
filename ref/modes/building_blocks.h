// The modes that exercise ref/core and ref/scene alone, wired from the building-block passes
// (ref/building_blocks/stages.h), in the order `fovref modes` lists them:
//
//   splat        centroid_splat -> headlight_shade -> final
//   camera-rays  camera_rays -> ray_dir
//   geometry     scene_geometry -> tri_positions, tri_normals, tri_uvs, tri_material
//   rng          rng -> rng                              (no scene)
//   halton       halton_points, halton_offsets            (no scene)
#pragma once

#include <vector>

#include "ref/stage/pipeline.h"

namespace fovref {

std::vector<ModeInfo> building_block_modes();

}  // namespace fovref
