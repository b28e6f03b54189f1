// The GGX lobe (ref/trace/ggx.h) against quadrature: D is normalised, the visible-normal sampler
// draws directions with exactly the density ggx_pdf states (a Monte Carlo estimate of the lobe's
// albedo with those samples matches the quadrature of f cos), the albedo never exceeds 1 and is
// close to 1 for a smooth mirror-like lobe, the sampled normals are unit and visible.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "ref/core/rng.h"
#include "ref/trace/ggx.h"

using namespace fovref;

namespace {

constexpr double pi_d = 3.14159265358979323846;

glm::vec3 direction(double theta, double phi) {
    return {static_cast<float>(std::sin(theta) * std::cos(phi)),
            static_cast<float>(std::sin(theta) * std::sin(phi)),
            static_cast<float>(std::cos(theta))};
}

// The albedo of the lobe for v with F0 = 1: the integral of f(l, v) l.z over the hemisphere,
// midpoint rule in (theta, phi).
double albedo_quadrature(glm::vec3 v, float alpha, int n) {
    double sum = 0.0;
    const double dt = 0.5 * pi_d / n, dp = 2.0 * pi_d / n;
    for (int i = 0; i < n; ++i) {
        const double theta = (i + 0.5) * dt;
        for (int j = 0; j < n; ++j) {
            const glm::vec3 l = direction(theta, (j + 0.5) * dp);
            sum += ggx_brdf(l, v, alpha, glm::vec3(1.0f)).x * l.z * std::sin(theta) * dt * dp;
        }
    }
    return sum;
}

}  // namespace

TEST_CASE("GGX: D is normalised: the integral of D(h) h.z over the hemisphere is 1") {
    for (const float alpha : {0.05f, 0.2f, 0.5f, 1.0f}) {
        CAPTURE(alpha);
        const int n = 200000;
        double sum = 0.0;
        const double dt = 0.5 * pi_d / n;
        for (int i = 0; i < n; ++i) {
            const double theta = (i + 0.5) * dt;
            sum += ggx_d(direction(theta, 0.0), alpha) * std::cos(theta) * std::sin(theta) * dt;
        }
        CHECK(2.0 * pi_d * sum == doctest::Approx(1.0).epsilon(2e-3));
    }
}

TEST_CASE("GGX: visible-normal samples have the density ggx_pdf states") {
    // E[f l.z / pdf] over the sampler's directions equals the quadrature of f l.z only if the
    // samples are distributed as ggx_pdf says; with F0 = 1 the weight is G2 / G1 (<= 1).
    for (const float alpha : {0.3f, 0.6f, 1.0f}) {
        for (const double view_deg : {0.0, 30.0, 70.0}) {
            CAPTURE(alpha);
            CAPTURE(view_deg);
            const glm::vec3 v = direction(view_deg * pi_d / 180.0, 0.4);
            const int samples = 200000;
            double sum = 0.0, sum2 = 0.0;
            for (int k = 0; k < samples; ++k) {
                const auto index = static_cast<std::uint32_t>(k);
                const glm::vec3 h = ggx_sample_visible_normal(v, alpha, rand_unit(7, index, 0),
                                                              rand_unit(7, index, 1));
                CHECK(glm::length(h) == doctest::Approx(1.0f).epsilon(1e-5));
                CHECK(glm::dot(h, v) >= -1e-6f);  // visible
                const glm::vec3 l = 2.0f * glm::dot(v, h) * h - v;
                double w = 0.0;
                const float pdf = ggx_pdf(l, v, alpha);
                if (pdf > 0.0f) w = ggx_brdf(l, v, alpha, glm::vec3(1.0f)).x * l.z / pdf;
                sum += w;
                sum2 += w * w;
            }
            const double mean = sum / samples;
            const double se = std::sqrt(std::max(0.0, sum2 / samples - mean * mean) / samples);
            const double quadrature = albedo_quadrature(v, alpha, 800);
            MESSAGE("alpha ", alpha, ", view ", view_deg, " deg: sampled ", mean, " +- ", se,
                    ", quadrature ", quadrature);
            CHECK(std::fabs(mean - quadrature) < 5.0 * se + 2e-3);
            CHECK(quadrature <= 1.0 + 2e-3);  // single scattering loses energy, never gains
        }
    }
}

TEST_CASE("GGX: head-on albedo against an independent binary64 integral, Fresnel at the extremes") {
    // Head-on albedo (F0 = 1), also computed independently in binary64: 0.98830 (alpha 0.1),
    // 0.87736 (0.3), 0.30685 (1: half the normals reflect below the horizon).
    CHECK(albedo_quadrature(glm::vec3(0, 0, 1), 0.1f, 800) ==
          doctest::Approx(0.98830).epsilon(1e-3));
    CHECK(albedo_quadrature(glm::vec3(0, 0, 1), 1.0f, 800) ==
          doctest::Approx(0.30685).epsilon(1e-3));
    CHECK(ggx_fresnel(glm::vec3(0.04f), 1.0f) == glm::vec3(0.04f));
    CHECK(ggx_fresnel(glm::vec3(0.04f), 0.0f) == glm::vec3(1.0f));
    CHECK(ggx_alpha(0.0f) == 1e-3f);
    CHECK(ggx_alpha(0.5f) == 0.25f);
    // Below the surface: nothing.
    CHECK(ggx_brdf(glm::vec3(0, 0, -1), glm::vec3(0, 0, 1), 0.5f, glm::vec3(1)) == glm::vec3(0));
    CHECK(ggx_pdf(glm::vec3(0, 0, 1), glm::vec3(0.6f, 0, -0.8f), 0.5f) == 0.0f);
}
