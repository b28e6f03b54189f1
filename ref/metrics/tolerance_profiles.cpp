// The shipped tolerance profiles of `fovref diff --profile` (SPEC §11: every tolerance states its
// reason). docs/diff.md tabulates them with the measurements behind each value.
#include <algorithm>
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

Tolerance integers(double edge_share, const std::string& reason) {
    Tolerance t = ids(edge_share, reason);
    t.integer = true;
    return t;
}

Tolerance shares(double abs, double rel, double failing_share, const std::string& reason) {
    Tolerance t = values(abs, rel, 0, reason);
    t.max_failing_share = failing_share;
    return t;
}

// A decision buffer: a flip where the oracle's margin lies within `epsilon` of the threshold is
// near-threshold (reported, not failing); any other flip fails.
Tolerance decision(const std::string& margin, std::vector<double> epsilon,
                   const std::string& reason) {
    Tolerance t = integers(0.0, reason);
    t.margin = margin;
    t.margin_epsilon = std::move(epsilon);
    return t;
}

// What the profile assumes of the GPU's own arithmetic (docs/diff.md, "What a correct port
// differs by"): binary32 with its own operation order and FMA; exp, log within 4 ulp; sin, cos,
// atan2 within 2^-20 absolute (NVIDIA's and AMD's hardware meet both; the Vulkan spec's minimum,
// sin/cos within 2^-11, needs a looser tolerance file). The largest screen point a mapping
// computes is the screen diagonal R (1469 px at 1280x720).
constexpr const char* gpu_arithmetic =
    "binary32 in the GPU's operation order with FMA; exp/log within 4 ulp, sin/cos/atan2 within "
    "2^-20 absolute";

// The G-buffer entries of one family (prefix "gbuffer_", "lp_gbuffer_", ...): `depth_rel` the
// relative bound of depths (ill-conditioned at grazing angles), `where` what moves the hit.
void add_gbuffer(ToleranceTable& table, const std::string& prefix, const std::string& how,
                 const std::string& id_reason, double id_share, double depth_rel,
                 const std::string& where) {
    table.buffers[prefix + "primitive_id"] = ids(id_share, id_reason);
    table.buffers[prefix + "material_id"] = ids(id_share, id_reason);
    const std::string depth_reason =
        how + where +
        "; ill-conditioned where the surface is seen at a grazing angle (a relative change e of "
        "the ray moves the point by about e / cos): measured up to 3.9e-5 relative (million "
        "pixels, llvmpipe), 1e-6 for 99.99% of the pixels";
    table.buffers[prefix + "view_depth"] = values(0.0, depth_rel, 0, depth_reason);
    table.buffers[prefix + "hit_distance"] = values(0.0, depth_rel, 0, depth_reason);
    table.buffers[prefix + "world_position"] =
        values(5e-3, depth_rel, 0,
               how + where +
                   "; the point moves along the ray with the depth, so a coordinate near 0 needs "
                   "an absolute bound: 5e-3 m = 1e-4 of the 50 m the procedural scenes span");
    table.buffers[prefix + "shading_normal"] =
        values(3e-3, 0.0, 0,
               "the interpolated vertex normal changes fast across small curved triangles, so "
               "the small difference in the interpolation point shows: measured up to 9.1e-4 "
               "(million pixels), 2.4e-5 for 99.9% of the pixels");
    table.buffers[prefix + "geometric_normal"] =
        values(1e-5, 0.0, 0,
               "the face normal from a float cross product and the GPU's normalize(): measured "
               "up to 1.8e-7");
    table.buffers[prefix + "albedo"] =
        values(4e-3, 0.0, 0,
               "bilinear texture filtering with fixed-point weights (8 bits on llvmpipe: up to "
               "1/256 of the texel difference; measured 1.6e-3 on checker-room); untextured "
               "albedo is exact");
    table.buffers[prefix + "motion"] =
        values(1e-3, 0.0, 0,
               "the surface point projected with the previous camera: its depth error times the "
               "motion (not measured here: the OpenGL client writes no motion)");
}

