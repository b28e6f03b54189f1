#include "ref/building_blocks/stages.h"

#include "ref/building_blocks/building_blocks.h"

namespace fovref {

namespace {
const std::vector<std::string> rgb = {"r", "g", "b"};
const std::vector<std::string> xyz = {"x", "y", "z"};
}  // namespace

void camera_rays_stage(FrameContext& ctx) {
    ctx.output("ray_dir", BufferKind::vector, xyz,
               camera_rays(ctx.camera, ctx.settings->width, ctx.settings->height));
}

void rng_stage(FrameContext& ctx) {
    ctx.output("rng", BufferKind::scalar, {"d0", "d1", "d2"},
               rng_image(static_cast<std::uint32_t>(ctx.frame), ctx.settings->width,
                         ctx.settings->height));
}

void halton_points_stage(FrameContext& ctx) {
    ctx.output("halton_points", BufferKind::scalar, {"x", "y"}, halton_image(false));
}

void halton_offsets_stage(FrameContext& ctx) {
    ctx.output("halton_offsets", BufferKind::scalar, {"x", "y"}, halton_image(true));
}

void centroid_splat_stage(FrameContext& ctx) {
    SplatBuffers s =
        centroid_splat(*ctx.scene, ctx.camera, ctx.settings->width, ctx.settings->height);
    ctx.result->counters.add("centroids_splatted", s.splatted);
    ctx.result->counters.add("centroids_behind", s.behind);
    ctx.result->counters.add("centroids_off_screen", s.off_screen);
    ctx.output("splat_depth", BufferKind::depth, {"z"}, std::move(s.depth));
    ctx.output("splat_primitive", BufferKind::id, {"id"}, std::move(s.primitive));
    ctx.output("splat_normal", BufferKind::vector, xyz, std::move(s.normal));
    ctx.output("splat_albedo", BufferKind::color, rgb, std::move(s.albedo));
}

void headlight_shade_stage(FrameContext& ctx) {
    ctx.output("final", BufferKind::color, rgb,
               headlight_shade(ctx.input("splat_albedo"), ctx.input("splat_normal"),
                               ctx.input("splat_primitive"), ctx.camera));
}

void scene_geometry_stage(FrameContext& ctx) {
    GeometryBuffers g = scene_geometry(*ctx.scene);
    ctx.result->counters.add("triangles", static_cast<std::int64_t>(ctx.scene->triangle_count()));
    ctx.output("tri_positions", BufferKind::scalar, xyz, std::move(g.positions));
    ctx.output("tri_normals", BufferKind::vector, xyz, std::move(g.normals));
    ctx.output("tri_uvs", BufferKind::scalar, {"u", "v"}, std::move(g.uvs));
    ctx.output("tri_material", BufferKind::id, {"id"}, std::move(g.material_ids));
}

StageDef camera_rays_stage_def() { return {"camera_rays", {}, {"ray_dir"}, camera_rays_stage}; }

StageDef rng_stage_def() { return {"rng", {}, {"rng"}, rng_stage}; }

StageDef halton_points_stage_def() {
    return {"halton_points", {}, {"halton_points"}, halton_points_stage};
}

StageDef halton_offsets_stage_def() {
    return {"halton_offsets", {}, {"halton_offsets"}, halton_offsets_stage};
}

StageDef centroid_splat_stage_def() {
    return {"centroid_splat",
            {},
            {"splat_depth", "splat_primitive", "splat_normal", "splat_albedo"},
            centroid_splat_stage};
}

StageDef headlight_shade_stage_def() {
    return {"headlight_shade",
            {"splat_albedo", "splat_normal", "splat_primitive"},
            {"final"},
            headlight_shade_stage};
}

StageDef scene_geometry_stage_def() {
    return {"scene_geometry",
            {},
            {"tri_positions", "tri_normals", "tri_uvs", "tri_material"},
            scene_geometry_stage};
}

}  // namespace fovref
