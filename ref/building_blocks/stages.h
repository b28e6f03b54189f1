// The building-block passes as stages (ref/building_blocks/building_blocks.h): each has fixed
// outputs and no configuration, so each is a constant StageDef.
//
//   camera_rays      -> ray_dir
//   rng              -> rng
//   halton_points    -> halton_points;   halton_offsets -> halton_offsets
//   centroid_splat   -> splat_depth, splat_primitive, splat_normal, splat_albedo
//   headlight_shade  splat_albedo, splat_normal, splat_primitive -> final
//   scene_geometry   -> tri_positions, tri_normals, tri_uvs, tri_material
#pragma once

#include "ref/stage/pipeline.h"

namespace fovref {

StageDef camera_rays_stage_def();
StageDef rng_stage_def();
StageDef halton_points_stage_def();
StageDef halton_offsets_stage_def();
StageDef centroid_splat_stage_def();
StageDef headlight_shade_stage_def();
StageDef scene_geometry_stage_def();

// The stages' bodies.
void camera_rays_stage(FrameContext& context);
void rng_stage(FrameContext& context);
void halton_points_stage(FrameContext& context);
void halton_offsets_stage(FrameContext& context);
void centroid_splat_stage(FrameContext& context);
void headlight_shade_stage(FrameContext& context);
void scene_geometry_stage(FrameContext& context);

}  // namespace fovref