// Pass 2's threshold decisions (resolve_tap, resolve_mip_level) and the oracle's margins of them.
void add_resolve_decisions(ToleranceTable& table) {
    table.buffers["resolve_tap"] = decision(
        "resolve_tap_margin", {2e-3},
        "pass 2's first tap (column, row) is floor of the sampling point's coordinates in "
        "texels, which the GPU's forward map (log, atan2; 4 ulp and 2^-20) moves by about 1e-3 "
        "texel (measured 7e-4 on lavapipe at 1280x720): a flip where the oracle's coordinate "
        "lies within 2e-3 texel of an integer (resolve_tap_margin) is near-threshold and changes "
        "no pixel (the blend is continuous across it); any other flip is a bug");
    table.buffers["resolve_mip_level"] = decision(
        "resolve_mip_margin", {1e-5},
        "the mip level read first is floor(lambda), lambda = log2(max(s_u, s_v)) of the texels "
        "per pixel: the GPU's log2 (4 ulp of |lambda| <= 12: 6e-6) and the few ulps of s_u's "
        "pow and ln (2e-6 / ln 2) move lambda by up to 1e-5 (measured 1.2e-6 on lavapipe): a "
        "flip where the oracle's lambda lies within 1e-5 of an integer (resolve_mip_margin) is "
        "near-threshold and changes no pixel (the levels' lerp is continuous); any other flip "
        "is a bug");
    table.buffers["resolve_tap_margin"] = values(
        2e-3, 0.0, 4,
        "the oracle's distance of pass 2's sampling point from where its tap changes (the diff "
        "reads the golden's to judge resolve_tap; a port need not write it); 1e30 where pass 2 "
        "read no buffer (within 4 ulp)");
    table.buffers["resolve_mip_margin"] = values(
        1e-5, 0.0, 4,
        "the oracle's distance of lambda from where the mip level changes (the diff reads the "
        "golden's to judge resolve_mip_level; a port need not write it); 1e30 where none (within 4 "
        "ulp)");
}

// TAA's depth, margins and ages.
void add_taa(ToleranceTable& table) {
    table.buffers["taa_view_depth"] =
        values(0.0, 3e-4, 0, "the depth of the texel pass 2 sampled: as lp_gbuffer_view_depth");
    table.buffers["taa_margin"] = values(
        4e-3, 0.0, 0,
        "the oracle's distances of TAA's decisions from their thresholds (the diff reads the "
        "golden's to judge taa_age's flips; a port need not write it): the depth test's within "
        "3e-4 relative, the reprojected point's within 4e-3 px; 1e30 where no such decision was "
        "made");
    table.buffers["taa_age"] = integers(
        0.02,
        "an age restarts where the depth test |z' - z_h| <= tau z' or the clamp decides "
        "differently; with depths within 3e-4 relative that happens only where the difference "
        "lies within 3e-4 of tau, at the edges of the rejected regions: 2% of the edge pixels; "
        "a port whose scene sits on the threshold over a whole surface needs its own file");
}

// The foveation buffers: the mappings' screen points, masks, ray counts, shading and pass 2.
void add_foveation(ToleranceTable& table) {
    const std::string a = gpu_arithmetic;
    const std::string point_reason =
        a +
        ": r = exp(L K^-1(t)) - 1 is within 4 ulp (<= 1469 x 2.4e-7 = 3.5e-4 px) and the "
        "angle's cos/sin within 2^-20 (<= 1469 x 9.5e-7 = 1.4e-3 px): 2e-3 px, doubled";
    table.buffers["lp_screen_point"] = values(4e-3, 0.0, 0, point_reason);
    table.buffers["vp_screen_point"] = values(4e-3, 0.0, 0, point_reason);
    const std::string mask_reason =
        "a texel is traced when its screen point lies on the screen (and outside the gaze "
        "circle): one within 4e-3 px of the border or the circle may flip, and it lies on the "
        "mask's edge; 1% of the edge texels allowed, an interior mismatch is a bug";
    for (const char* mask : {"lp_valid", "gaze_valid", "vp_valid", "acuity_valid"})
        table.buffers[mask] = ids(0.01, mask_reason);
    table.buffers["sample_mask"] =
        ids(0.01,
            "a pixel is sampled when its random number lies below L(e), which the GPU's "
            "arithmetic gives within a few ulps: a flip needs a draw within ulps of L (about "
            "1e-6 of the pixels)");
    table.buffers["acuity_point"] = values(4e-3, 0.0, 0, point_reason);
    table.buffers["acuity_count"] =
        integers(0.01, "a sample point within 4e-3 px of a pixel edge lands in the neighbour");
    table.buffers["ray_pixel"] = decision(
        "pixel_edge(lp_screen_point)", {4e-3},
        "the pixel a traced texel's ray is counted in is floor of its screen point, which the "
        "GPU computes within 4e-3 px (lp_screen_point's bound): a flip where the oracle's point "
        "lies within 4e-3 px of a pixel edge is near-threshold (it moves one count of "
        "ray_positions to the neighbour); any other flip is a bug");
    table.buffers["ray_positions"] = shares(
        1.0, 0.0, 0.001,
        "a texel's screen point within 4e-3 px of a pixel edge is counted in the neighbour: a "
        "count may be off by one; off by two (two points crossing into one pixel) on at most "
        "0.1% of the pixels");
    const std::string shade_reason =
        "shading on the G-buffer above with the GPU's own sqrt, division and pow (not "
        "correctly rounded; not measured here: the OpenGL client shades nothing)";
    for (const char* color : {"lp_color", "gaze_color", "vp_color", "shaded", "lp_color_aa",
                              "acuity_sum", "taa_bounds"})
        table.buffers[color] = values(1e-3, 1e-3, 0, shade_reason);
    const std::string resolve_reason =
        "pass 2's taps and weights from the forward map (log, atan2; 4 ulp and 2^-20): the "
        "sampling point moves by about 1e-3 texel, which changes a bilinear blend by 1e-3 of "
        "the local contrast, on top of the shading's 1e-3; later filters (TAA's convex blend, "
        "lerp, post-AA, blur) are weighted means, which do not grow an error";
    for (const char* screen :
         {"resolved", "taa_color", "lerp_filtered", "blur_horizontal", "filled", "final"})
        table.buffers[screen] = values(2e-3, 1e-3, 0, resolve_reason);
    add_resolve_decisions(table);
    add_taa(table);
}

