// Error ranges (SPEC §10, Lund §3.6): rings partition the covered pixels exactly, ring statistics
// agree with the whole-image ones, and heatmaps show the scale, legend and ring boundaries.
#include <doctest/doctest.h>

#include <cmath>
#include <limits>

#include "ref/core/error.h"
#include "ref/metrics/heatmap.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/rings.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

TEST_CASE("rings: half-open bounds, each pixel in exactly one ring") {
    const float w = 1.5f;
    CHECK(ring_of(0.0f, w, 4) == 0);
    CHECK(ring_of(1.5f, w, 4) == 1);  // the lower bound belongs to the ring
    CHECK(ring_of(std::nextafter(1.5f, 0.0f), w, 4) == 0);
    CHECK(ring_of(std::nextafter(6.0f, 0.0f), w, 4) == 3);
    CHECK(ring_of(6.0f, w, 4) == -1);  // e >= E: outside
    CHECK(ring_of(std::numeric_limits<float>::quiet_NaN(), w, 4) == -1);

    for (const auto& [gx, gy, range] :
         {std::tuple{80.0f, 45.0f, 1.0f}, {10.0f, 70.0f, 1.0f}, {80.0f, 45.0f, 0.5f}}) {
        RingSettings settings;
        settings.max_range = range;
        const RingLayout layout = ring_layout(160, 90, {gx, gy}, 120.0f, settings);
        std::int64_t covered = 0;
        for (int y = 0; y < 90; ++y)
            for (int x = 0; x < 160; ++x) {
                const int k = layout.ring[static_cast<std::size_t>(y * 160 + x)];
                const float e = eccentricity_deg(
                    {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f}, {gx, gy}, 120.0f);
                if (k < 0) {
                    CHECK(e >= layout.outer(19));
                    continue;
                }
                ++covered;
                // The ring's bounds, with the same binary32 products ring_of uses.
                CHECK(layout.inner(k) <= e);
                CHECK(e < layout.outer(k));
            }
        if (range == 1.0f) CHECK(covered == 160 * 90);  // the farthest corner bounds every centre
        if (range == 0.5f) CHECK(covered < 160 * 90);
    }
}

TEST_CASE("rings: statistics agree with the whole image") {
    test::SplitMix64 rng(4);
    Image a(64, 48, 3), b(64, 48, 3);
    for (std::size_t i = 0; i < a.data.size(); ++i) {
        a.data[i] = rng.unit();
        b.data[i] = a.data[i] + 0.2f * (rng.unit() - 0.5f);
    }
    const RingLayout layout = ring_layout(64, 48, {32.0f, 24.0f}, 50.0f);
    const SsimMap map = ssim_map(luma(a), luma(b));
    const auto rings = ring_errors(a, b, layout, &map);
    REQUIRE(rings.size() == 20);
    double weighted_mse = 0, weighted_ssim = 0;
    std::int64_t pixels = 0, ssim_pixels = 0;
    for (const RingStats& r : rings) {
        pixels += r.pixels;
        ssim_pixels += r.ssim_pixels;
        if (r.pixels) weighted_mse += r.mse * static_cast<double>(r.pixels);
        if (r.ssim_pixels) weighted_ssim += r.ssim * static_cast<double>(r.ssim_pixels);
        if (r.pixels) CHECK(r.rmse == std::sqrt(r.mse));
        if (r.pixels) CHECK(r.psnr == psnr(r.mse));
    }
    CHECK(pixels == 64 * 48);
    CHECK(ssim_pixels == 54 * 38);  // every pixel of the valid region is in some ring
    CHECK(weighted_mse / static_cast<double>(pixels) == doctest::Approx(mse(a, b)).epsilon(1e-12));
    CHECK(weighted_ssim / static_cast<double>(ssim_pixels) ==
          doctest::Approx(map.mean).epsilon(1e-12));

    // A constant error: every ring has MSE = delta^2 and SD 0.
    const Image c(64, 48, 3, 0.5f), d(64, 48, 3, 0.75f);
    for (const RingStats& r : ring_errors(c, d, layout, nullptr)) {
        if (!r.pixels) continue;
        CHECK(r.mse == 0.0625);
        CHECK(r.sd == 0.0);
        CHECK(std::isnan(r.ssim));  // no SSIM map given
    }
}

TEST_CASE("rings: bad settings are errors naming the setting") {
    using test::contains;
    using test::error_message;
    RingSettings s;
    s.count = 0;
    CHECK(contains(error_message([&] { ring_layout(8, 8, {4, 4}, 10, s); }), "number of rings"));
    s = {};
    s.max_range = 1.5f;
    CHECK(contains(error_message([&] { ring_layout(8, 8, {4, 4}, 10, s); }), "max_range"));
    CHECK(contains(error_message([] { ring_layout(8, 8, {4, 4}, 0.0f); }), "viewing distance"));
    CHECK(contains(error_message([] {
                       ring_layout(8, 8, {std::numeric_limits<float>::infinity(), 4}, 10.0f);
                   }),
                   "gaze"));
}

