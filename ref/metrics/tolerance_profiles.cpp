// The shipped tolerance profiles of `fovref diff --profile` (SPEC §11: every tolerance states its
// reason). docs/diff.md tabulates them with the measurements behind each value.
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/metrics/compare.h"

namespace fovref {

namespace {

Tolerance ids(double edge_share, const std::string& reason) {
    Tolerance t;
    t.max_edge_mismatch_share = edge_share;
    t.max_interior_mismatches = 0;
    t.reason = reason;
    return t;
}

Tolerance values(double abs, double rel, std::int64_t ulp, const std::string& reason) {
    Tolerance t;
    t.abs = abs;
    t.rel = rel;
    t.ulp = ulp;
    t.reason = reason;
    return t;
}

// Shared by both GPU profiles: what differs once the same primitive is seen. The values are
// about 3x the largest differences measured between fovref and Mesa's llvmpipe (OpenGL 4.5,
// tools/clients/osmesa_gbuffer.cpp) on the five procedural scenes at 1280x720 (docs/diff.md).
// `how` says where the GPU's attribute arithmetic differs, `id_reason` why its ids may differ
// on edges; `id_buffers` are the id buffers the profile covers.
ToleranceTable make_gpu_profile(const std::string& how, const std::string& id_reason,
                                const std::vector<std::string>& id_buffers) {
    ToleranceTable table;
    for (const std::string& name : id_buffers) table.buffers[name] = ids(0.0025, id_reason);
    const std::string depth_reason =
        how +
        "; ill-conditioned where the surface is seen at a grazing angle (a relative change e of "
        "the ray moves the point by about e / cos): measured up to 3.9e-5 relative (million), "
        "1e-6 for 99.99% of the pixels";
    table.buffers["gbuffer_view_depth"] = values(0.0, 1e-4, 0, depth_reason);
    table.buffers["gbuffer_hit_distance"] = values(0.0, 1e-4, 0, depth_reason);
    table.buffers["gbuffer_world_position"] =
        values(5e-3, 1e-4, 0,
               how +
                   "; the point moves along the ray with the depth (up to 4e-5 of the distance "
                   "measured), so a coordinate near 0 needs an absolute bound: 5e-3 m = 1e-4 "
                   "of the 50 m the procedural scenes span");
    table.buffers["gbuffer_shading_normal"] =
        values(3e-3, 0.0, 0,
               "the interpolated vertex normal changes fast across small curved triangles, so "
               "the small difference in the interpolation point shows: measured up to 9.1e-4 "
               "(million), 2.4e-5 for 99.9% of the pixels");
    table.buffers["gbuffer_geometric_normal"] =
        values(1e-5, 0.0, 0,
               "the face normal from a float cross product and the GPU's normalize(): measured "
               "up to 1.8e-7");
    table.buffers["gbuffer_albedo"] =
        values(4e-3, 0.0, 0,
               "bilinear texture filtering with fixed-point weights (8 bits on llvmpipe: up to "
               "1/256 of the texel difference; measured 1.6e-3 on checker-room); untextured "
               "albedo is exact");
    table.buffers["gbuffer_motion"] =
        values(1e-3, 0.0, 0,
               "the surface point projected with the previous camera: its depth error times the "
               "motion (not measured here: the OpenGL client writes no motion)");
    table.buffers["final"] =
        values(1e-3, 1e-3, 0,
               "shading on the G-buffer above with the GPU's own sqrt, division and pow (not "
               "correctly rounded; not measured here: the OpenGL client shades nothing)");
    table.fallback.reason = "bit-exact (no GPU tolerance declared for this buffer)";
    return table;
}

ToleranceTable make_gpu_raster() {
    return make_gpu_profile(
        "perspective-correct interpolation of float attributes over the unsnapped triangle, in "
        "the GPU's operation order",
        "a GPU rasterizer snaps its own float projection to the sub-pixel grid and clips "
        "differently (docs/raster.md): centres within ~1/256 px of an edge may change owner; "
        "measured up to 0.031% of the golden's edge pixels (llvmpipe, 1280x720), 0.25% allowed; "
        "an interior mismatch is a bug",
        {"gbuffer_primitive_id", "gbuffer_material_id", "splat_primitive"});
}

ToleranceTable make_gpu_rt() {
    return make_gpu_profile(
        "the hit's t and barycentrics from the GPU's own ray-triangle arithmetic (another shear "
        "or Moller-Trumbore, FMA)",
        "a GPU ray-triangle test (hardware or software) decides rays within ~1 ulp of a shared "
        "edge differently and need not be watertight; the same share as gpu-raster (0.25% of "
        "the golden's edge pixels; not measured against a GPU ray tracer here); an interior "
        "mismatch is a bug",
        {"gbuffer_primitive_id", "gbuffer_material_id"});
}

}  // namespace

const std::vector<std::string>& tolerance_profile_names() {
    static const std::vector<std::string> names = {"bit-exact", "gpu-raster", "gpu-rt"};
    return names;
}

ToleranceTable tolerance_profile(const std::string& name) {
    if (name == "bit-exact") {
        ToleranceTable table;
        table.fallback.reason = "bit-exact: the default between builds of fovref (SPEC §11)";
        return table;
    }
    if (name == "gpu-raster") return make_gpu_raster();
    if (name == "gpu-rt") return make_gpu_rt();
    std::string known;
    for (const std::string& n : tolerance_profile_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("--profile '" + name + "': unknown profile (expected " + known + ")");
}

}  // namespace fovref