// BMFR's phases (screen or Visual-Polar) and the path-traced radiance they denoise.
void add_path_tracing(ToleranceTable& table) {
    const std::string path_reason =
        "1-spp paths with the same random numbers: the GPU's sqrt, cos and sin in the sampling "
        "move a secondary or shadow ray by ulps, which flips its hit where it passes an edge "
        "and changes the whole pixel; 0.2% of the pixels (an estimate: issue 30 measures it), the "
        "rest within the shading's 1e-3";
    for (const char* radiance :
         {"radiance", "emission", "vp_radiance", "vp_emission", "lp_radiance", "lp_emission",
          "acuity_radiance", "sparse_radiance", "bmfr_illumination", "bmfr_accumulated_noisy"})
        table.buffers[radiance] = shares(1e-3, 1e-3, 0.002, path_reason);
    table.buffers["bmfr_accept"] = integers(
        0.05,
        "a tap is accepted when |P_k - P|^2 and |n_k - n|^2 are below the limits (strict): "
        "positions within 3e-4 relative flip taps near the limits, at the edges of the "
        "disocclusions; 5% of the edge pixels");
    table.buffers["bmfr_accept_margin"] = values(
        1e-3, 1e-4, 0,
        "the oracle's distances of BMFR's accept tests from their limits (the diff reads the "
        "golden's to judge bmfr_accept's flips; a port need not write it); 1e30 where none was "
        "decided");
    table.buffers["bmfr_spp"] = integers(
        0.05, "the sample count follows the accept bits from frame to frame: as bmfr_accept");
    table.buffers["bmfr_previous_pixel"] = values(
        1e-3, 1e-5, 0,
        "the world position times the previous view-projection and a division: a few ulps of "
        "the pixel coordinate");
    table.buffers["bmfr_feature_range"] = values(
        1e-3, 1e-3, 0, "the block's min and max of the stored features: the G-buffer's error");
    table.buffers["bmfr_weights"] =
        values(5e-2, 5e-2, 0,
               "the least-squares weights are ill-conditioned (nearly collinear features in flat "
               "blocks): a GPU's parallel reduction order in the QR changes them far more than the "
               "fitted colour; check bmfr_fitted, which the profile bounds tighter in effect");
    const std::string fit_reason =
        "the fit in half (or single) precision storage: each of the 10 features and weights "
        "carries ~1e-3 relative, and the GPU's reduction order differs from the binary64 row "
        "order; 1e-2, on 0.2% of the pixels more (the path tracer's flips)";
    for (const char* fitted : {"bmfr_fitted", "bmfr_accumulated_filtered"})
        table.buffers[fitted] = shares(1e-2, 1e-2, 0.002, fit_reason);
    const std::string display_reason =
        "display space x^(1/2.2) of the fit's 1e-2 relative: 4.5e-3, plus the TAA's YCoCg clamp "
        "(a weighted mean); 0.2% of the pixels more";
    for (const char* display : {"bmfr_display", "bmfr_taa"})
        table.buffers[display] = shares(5e-3, 5e-3, 0.002, display_reason);
    // Path-traced images and what follows them carry the paths' flips, after BMFR the fit's
    // error (replacing the entries above for a golden that path traces or runs BMFR)
    for (const char* after :
         {"final", "vp_color", "lp_color", "resolved", "blur_horizontal", "filled", "acuity_sum"}) {
        table.path_traced[after] =
            shares(2e-3, 1e-3, 0.002, path_reason + "; then pass 2's and the filters' means");
        table.denoised[after] =
            shares(1e-2, 1.2e-2, 0.002,
                   "after BMFR: the linear x^2.2 of bmfr_taa's 5e-3 relative (1.1e-2), and what "
                   "follows it (the resolve and the blur ramp are weighted means)");
    }
}

