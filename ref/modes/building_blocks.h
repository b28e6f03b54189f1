// Modes that exercise ref/core and ref/scene alone (the passes in ref/building_blocks):
// camera-rays, rng, halton, splat, geometry. Each stage is a named function wiring one pass.
#pragma once

#include "ref/stage/pipeline.h"

namespace fovref {

Pipeline camera_rays_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline rng_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline halton_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline splat_pipeline(const Scene* scene, const RenderSettings& settings);
Pipeline geometry_pipeline(const Scene* scene, const RenderSettings& settings);

// The stages.
void camera_rays_stage(FrameContext& context);
void rng_stage(FrameContext& context);
void halton_points_stage(FrameContext& context);
void halton_offsets_stage(FrameContext& context);
void centroid_splat_stage(FrameContext& context);
void headlight_shade_stage(FrameContext& context);
void scene_geometry_stage(FrameContext& context);

}  // namespace fovref
