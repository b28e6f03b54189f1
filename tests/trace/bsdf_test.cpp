// The path tracer's BSDF (ref/trace/bsdf.h): the sampled weight f cos / pdf has the expectation
// of the quadrature of f cos over the hemisphere (the directional albedo) and of f cos g for a
// test function g, which holds only if the lobe mixture's density is the one the weight divides
// by; a diffuse material samples exactly as cosine_direction with the weight albedo.
#include <doctest/doctest.h>

#include <cmath>
#include <initializer_list>

#include "ref/core/rng.h"
#include "ref/trace/bsdf.h"
#include "ref/trace/pathtrace.h"

using namespace fovref;

namespace {

constexpr double pi = 3.14159265358979323846;

// The integral of f(l, v) cos g(l) over the hemisphere of b.n, midpoint rule in (theta, phi).
template <class G>
glm::dvec3 quadrature(const Bsdf& b, glm::vec3 v, G g, int n) {
    glm::dvec3 sum(0.0);
    const double dt = 0.5 * pi / n, dp = 2.0 * pi / n;
    for (int i = 0; i < n; ++i) {
        const double theta = (i + 0.5) * dt;
        for (int j = 0; j < n; ++j) {
            const double phi = (j + 0.5) * dp;
            const glm::vec3 l = b.t * static_cast<float>(std::sin(theta) * std::cos(phi)) +
                                b.s * static_cast<float>(std::sin(theta) * std::sin(phi)) +
                                b.n * static_cast<float>(std::cos(theta));
            sum += glm::dvec3(bsdf_eval(b, l, v)) * (std::cos(theta) * std::sin(theta) * dt * dp) *
                   g(l);
        }
    }
    return sum;
}

}  // namespace

TEST_CASE("bsdf_sample: E[f cos / pdf] = the quadrature of f cos (glossy lobe mixtures)") {
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, 1.0f, -0.2f));
    for (const float roughness : {0.3f, 0.6f, 1.0f})
        for (const float view_deg : {10.0f, 45.0f, 75.0f}) {
            Material m;
            m.albedo = glm::vec3(0.4f, 0.2f, 0.1f);
            m.specular = glm::vec3(0.6f, 0.5f, 0.4f);
            m.roughness = roughness;
            const Bsdf b = make_bsdf(m, m.albedo, n);
            REQUIRE(b.glossy());
            const float a = view_deg * 0.0174532925f;
            const glm::vec3 v = b.n * std::cos(a) + b.t * std::sin(a);
            const auto weight_g = [&](glm::vec3 l) { return 0.5 + l.x * l.x; };
            const glm::dvec3 albedo = quadrature(
                b, v, [](glm::vec3) { return 1.0; }, 400);
            const glm::dvec3 moment = quadrature(b, v, weight_g, 400);
            double sum = 0, sum2 = 0, gsum = 0, gsum2 = 0;
            const int count = 200000;
            for (int i = 0; i < count; ++i) {
                const auto u = static_cast<std::uint32_t>(i);
                glm::vec3 l, w;
                double x = 0.0, gx = 0.0;
                if (bsdf_sample(b, v, rand_unit(7, u, 0), rand_unit(7, u, 1), rand_unit(7, u, 2), l,
                                w)) {
                    x = w.x;
                    gx = w.x * weight_g(l);
                }
                sum += x;
                sum2 += x * x;
                gsum += gx;
                gsum2 += gx * gx;
            }
            const double mean = sum / count, gmean = gsum / count;
            const double se = std::sqrt((sum2 / count - mean * mean) / count);
            const double gse = std::sqrt((gsum2 / count - gmean * gmean) / count);
            CAPTURE(roughness);
            CAPTURE(view_deg);
            MESSAGE("albedo (red) " << mean << " +- " << se << ", quadrature " << albedo.x);
            CHECK(std::fabs(mean - albedo.x) < 5.0 * se + 2e-3);
            CHECK(std::fabs(gmean - moment.x) < 5.0 * gse + 2e-3);
        }
}

TEST_CASE("bsdf_sample: a diffuse material samples cosine_direction with the weight albedo") {
    Material m;
    m.albedo = glm::vec3(0.5f, 0.25f, 0.125f);
    const glm::vec3 n = glm::normalize(glm::vec3(-1.0f, 0.5f, 2.0f));
    const Bsdf b = make_bsdf(m, m.albedo, n);
    CHECK_FALSE(b.glossy());
    for (const float u : {0.1f, 0.5f, 0.9f}) {
        glm::vec3 l, w;
        REQUIRE(bsdf_sample(b, n, 0.3f, u, 1.0f - u, l, w));
        CHECK(l == cosine_direction(n, u, 1.0f - u));
        CHECK(w == m.albedo);
    }
}
