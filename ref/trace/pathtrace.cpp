#include "ref/trace/pathtrace.h"

#include <algorithm>
#include <cmath>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/trace/bsdf.h"

namespace fovref {

namespace {

constexpr float inv_pi = 0.318309886183790671538f;
constexpr float two_pi = 6.28318530717958647692f;

// Turns the normals of `surface` to the side `towards` points to (two-sided surfaces, as
// direct_light.h): n_g towards it, n_s to n_g's side.
void facing_normals(const SurfacePoint& surface, glm::vec3 towards, glm::vec3& n_g,
                    glm::vec3& n_s) {
    n_g = glm::dot(surface.geometric_normal, towards) >= 0.0f ? surface.geometric_normal
                                                              : -surface.geometric_normal;
    n_s = glm::dot(surface.shading_normal, n_g) < 0.0f ? -surface.shading_normal
                                                       : surface.shading_normal;
}

// MIS: what a secondary ray (unit `direction`, sampled with solid-angle density p_bsdf) adds
// when it hits `surface`: an emissive triangle's Le seen from its front, weighted by the power
// heuristic against NEE's density d^2 / (N A cos_l) of that point; 0 for any other surface.
glm::vec3 mis_emitter_hit(const Scene& scene, const SurfacePoint& surface, const Hit& hit,
                          glm::vec3 direction, float p_bsdf) {
    const Material& material = scene.materials[static_cast<std::size_t>(surface.material)];
    const glm::vec3 e = material.emission;
    if (!(e.x > 0.0f || e.y > 0.0f || e.z > 0.0f)) return glm::vec3(0.0f);
    const float cos_light = -glm::dot(surface.geometric_normal, direction);
    if (!(cos_light > 0.0f)) return glm::vec3(0.0f);  // its back: it emits from its front only
    const std::size_t base = 3 * static_cast<std::size_t>(hit.primitive);
    const glm::vec3 cross = glm::cross(scene.positions[base + 1] - scene.positions[base],
                                       scene.positions[base + 2] - scene.positions[base]);
    const float area = 0.5f * std::sqrt(glm::dot(cross, cross));
    const float p_light =
        hit.t * hit.t / (static_cast<float>(scene.lights.size()) * area * cos_light);
    return e * mis_power_weight(p_bsdf, p_light);
}

// The secondary direction of vertex k: a glossy BSDF's lobe mixture (throughput times its
// weight) or cosine-weighted about n_s. False when the glossy reflection points below the shading
// surface.
bool sample_secondary(const Bsdf& bsdf, glm::vec3 n_s, glm::vec3 v, std::uint32_t frame,
                      std::uint32_t pixel, int k, glm::vec3& direction, glm::vec3& throughput) {
    const std::uint32_t base = 6u * static_cast<std::uint32_t>(k);
    if (!bsdf.glossy()) {
        direction = cosine_direction(n_s, rand_unit(frame, pixel, base + 3),
                                     rand_unit(frame, pixel, base + 4));
        return true;
    }
    // The lobe choice uses its own dimensions (65536 + k), so that diffuse paths keep the
    // numbers they had before glossy materials were sampled.
    glm::vec3 weight;
    if (!bsdf_sample(bsdf, v, rand_unit(frame, pixel, 65536u + static_cast<std::uint32_t>(k)),
                     rand_unit(frame, pixel, base + 3), rand_unit(frame, pixel, base + 4),
                     direction, weight))
        return false;
    throughput *= weight;
    return true;
}

}  // namespace

glm::vec3 cosine_direction(glm::vec3 n, float u1, float u2) {
    // Duff et al. 2017, "Building an orthonormal basis, revisited".
    glm::vec3 t, s;
    duff_basis(n, t, s);
    const float r = std::sqrt(u1);
    const float phi = two_pi * u2;
    const float z = std::sqrt(std::max(0.0f, 1.0f - u1));
    return t * (r * dm::cos(phi)) + s * (r * dm::sin(phi)) + n * z;
}

float mis_power_weight(float a, float b) {
    // Through the ratio of the smaller to the larger density, so that neither square overflows
    // (a sliver of a light seen edge-on has a huge light density) nor underflows to 0 for both
    if (!(a > 0.0f)) return b > 0.0f ? 0.0f : 1.0f;
    if (!(b > 0.0f)) return 1.0f;
    if (std::isinf(a) && std::isinf(b)) return 0.5f;
    if (a >= b) {
        const float r = b / a;
        return 1.0f / (1.0f + r * r);
    }
    const float r = a / b;
    return (r * r) / (1.0f + r * r);
}

glm::vec3 sample_one_light(const Scene& scene, const Bvh& bvh, const SurfacePoint& surface,
                           glm::vec3 n_g, glm::vec3 n_s, std::uint32_t frame, std::uint32_t pixel,
                           std::uint32_t dimension, ShadingStats& stats, const Bsdf* glossy,
                           glm::vec3 v, bool mis) {
    if (scene.lights.empty()) return glm::vec3(0.0f);
    const auto count = static_cast<std::uint32_t>(scene.lights.size());
    // Uniform choice: floor(u N), clamped (u < 1, but u N may round up to N).
    const std::uint32_t l = std::min(
        static_cast<std::uint32_t>(rand_unit(frame, pixel, dimension) * static_cast<float>(count)),
        count - 1u);
    const Light& light = scene.lights[l];
    glm::vec3 y, light_normal;
    float area = 0.0f;
    if (!sample_light_point(light, rand_unit(frame, pixel, dimension + 1),
                            rand_unit(frame, pixel, dimension + 2), y, light_normal, area)) {
        ++stats.light_samples_degenerate;
        return glm::vec3(0.0f);
    }
    const glm::vec3 to_light = y - surface.position;
    const float d2 = glm::dot(to_light, to_light);
    if (!(d2 > min_light_distance2)) {
        ++stats.light_samples_degenerate;
        return glm::vec3(0.0f);
    }
    const float d = std::sqrt(d2);
    const float cos_surface = glm::dot(n_s, to_light) / d;
    float geometry = cos_surface / d2;
    if (light.type != Light::Type::point)
        geometry *= area * (-glm::dot(light_normal, to_light) / d);
    if (!(cos_surface > 0.0f) || !(geometry > 0.0f) || glm::dot(n_g, to_light) <= 0.0f) {
        ++stats.lights_facing_away;
        return glm::vec3(0.0f);
    }
    const glm::vec3 origin = surface.position + n_g * (shadow_epsilon_scale * scene.scene_scale);
    if (!shadow_visible(bvh, origin, y, stats)) return glm::vec3(0.0f);
    // MIS against the BSDF's density for an emissive triangle, which a secondary ray can hit:
    // p_l = d^2 / (N A cos_l), p_b = cos / pi or the glossy BSDF's
    float weight = 1.0f;
    if (mis && light.type == Light::Type::triangle) {
        const float cos_light = -glm::dot(light_normal, to_light) / d;
        const float p_light = d2 / (static_cast<float>(count) * area * cos_light);
        const float p_bsdf = glossy ? bsdf_pdf(*glossy, to_light / d, v) : cos_surface * inv_pi;
        weight = mis_power_weight(p_light, p_bsdf);
    }
    // f Le G / (pdf of the choice 1 / N), the point's pdf 1 / A folded into G.
    if (glossy)
        return bsdf_eval(*glossy, to_light / d, v) * light.intensity *
               (geometry * static_cast<float>(count) * weight);
    return surface.albedo * inv_pi * light.intensity *
           (geometry * static_cast<float>(count) * weight);
}

glm::vec3 pathtrace_pixel(const Scene& scene, const Bvh& bvh, const PathTraceParams& params,
                          const ShadeInputs& in, const Camera& camera, int frame, int x, int y,
                          PathTraceStats& stats, glm::vec3* emission) {
    if (emission) *emission = glm::vec3(0.0f);
    SurfacePoint surface;
    if (!gbuffer_surface(scene, in, x, y, surface, stats.shading)) return glm::vec3(0.0f);
    ++stats.paths;
    const auto f = static_cast<std::uint32_t>(frame);
    const std::uint32_t pixel = shade_pixel_index(in, x, y);
    glm::vec3 incoming = camera.position - surface.position;  // towards where the path came from
    glm::vec3 n_g, n_s;
    facing_normals(surface, incoming, n_g, n_s);
    const Material& first = scene.materials[static_cast<std::size_t>(surface.material)];
    glm::vec3 radiance =
        glm::dot(surface.geometric_normal, incoming) >= 0.0f ? first.emission : glm::vec3(0.0f);
    if (emission) *emission = radiance;
    glm::vec3 throughput(1.0f);
    const float epsilon = shadow_epsilon_scale * scene.scene_scale;
    for (int k = 0;; ++k) {
        const std::uint32_t base = 6u * static_cast<std::uint32_t>(k);
        const Material& material = scene.materials[static_cast<std::size_t>(surface.material)];
        const Bsdf bsdf = make_bsdf(material, surface.albedo, n_s);
        const glm::vec3 v = incoming / std::sqrt(glm::dot(incoming, incoming));
        ++stats.shading.shaded;
        // MIS only where the secondary ray is the competing strategy (not at the last vertex)
        const bool mis = params.mis && k < params.max_bounces;
        radiance +=
            throughput * sample_one_light(scene, bvh, surface, n_g, n_s, f, pixel, base,
                                          stats.shading, bsdf.glossy() ? &bsdf : nullptr, v, mis);
        if (k == params.max_bounces) break;
        const bool black =
            !(surface.albedo.x > 0.0f || surface.albedo.y > 0.0f || surface.albedo.z > 0.0f);
        if (black && !bsdf.glossy()) {
            ++stats.ended_black;
            break;
        }
        if (!bsdf.glossy()) {
            // f cos / pdf = (albedo / pi) cos / (cos / pi) = albedo.
            throughput *= surface.albedo;
        }
        if (k >= 1) {
            if (!(rand_unit(f, pixel, base + 5) < params.rr)) {
                ++stats.ended_roulette;
                break;
            }
            throughput /= params.rr;
        }
        Ray ray;
        ray.origin = surface.position + n_g * epsilon;
        if (!sample_secondary(bsdf, n_s, v, f, pixel, k, ray.direction, throughput) ||
            !(glm::dot(ray.direction, n_g) > 0.0f)) {  // below the geometric surface: absorbed
            ++stats.ended_below;
            break;
        }
        const Hit hit = trace_closest(bvh, ray, stats.secondary);
        if (!hit.hit()) {
            ++stats.ended_background;
            break;
        }
        surface = surface_at(scene, hit.primitive, hit.u, hit.v);
        incoming = -ray.direction;
        if (params.mis) {
            // the density of the direction just sampled (n_s is still the vertex's)
            const float p_bsdf = bsdf.glossy() ? bsdf_pdf(bsdf, ray.direction, v)
                                               : glm::dot(n_s, ray.direction) * inv_pi;
            radiance += throughput * mis_emitter_hit(scene, surface, hit, ray.direction, p_bsdf);
        }
        facing_normals(surface, incoming, n_g, n_s);
    }
    return radiance;
}

Image pathtrace(const Scene& scene, const Bvh& bvh, const PathTraceParams& params,
                const ShadeInputs& in, const Camera& camera, int frame, PathTraceStats& stats,
                Image* emission, const Image* mask) {
    FOVREF_CHECK(!mask || (mask->width == in.position.width && mask->height == in.position.height),
                 "pathtrace: the mask does not match the G-buffer");
    FOVREF_CHECK(params.max_bounces >= 1, "path tracing with no secondary ray");
    FOVREF_CHECK(params.rr > 0.0f && params.rr <= 1.0f, "Russian roulette probability");
    Image out(in.position.width, in.position.height, 3, 0.0f);
    if (emission) *emission = Image(out.width, out.height, 3, 0.0f);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            if (mask && mask->at(x, y) == 0.0f) continue;
            glm::vec3 e;
            const glm::vec3 l = pathtrace_pixel(scene, bvh, params, in, camera, frame, x, y, stats,
                                                emission ? &e : nullptr);
            for (int c = 0; c < 3; ++c) out.at(x, y, c) = l[c];
            if (emission)
                for (int c = 0; c < 3; ++c) emission->at(x, y, c) = e[c];
        }
    return out;
}

std::vector<ParamSpec> path_param_specs() {
    return {{"max_bounces", "1",
             "secondary rays per path: 1 = the sources' four rays per sample (primary, two "
             "shadow rays, one secondary); more with Russian roulette"},
            {"rr", "0.8", "Russian-roulette continuation probability from the second bounce on"},
            {"mis", "off",
             "multiple importance sampling of emissive triangles: 'off' (NEE only, SPEC §8) or "
             "'power' (NEE and the secondary ray, power heuristic, as Koskela P2's path tracer)"}};
}

PathTraceParams parse_path_params(const Params& params, const std::vector<ParamSpec>& specs,
                                  bool rr_needs_bounces) {
    PathTraceParams path;
    path.max_bounces = params.get_int(specs, "max_bounces", 1, 64);
    path.rr = params.get_float(specs, "rr", 0.01f, 1.0f);
    path.mis = params.get_choice(specs, "mis", {"off", "power"}) == 1;
    if (rr_needs_bounces && path.max_bounces == 1 && params.given("rr"))
        throw Error("parameter 'rr' applies from the second bounce on: add max_bounces=2 or more");
    return path;
}

}  // namespace fovref
