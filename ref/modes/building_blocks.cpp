#include "ref/modes/building_blocks.h"

#include "ref/building_blocks/stages.h"

namespace fovref {

namespace {

Pipeline splat_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.add(centroid_splat_stage_def()).add(headlight_shade_stage_def());
    p.final_outputs = {"final"};
    return p;
}

Pipeline camera_rays_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.add(camera_rays_stage_def());
    p.final_outputs = {"ray_dir"};
    return p;
}

Pipeline geometry_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.add(scene_geometry_stage_def());
    p.final_outputs = {"tri_positions", "tri_normals", "tri_uvs", "tri_material"};
    return p;
}

Pipeline rng_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.add(rng_stage_def());
    p.final_outputs = {"rng"};
    return p;
}

Pipeline halton_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.add(halton_points_stage_def()).add(halton_offsets_stage_def());
    p.final_outputs = {"halton_offsets"};
    return p;
}

ModeInfo mode(std::string name, std::string description,
              Pipeline (*build)(const Scene*, const RenderSettings&), bool needs_scene = true) {
    ModeInfo m;
    m.name = std::move(name);
    m.description = std::move(description);
    m.build = build;
    m.needs_scene = needs_scene;
    return m;
}

}  // namespace

std::vector<ModeInfo> building_block_modes() {
    return {
        mode("splat",
             "centroid splat of every triangle with headlight shading (a trivial pass that pins "
             "scene, materials, textures and camera path)",
             splat_pipeline),
        mode("camera-rays", "primary ray direction through every pixel centre (SPEC §1)",
             camera_rays_pipeline),
        mode("geometry", "the scene's triangles, normals, uvs and material ids as buffers",
             geometry_pipeline),
        mode("rng", "rand(frame, pixel, d) for d = 0..2 (SPEC §0)", rng_pipeline, false),
        mode("halton", "the 16 Halton(2,3) points, raw and scaled (Lund eq. 3.11)", halton_pipeline,
             false),
    };
}

}  // namespace fovref