// Shared by both GPU profiles: what differs once the same primitive is seen. The G-buffer values
// are about 3x the largest differences measured between fovref and Mesa's llvmpipe (OpenGL 4.5,
// tools/clients/gl_gbuffer.cpp, then through OSMesa) on the five procedural scenes at 1280x720
// (docs/diff.md);
// the rest from the error analysis beside each entry (issue 30's Vulkan port re-measures them).
// `how` says where the GPU's attribute arithmetic differs, `id_reason` why its ids may differ
// on edges.
ToleranceTable make_gpu_profile(const std::string& how, const std::string& id_reason) {
    ToleranceTable table;
    add_gbuffer(table, "gbuffer_", how, id_reason, 0.0025, 1e-4, "");
    const std::string texel_rays =
        "; the texel's ray passes through its screen point (4e-3 px, lp_screen_point), which "
        "turns the ray by about 3e-6 rad: 3e-4 relative at 88 degrees of incidence";
    add_gbuffer(table, "lp_gbuffer_", how, id_reason, 0.0025, 3e-4, texel_rays);
    add_gbuffer(table, "gaze_gbuffer_", how, id_reason, 0.0025, 1e-4, "");
    add_gbuffer(table, "vp_gbuffer_", how, id_reason, 0.0025, 3e-4, texel_rays);
    add_gbuffer(table, "acuity_gbuffer_", how, id_reason, 0.0025, 3e-4,
                "; the sample's screen point from the acuity model's inverse CDF (exp, log)");
    table.buffers["splat_primitive"] = ids(0.0025, id_reason);
    add_foveation(table);
    add_path_tracing(table);
    table.fallback.reason = "bit-exact (no GPU tolerance declared for this buffer)";
    return table;
}

ToleranceTable make_gpu_raster() {
    ToleranceTable table = make_gpu_profile(
        "perspective-correct interpolation of float attributes over the unsnapped triangle, in "
        "the GPU's operation order",
        "a GPU rasterizer snaps its own float projection to the sub-pixel grid and clips "
        "differently (docs/raster.md): centres within ~1/256 px of an edge may change owner; "
        "measured up to 0.031% of the golden's edge pixels (llvmpipe, 1280x720), 0.25% allowed; "
        "an interior mismatch is a bug");
    // kfr samples the rasterized G-buffer at floor(screen point): a point within 4e-3 px of a
    // pixel edge copies the neighbour pixel (4 x 4e-3 = 1.6% of the texels at most)
    for (auto& [name, t] : table.buffers) {
        if (name.rfind("lp_gbuffer_", 0) != 0) continue;
        const std::string kfr =
            "; kfr copies the G-buffer pixel under floor(screen point), and a point within 4e-3 "
            "px of a pixel edge copies the neighbour: up to 1.6% of the texels";
        if (t.max_edge_mismatch_share > 0.0)
            t.max_edge_mismatch_share = 0.02;
        else
            t.max_failing_share = 0.02;
        t.reason += kfr;
    }
    return table;
}

ToleranceTable make_gpu_rt() {
    return make_gpu_profile(
        "the hit's t and barycentrics from the GPU's own ray-triangle arithmetic (another shear "
        "or Moller-Trumbore, FMA)",
        "a GPU ray-triangle test (hardware or software) decides rays within ~1 ulp of a shared "
        "edge differently and need not be watertight; the same share as gpu-raster (0.25% of "
        "the golden's edge pixels; not measured against a GPU ray tracer here); an interior "
        "mismatch is a bug");
}

