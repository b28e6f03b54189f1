// The registry of render modes. Each mode is a pipeline of stages (one GPU pass each); later
// renderers add their modes here.
#include <memory>

#include "ref/core/error.h"
#include "ref/core_passes/core_passes.h"
#include "ref/stage/pipeline.h"
#include "ref/trace/trace_modes.h"

namespace fovref {

namespace {

const std::vector<std::string> rgb = {"r", "g", "b"};
const std::vector<std::string> xyz = {"x", "y", "z"};

Pipeline camera_rays_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.stages.push_back({"camera_rays", {}, {"ray_dir"}, [](FrameContext& ctx) {
                            ctx.result->add(
                                "ray_dir", BufferKind::vector, xyz,
                                camera_rays(ctx.camera, ctx.settings->width, ctx.settings->height));
                        }});
    p.final_outputs = {"ray_dir"};
    return p;
}

Pipeline rng_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.stages.push_back({"rng", {}, {"rng"}, [](FrameContext& ctx) {
                            ctx.result->add("rng", BufferKind::scalar, {"d0", "d1", "d2"},
                                            rng_image(static_cast<std::uint32_t>(ctx.frame),
                                                      ctx.settings->width, ctx.settings->height));
                        }});
    p.final_outputs = {"rng"};
    return p;
}

Pipeline halton_pipeline(const Scene*, const RenderSettings&) {
    Pipeline p;
    p.stages.push_back(
        {"halton_points", {}, {"halton_points"}, [](FrameContext& ctx) {
             ctx.result->add("halton_points", BufferKind::scalar, {"x", "y"}, halton_image(false));
         }});
    p.stages.push_back(
        {"halton_offsets", {}, {"halton_offsets"}, [](FrameContext& ctx) {
             ctx.result->add("halton_offsets", BufferKind::scalar, {"x", "y"}, halton_image(true));
         }});
    p.final_outputs = {"halton_offsets"};
    return p;
}

Pipeline splat_pipeline(const Scene* scene, const RenderSettings&) {
    Pipeline p;
    p.stages.push_back(
        {"centroid_splat",
         {},
         {"splat_depth", "splat_primitive", "splat_normal", "splat_albedo"},
         [scene](FrameContext& ctx) {
             SplatBuffers s =
                 centroid_splat(*scene, ctx.camera, ctx.settings->width, ctx.settings->height);
             ctx.result->counters.add("centroids_splatted", s.splatted);
             ctx.result->counters.add("centroids_behind", s.behind);
             ctx.result->counters.add("centroids_off_screen", s.off_screen);
             ctx.result->add("splat_depth", BufferKind::depth, {"z"}, std::move(s.depth));
             ctx.result->add("splat_primitive", BufferKind::id, {"id"}, std::move(s.primitive));
             ctx.result->add("splat_normal", BufferKind::vector, xyz, std::move(s.normal));
             ctx.result->add("splat_albedo", BufferKind::color, rgb, std::move(s.albedo));
         }});
    p.stages.push_back(
        {"headlight_shade",
         {"splat_albedo", "splat_normal", "splat_primitive"},
         {"final"},
         [](FrameContext& ctx) {
             ctx.result->add("final", BufferKind::color, rgb,
                             headlight_shade(ctx.input("splat_albedo"), ctx.input("splat_normal"),
                                             ctx.input("splat_primitive"), ctx.camera));
         }});
    p.final_outputs = {"final"};
    return p;
}

Pipeline geometry_pipeline(const Scene* scene, const RenderSettings&) {
    Pipeline p;
    p.stages.push_back(
        {"scene_geometry",
         {},
         {"tri_positions", "tri_normals", "tri_uvs", "tri_material"},
         [scene](FrameContext& ctx) {
             GeometryBuffers g = scene_geometry(*scene);
             ctx.result->counters.add("triangles",
                                      static_cast<std::int64_t>(scene->triangle_count()));
             ctx.result->add("tri_positions", BufferKind::scalar, xyz, std::move(g.positions));
             ctx.result->add("tri_normals", BufferKind::vector, xyz, std::move(g.normals));
             ctx.result->add("tri_uvs", BufferKind::scalar, {"u", "v"}, std::move(g.uvs));
             ctx.result->add("tri_material", BufferKind::id, {"id"}, std::move(g.material_ids));
         }});
    p.final_outputs = {"tri_positions", "tri_normals", "tri_uvs", "tri_material"};
    return p;
}

}  // namespace

const std::vector<ModeInfo>& render_modes() {
    static const std::vector<ModeInfo> modes = [] {
        auto mode = [](std::string name, std::string description, auto build) {
            ModeInfo m;
            m.name = std::move(name);
            m.description = std::move(description);
            m.build = build;
            return m;
        };
        ModeInfo basic = mode("basic",
                              "one ray per pixel centre, Lambertian shading with one shadow ray "
                              "per light (Lund §3.1)",
                              basic_pipeline);
        basic.params = basic_params();
        basic.explain = explain_basic;
        basic.pixel_functions = basic_pixel_functions;
        ModeInfo ground_truth =
            mode("ground-truth",
                 "16 Halton(2,3) rays per pixel, shaded as basic, box-filtered (Lund §3.2)",
                 ground_truth_pipeline);
        ground_truth.explain = explain_ground_truth;
        ground_truth.pixel_functions = ground_truth_pixel_functions;
        ModeInfo rng = mode("rng", "rand(frame, pixel, d) for d = 0..2 (SPEC §0)", rng_pipeline);
        rng.needs_scene = false;
        ModeInfo halton = mode(
            "halton", "the 16 Halton(2,3) points, raw and scaled (Lund eq. 3.11)", halton_pipeline);
        halton.needs_scene = false;
        return std::vector<ModeInfo>{
            basic,
            ground_truth,
            mode("splat",
                 "centroid splat of every triangle with headlight shading (a trivial pass that "
                 "pins scene, materials, textures and camera path)",
                 splat_pipeline),
            mode("camera-rays", "primary ray direction through every pixel centre (SPEC §1)",
                 camera_rays_pipeline),
            mode("geometry", "the scene's triangles, normals, uvs and material ids as buffers",
                 geometry_pipeline),
            rng,
            halton,
        };
    }();
    return modes;
}

}  // namespace fovref
