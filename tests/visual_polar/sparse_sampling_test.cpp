// Sparse screen-space sampling (ref/visual_polar/sparse_sampling.h): push-pull leaves a fully
// sampled image unchanged and fills holes from the available samples; linear fall-off samples
// each pixel with its probability (a frequency test with a binomial bound); acuity sampling's
// eccentricities follow the acuity model's CDF (a Kolmogorov-Smirnov distance).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/visual_polar/map.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/sparse_sampling.h"

using namespace fovref;

TEST_CASE(
    "push_pull: a fully sampled image is unchanged, holes take the average of the samples "
    "around them, no sample gives black") {
    Image image(37, 21, 3), all(37, 21, 1, 1.0f);
    for (std::size_t i = 0; i < image.data.size(); ++i)
        image.data[i] = rand_unit(1u, static_cast<std::uint32_t>(i), 0u);
    CHECK(bit_equal(push_pull(image, all), image));
    // one sample: everything takes its value
    Image one(37, 21, 1, 0.0f);
    one.at(20, 7) = 1.0f;
    const Image filled = push_pull(image, one);
    for (int y = 0; y < 21; ++y)
        for (int x = 0; x < 37; ++x) REQUIRE(filled.at(x, y, 1) == image.at(20, 7, 1));
    // a hole in a 2x2 block takes the average of the block's three samples
    Image holes = all;
    holes.at(4, 6) = 0.0f;
    const Image h = push_pull(image, holes);
    const float expected = (image.at(5, 6, 0) + image.at(4, 7, 0) + image.at(5, 7, 0)) / 3.0f;
    CHECK(h.at(4, 6, 0) == doctest::Approx(expected).epsilon(1e-6));
    CHECK(push_pull(image, Image(37, 21, 1, 0.0f)) == Image(37, 21, 3, 0.0f));
}

TEST_CASE(
    "linear fall-off: 1 inside 10 deg, 0.2 beyond 20 deg, linear between, each pixel is "
    "sampled with that frequency over many frames") {
    const LinearFalloff f;
    CHECK(linear_falloff_probability(f, 0.0f) == 1.0f);
    CHECK(linear_falloff_probability(f, 10.0f) == 1.0f);
    CHECK(linear_falloff_probability(f, 15.0f) == doctest::Approx(0.6f));
    CHECK(linear_falloff_probability(f, 20.0f) == doctest::Approx(0.2f));
    CHECK(linear_falloff_probability(f, 80.0f) == 0.2f);
    const int frames = 4000;
    for (const float p : {0.2f, 0.6f, 0.93f})
        for (std::uint32_t pixel : {0u, 12345u, 999999u}) {
            int hits = 0;
            for (int frame = 0; frame < frames; ++frame)
                hits += linear_falloff_sampled(static_cast<std::uint32_t>(frame), pixel, p) ? 1 : 0;
            const double rate = static_cast<double>(hits) / frames;
            const double sd = std::sqrt(p * (1.0 - p) / frames);
            CAPTURE(p);
            CAPTURE(pixel);
            CHECK(std::fabs(rate - p) < 5.0 * sd);  // binomial: 5 standard deviations
        }
}

TEST_CASE("acuity sampling: the eccentricities follow the acuity model's CDF") {
    // The model's CDF over eccentricity: F(e) = int_0^e m(t) t dt / int_0^E m(t) t dt (samples
    // per area proportional to m), E = P(1); by the midpoint rule.
    const double e_max = vp_inverse_cdf(1.0f);
    const int steps = 20000;
    std::vector<double> cdf(steps + 1, 0.0);
    for (int k = 0; k < steps; ++k) {
        const double t = (k + 0.5) * e_max / steps;
        cdf[k + 1] = cdf[k] + vp_acuity(static_cast<float>(t)) * t;
    }
    for (double& v : cdf) v /= cdf[steps];
    const auto model = [&](double e) {
        const double x = std::clamp(e / e_max * steps, 0.0, static_cast<double>(steps));
        const int k = std::min(static_cast<int>(x), steps - 1);
        return cdf[k] + (cdf[k + 1] - cdf[k]) * (x - k);
    };
    const int n = 100000;
    std::vector<double> e(n);
    for (int k = 0; k < n; ++k) {
        // the linear model with 1 pixel per degree: the distance is e itself
        const glm::vec2 p = acuity_sample(3u, static_cast<std::uint32_t>(k), {0.0f, 0.0f},
                                          EccentricityModel{false, 180.0f / 3.14159265f});
        e[static_cast<std::size_t>(k)] = std::sqrt(static_cast<double>(p.x) * p.x + p.y * p.y);
    }
    std::sort(e.begin(), e.end());
    double d = 0.0;
    for (int k = 0; k < n; ++k) {
        const double f = model(e[static_cast<std::size_t>(k)]);
        d = std::max({d, std::fabs(f - static_cast<double>(k) / n),
                      std::fabs(f - static_cast<double>(k + 1) / n)});
    }
    MESSAGE("KS distance to the model's CDF: " << d << " (n = " << n << ")");
    // the KS critical value at 99.9% is 1.95 / sqrt(n) = 0.0062, plus up to 0.004 for the fit's own
    // deviation from the model (P is a polynomial fit of the model's inverse CDF)
    CHECK(d < 0.0062 + 0.004);
}

TEST_CASE(
    "sparse sampling: one eccentricity model for linear fall-off and acuity sampling, exact "
    "by default, linear on request") {
    // d_px = 1000: 30 degrees is 1000 tan(30) = 577.35 px exactly (the display model), and
    // 30 * 1000 pi / 180 = 523.60 px with the linear pixels-per-degree scale
    const EccentricityModel exact{true, 1000.0f}, linear{false, 1000.0f};
    CHECK(SparseParams{}.exact_eccentricity);
    CHECK(exact.radius(30.0f) == doctest::Approx(577.350269).epsilon(1e-6));
    CHECK(linear.radius(30.0f) == doctest::Approx(523.598776).epsilon(1e-6));
    CHECK(exact.degrees(577.350269f) == doctest::Approx(30.0).epsilon(1e-5));
    CHECK(linear.degrees(523.598776f) == doctest::Approx(30.0).epsilon(1e-6));
    CHECK(std::isinf(exact.radius(90.0f)));  // beyond the display: off every screen
    // the fall-off uses the same model: a pixel 550 px from the gaze is at 28.8 degrees exactly
    // (sampled with P_p beyond p_l = 20) but 31.5 linearly; at 300 px, 16.7 against 17.2
    LinearFalloff f;
    const float e_exact = exact.degrees(300.0f), e_linear = linear.degrees(300.0f);
    CHECK(e_exact == doctest::Approx(16.6992).epsilon(1e-4));
    CHECK(e_linear == doctest::Approx(17.1887).epsilon(1e-4));
    CHECK(linear_falloff_probability(f, e_exact) > linear_falloff_probability(f, e_linear));
    // the modes take the parameter
    Params p;
    CHECK(parse_sparse_params(p, "acuity").exact_eccentricity);
    p.set("eccentricity", "linear");
    CHECK_FALSE(parse_sparse_params(p, "linear-falloff").exact_eccentricity);
    p.set("eccentricity", "degrees");
    CHECK_THROWS_AS(parse_sparse_params(p, "acuity"), Error);
}