// The Vulkan compute port's profile (tools/clients/vulkan/, docs/gpu-port.md): gpu-rt's entries
// (its frame pass traces rays in a compute shader) with the threshold decisions compared as
// decisions, each ε from the error analysis of the value the decision tests.
ToleranceTable make_vulkan() {
    ToleranceTable table = make_gpu_rt();
    // Measured on the port (lavapipe, 1280x720): pass 2's sampling point moves by up to 7e-4
    // texel (native atan and log), which times the contrast at an emitter's edge (8 against
    // 0.13 on cornell) gives up to 4.4e-3; 11 of 921600 pixels (1.2e-5) on cornell-kfov, 9 on
    // cornell-cfov, 97 and 105 (1.1e-4) on the two frames of textured-room-ckfov-gaze-lerp (its
    // ceiling light's longer edge); and a Visual-Polar row index within 2.3e-5 of its threshold
    // next to untraced texels changed one pixel of checker-room-visual-polar-basic by 0.051
    for (const char* screen :
         {"resolved", "taa_color", "lerp_filtered", "blur_horizontal", "filled", "final"}) {
        Tolerance& t = table.buffers[screen];
        t.max_failing_share = 2e-4;
        t.reason +=
            "; beyond that 2e-4 of the pixels (measured up to 1.1e-4 at 1280x720: pass 2's "
            "sampling point, 7e-4 texel off, at an emitter's edge of contrast 8, up to 4.4e-3; a "
            "Visual-Polar row within 2.3e-5 of its threshold beside untraced texels)";
    }
    const std::string border =
        "a texel is traced when its screen point lies on the screen: the GPU's point is within "
        "4e-3 px of the oracle's (lp_screen_point's bound), so a flip where the oracle's point "
        "lies within 4e-3 px of the border is near-threshold; any other flip is a bug (the gaze "
        "circle's edge is not covered: a flip there fails)";
    table.buffers["lp_valid"] = decision("screen_border(lp_screen_point)", {4e-3}, border);
    table.buffers["ray_positions"] = values(
        0.0, 0.0, 0,
        "exact: each count off by one comes from a ray_pixel flip, which the diff judges as a "
        "decision and, when near-threshold, attributes the two pixels it changed to (measured "
        "at 1280x720: 41 flips on cornell-kfov, 12 on cornell-cfov, all within 3.1e-4 px of a "
        "pixel edge)");
    table.buffers["vp_valid"] = decision("screen_border(vp_screen_point)", {4e-3}, border);
    table.buffers["taa_age"] = decision(
        "taa_margin", {3e-4, 4e-3},
        "an age restarts where TAA rejects the history: the depth test |z' - z_h| <= tau z' "
        "(channel 0 of taa_margin: (tau z' - |z' - z_h|) / z', the GPU's reprojected depth "
        "within 3e-4 relative) or the reprojected point leaving the history (channel 1: its "
        "distance in pixels from the border of the taps' region, the GPU's within 4e-3 px); a "
        "flip within those of the threshold is near-threshold, any other flip is a bug");
    table.buffers["bmfr_accept"] = decision(
        "bmfr_accept_margin", {1e-4, 1e-4, 1e-3},
        "a tap is accepted when |P_k - P|^2 and |n_k - n|^2 lie below the limits (strict); "
        "bmfr_accept_margin holds, over the pixel's taps, the smallest |L^2 - d^2| / L^2 of "
        "each test and the reprojected index's distance from where the taps change: with the "
        "golden's own positions and normals (a stage-isolated port) d^2 differs by ulps, 1e-4 "
        "relative, and the index by bmfr_previous_pixel's 1e-3 px; a port that computes its "
        "own G-buffer needs its positions' error here (about 2 x 3e-4 |P| / L)");
    return table;
}

}  // namespace

const std::vector<std::string>& tolerance_profile_names() {
    static const std::vector<std::string> names = {"bit-exact", "gpu-raster", "gpu-rt", "vulkan"};
    return names;
}

ToleranceTable tolerance_profile(const std::string& name, const std::vector<std::string>& golden) {
    ToleranceTable table;
    if (name == "bit-exact")
        table.fallback.reason = "bit-exact: the default between builds of fovref (SPEC §11)";
    else if (name == "gpu-raster")
        table = make_gpu_raster();
    else if (name == "gpu-rt")
        table = make_gpu_rt();
    else if (name == "vulkan")
        table = make_vulkan();
    if (!table.fallback.reason.empty()) {
        const auto has = [&golden](const char* buffer) {
            return std::find(golden.begin(), golden.end(), buffer) != golden.end();
        };
        const bool denoised = has("bmfr_taa");
        const bool path_traced = has("radiance") || has("vp_radiance") || has("lp_radiance") ||
                                 has("sparse_radiance") || has("acuity_radiance");
        const std::map<std::string, Tolerance>* over = denoised      ? &table.denoised
                                                       : path_traced ? &table.path_traced
                                                                     : nullptr;
        if (over)
            for (const auto& [buffer, t] : *over) table.buffers[buffer] = t;
        return table;
    }
    std::string known;
    for (const std::string& n : tolerance_profile_names()) known += (known.empty() ? "" : ", ") + n;
    throw Error("--profile '" + name + "': unknown profile (expected " + known + ")");
}

}  // namespace fovref
