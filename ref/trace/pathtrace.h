// One-sample-per-pixel path tracing (Koskela §2.4, P2 §3.1; SPEC §8), the `pathtrace` mode's
// shading pass. The primary hit comes from the rasterized G-buffer; each pixel then traces, with
// the default max_bounces = 1, the sources' four rays:
//
//   vertex 0 (the G-buffer surface, seen from the camera):
//     Le of an emitter seen directly (its front side)
//     + NEE: one light chosen uniformly among the N lights, one point uniformly on it, one
//       shadow ray; contribution f Le G V N (f = albedo / pi, G = cos cos_l A / d^2 for an
//       area light, cos / d^2 with I for a point light)
//     + one secondary ray, cosine-weighted about the shading normal (throughput x albedo)
//   vertex 1 (the secondary hit): NEE as above, weighted by the throughput; its own emission is
//     not added (it is counted through NEE only: no double counting, no MIS; SPEC §8)
//   max_bounces B > 1: vertices 1 .. B-1 also sample a secondary ray, continued with Russian
//     roulette probability q = rr (Koskela eq. 2.2) from vertex 1 on (throughput / q)
//
// MIS (`mis=power`; P2's path tracer, Veach's power heuristic): at every vertex k < B that traces
// a secondary ray, an emissive triangle is reached by two strategies, NEE and the secondary ray,
// with solid-angle densities p_l = d^2 / (N A cos_l) (N lights, the triangle's area A, cos_l of
// its normal with the direction back) and p_b = the BSDF's (cos / pi for Lambert, bsdf_pdf for a
// glossy one). NEE's estimate of such a light is weighted by p_l^2 / (p_l^2 + p_b^2), and a
// secondary ray that hits the front of an emissive triangle adds throughput Le p_b^2 / (p_l^2 +
// p_b^2) (throughput after the vertex's BSDF weight and roulette). Quad and point lights, which no
// ray can hit, and every light at the last vertex (k = B: no secondary ray) keep weight 1. The
// random numbers are the same as without MIS: only the weights change, so `mis=power` has the
// same expectation (tested against `off` on pathtrace-reference) and lower variance where the
// BSDF finds a light NEE samples poorly (glossy reflections of small lights).
//
// A path ends at the background (no environment light), at a black albedo, at a Russian-roulette
// termination, at a direction sampled about the shading normal that points below the geometric
// surface (absorbed), or after B secondary rays; each is counted. Surfaces are two-sided as in
// direct_light.h (normals turned towards the incoming direction). A glossy material (specular
// > 0) is evaluated and sampled with the BSDF of ref/trace/bsdf.h (Lambert + GGX, the secondary
// direction from the lobe mixture), in NEE and for the secondary ray.
//
// Random numbers (SPEC §0): rand(frame, pixel, d) with d = 6 k + j at vertex k:
//   j = 0 light choice, 1 and 2 the point on the light, 3 and 4 the secondary direction,
//   5 Russian roulette; and d = 65536 + k the lobe choice of a glossy vertex.
#pragma once

#include <cstdint>

#include "ref/bvh/bvh.h"
#include "ref/scene/scene.h"
#include "ref/scene/surface.h"
#include "ref/stage/params.h"
#include "ref/trace/direct_light.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

struct PathTraceParams {
    int max_bounces = 1;  ///< secondary rays per path (1: the sources' four-ray configuration)
    float rr = 0.8f;      ///< Russian-roulette continuation probability (max_bounces > 1)
    /// `mis=power`: multiple importance sampling of emissive triangles (Koskela P2's path
    /// tracer), below; `mis=off` (default, SPEC §8): NEE only.
    bool mis = false;
};

/// The path tracer's parameters max_bounces and rr of the sparse modes (visual-polar,
/// linear-falloff, acuity: "four rays per sample").
std::vector<ParamSpec> path_param_specs();

/// max_bounces and rr from a mode's parameters (`specs` holds them); throws fovref::Error naming
/// the parameter, and (with `rr_needs_bounces`) when rr is given but max_bounces is 1, where it
/// changes nothing.
PathTraceParams parse_path_params(const Params& params, const std::vector<ParamSpec>& specs,
                                  bool rr_needs_bounces = true);

struct PathTraceStats {
    ShadingStats shading;  ///< NEE: shadow rays and their traversal, light samples skipped
    TraceStats secondary;  ///< the secondary rays' traversal
    std::int64_t paths = 0;
    std::int64_t ended_background = 0;  ///< a secondary ray left the scene
    std::int64_t ended_black = 0;       ///< a black albedo ended the path
    std::int64_t ended_roulette = 0;    ///< Russian roulette ended the path
    std::int64_t ended_below = 0;       ///< the sampled direction went below the geometric surface
};

/// A direction about unit normal n with pdf cos / pi, from two numbers in [0, 1):
/// r = sqrt(u1), phi = 2 pi u2, local (r cos phi, r sin phi, sqrt(1 - u1)) in the basis of
/// Duff et al. 2017 around n.
glm::vec3 cosine_direction(glm::vec3 n, float u1, float u2);

struct Bsdf;

/// NEE at `surface` (normals already turned to the incoming side): one light chosen with the
/// numbers of dimensions d, d + 1, d + 2. Returns f Le G V N (the estimate of the direct light),
/// f = albedo / pi, or the glossy BSDF's f(l, v) when `glossy` is given (v towards the viewer).
/// `mis` (MIS, may be null): the estimate is weighted by the power heuristic against the BSDF's
/// density when the light is an emissive triangle.
glm::vec3 sample_one_light(const Scene& scene, const Bvh& bvh, const SurfacePoint& surface,
                           glm::vec3 n_g, glm::vec3 n_s, std::uint32_t frame, std::uint32_t pixel,
                           std::uint32_t dimension, ShadingStats& stats,
                           const Bsdf* glossy = nullptr, glm::vec3 v = glm::vec3(0.0f),
                           bool mis = false);

/// The power heuristic's weight of the strategy with density `a` against one with `b`:
/// a^2 / (a^2 + b^2), computed as 1 / (1 + r^2) with r = b / a when a >= b, else r^2 / (1 + r^2)
/// with r = a / b (binary32; no square overflows or underflows): 0 when a = 0 < b, 1 when b = 0,
/// and 1/2 for two infinite densities.
float mis_power_weight(float a, float b);

/// The radiance of one path from G-buffer pixel (x, y) (black for background). `emission`
/// (may be null) gets the first term alone: the emission of the surface seen directly.
glm::vec3 pathtrace_pixel(const Scene& scene, const Bvh& bvh, const PathTraceParams& params,
                          const ShadeInputs& in, const Camera& camera, int frame, int x, int y,
                          PathTraceStats& stats, glm::vec3* emission = nullptr);

/// The pass: an RGB image of the G-buffer's size; `emission` (may be null) gets each pixel's
/// directly seen emission (BMFR keeps it out of the fit, docs/bmfr.md). `mask` (may be null):
/// only pixels where it is not 0 are traced, the others stay black (sparse sampling, untraced
/// Visual-Polar texels).
Image pathtrace(const Scene& scene, const Bvh& bvh, const PathTraceParams& params,
                const ShadeInputs& in, const Camera& camera, int frame, PathTraceStats& stats,
                Image* emission = nullptr, const Image* mask = nullptr);

}  // namespace fovref