TEST_CASE("heatmap: colour scale, legend, ring overlay, non-finite values") {
    Image values(40, 30, 1, 0.0f);
    values.at(3, 4) = 2.0f;
    values.at(5, 5) = 1.0f;
    values.at(6, 6) = std::numeric_limits<float>::quiet_NaN();
    HeatmapSettings settings;
    settings.legend = false;
    const Image map = heatmap(values, settings);
    REQUIRE(map.width == 40);
    const glm::vec3 bottom = heatmap_colour(0.0f), top = heatmap_colour(1.0f);
    CHECK(map.at(0, 0, 0) == bottom.r);
    CHECK(map.at(3, 4, 0) == top.r);  // the largest value is the top of the scale
    CHECK(map.at(3, 4, 2) == top.b);
    // The map uses the nearest of 4096 table entries: 0.5 -> entry round(0.5 * 4095) = 2048.
    const glm::vec3 middle = heatmap_colour(2048.0f / 4095.0f);
    CHECK(map.at(5, 5, 1) == middle.g);
    CHECK(map.at(6, 6, 0) == 1.0f);  // NaN: magenta
    CHECK(map.at(6, 6, 1) == 0.0f);
    // The colour table is monotonic in lightness (perceptually uniform maps are).
    float previous = -1.0f;
    for (int i = 0; i <= 64; ++i) {
        const glm::vec3 c = heatmap_colour(static_cast<float>(i) / 64.0f);
        const float y = 0.2126f * c.r + 0.7152f * c.g + 0.0722f * c.b;
        CHECK(y > previous);
        previous = y;
    }
    // A fixed scale clamps larger values to the top colour.
    settings.scale_max = 0.5f;
    CHECK(heatmap(values, settings).at(5, 5, 0) == top.r);
    // The legend adds a panel with the colour bar.
    settings.legend = true;
    const Image with_legend = heatmap(values, settings);
    CHECK(with_legend.width > 40);
    CHECK(with_legend.at(44, 0, 0) == top.r);  // bar top = the scale's top
    // Ring boundaries are blended 25% white over the colour: 0.75 c + 0.25.
    const RingLayout rings = ring_layout(40, 30, {20, 15}, 30.0f);
    settings.legend = false;
    settings.rings = &rings;
    const Image ringed = heatmap(Image(40, 30, 1, 0.0f), settings);
    int white = 0;
    const float blended = 0.75f * bottom.r + 0.25f;
    for (int x = 0; x < 40; ++x) white += ringed.at(x, 15, 0) == blended;
    CHECK(white >= 2 * 5);  // a horizontal line through the gaze crosses each ring twice
}

TEST_CASE("id_mismatch_image: rings that survive downscaling, interior on top of edge") {
    Image background(256, 128, 3, 1.0f), map(256, 128, 1, 0.0f);
    map.at(40, 40) = 1.0f;   // edge mismatch
    map.at(200, 64) = 2.0f;  // interior mismatch
    map.at(203, 64) = 1.0f;  // an edge one close by: the interior ring is drawn over it
    const Image out = id_mismatch_image(background, map);
    auto rgb = [&](int x, int y) {
        return glm::vec3(out.at(x, y, 0), out.at(x, y, 1), out.at(x, y, 2));
    };
    const int radius = 256 / 64;  // 4, ring thickness 1
    CHECK(rgb(40, 40) == edge_marker_colour);
    CHECK(rgb(40 + radius, 40) == edge_marker_colour);
    CHECK(rgb(40 - radius, 40 - radius) == edge_marker_colour);
    CHECK(rgb(41, 40) != edge_marker_colour);  // inside the ring: background
    CHECK(rgb(200 + radius, 64) == interior_marker_colour);
    CHECK(rgb(203, 64) == edge_marker_colour);  // not covered by the interior ring
    CHECK(rgb(196, 64) == interior_marker_colour);
    // The background is dimmed to grey: clearly darker than the markers' channels.
    CHECK(rgb(10, 100).x < 0.6f);
    CHECK(rgb(10, 100).x == rgb(10, 100).y);
    CHECK(fovref::test::contains(
        fovref::test::error_message([&] { id_mismatch_image(background, Image(8, 8, 1)); }),
        "same size"));
}

// ring_means (per-ring FLIP in evaluate and sweeps): a constant map gives the constant in every
// ring; the pixel-weighted mean of the ring means is the mean over the covered pixels, recounted
// here pixel by pixel from the layout; a ring without pixels is NaN; a wrong shape is an error.
TEST_CASE("rings: per-ring means of a map") {
    const RingLayout layout = ring_layout(64, 36, {20.0f, 18.0f}, 60.0f);
    const RingLayout sparse = ring_layout(8, 6, {4.0f, 3.0f}, 100.0f, RingSettings{200, 1.0f});
    for (double m : ring_means(Image(64, 36, 1, 0.25f), layout)) CHECK(m == 0.25);
    Image map(64, 36, 1);
    for (std::size_t i = 0; i < map.data.size(); ++i)
        map.data[i] = static_cast<float>((i * 7919) % 1000) / 1000.0f;
    const std::vector<double> means = ring_means(map, layout);
    std::vector<double> count(means.size(), 0.0);
    double total = 0.0, covered = 0.0;
    for (std::size_t p = 0; p < map.data.size(); ++p)
        if (layout.ring[p] >= 0) {
            count[static_cast<std::size_t>(layout.ring[p])] += 1.0;
            total += map.data[p];
            covered += 1.0;
        }
    double weighted = 0.0;
    for (std::size_t k = 0; k < means.size(); ++k)
        if (count[k] > 0) weighted += means[k] * count[k];
    CHECK(std::fabs(weighted / covered - total / covered) < 1e-12);
    bool some_empty = false;
    const std::vector<double> sparse_means = ring_means(Image(8, 6, 1, 1.0f), sparse);
    for (std::size_t k = 0; k < sparse_means.size(); ++k)
        some_empty = some_empty || std::isnan(sparse_means[k]);
    CHECK(some_empty);  // 200 rings over 48 pixels
    CHECK_THROWS_AS(ring_means(Image(64, 36, 3, 0.0f), layout), Error);
    CHECK_THROWS_AS(ring_means(Image(32, 36, 1, 0.0f), layout), Error);
}
