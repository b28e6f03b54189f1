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
glm::vec3 sample_one_light(const Scene& scene, const Bvh& bvh, const SurfacePoint& surface,
                           glm::vec3 n_g, glm::vec3 n_s, std::uint32_t frame, std::uint32_t pixel,
                           std::uint32_t dimension, ShadingStats& stats,
                           const Bsdf* glossy = nullptr, glm::vec3 v = glm::vec3(0.0f));

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
