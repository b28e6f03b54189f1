// The converged reference (ref/trace/pathtrace_reference.h): a run resumed from its written sums
// gives the same bits as one run; its standard error is the sample formula; it converges to the
// mean of many 1-spp pathtrace frames (the same estimator) within the stated statistical bound.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "ref/core/rng.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "ref/trace/pathtrace.h"
#include "ref/trace/pathtrace_reference.h"

using namespace fovref;

namespace {

std::vector<FrameResult> reference(const Scene& scene, int spp, std::vector<Buffer> resume = {}) {
    RenderSettings s;
    s.width = 24;
    s.height = 16;
    s.params.set("spp", std::to_string(spp));
    s.state_buffers = std::move(resume);
    return render(&scene, "pathtrace-reference", s);
}

}  // namespace

TEST_CASE("pathtrace-reference: resuming from the written sums gives the bits of one run") {
    const Scene scene = make_procedural_scene("cornell");
    const std::vector<FrameResult> part = reference(scene, 5);
    const std::vector<FrameResult> rest = reference(scene, 12, part[0].buffers);
    const std::vector<FrameResult> whole = reference(scene, 12);
    for (const char* name : {"final", "standard_error", "reference_sum", "reference_compensation",
                             "reference_squares", "reference_count"}) {
        CAPTURE(name);
        CHECK(bit_equal(rest[0].find(name)->image, whole[0].find(name)->image));
    }
    CHECK(rest[0].counters.get("reference_samples_resumed") == 5);
    CHECK(whole[0].find("reference_count")->image.data[0] == 12.0f);
    CHECK_THROWS_WITH_AS(reference(scene, 4, part[0].buffers),
                         doctest::Contains("already holds 5 samples"), Error);
}

TEST_CASE("reference_estimate: the mean and the standard error of the mean") {
    PathReferenceSums sums = empty_reference_sums(1, 1);
    const float samples[4] = {1.0f, 2.0f, 4.0f, 5.0f};  // mean 3, population variance 2.5
    for (float v : samples)
        for (int c = 0; c < 3; ++c) {
            sums.sum.data[static_cast<std::size_t>(c)] += v;
            sums.squares.data[static_cast<std::size_t>(c)] += v * v;
        }
    sums.count = 4;
    Image mean, error;
    reference_estimate(sums, mean, error);
    CHECK(mean.data[0] == 3.0f);
    // sqrt(2.5 / 3): the population variance over n - 1
    CHECK(error.data[0] == doctest::Approx(std::sqrt(2.5 / 3.0)).epsilon(1e-6));
}

TEST_CASE("pathtrace-reference converges to the mean of 1-spp pathtrace frames") {
    // The jittered reference averages over each pixel's area, pathtrace samples its centre:
    // compare the image means (the area average of the whole image), within 5 standard errors.
    const Scene scene = make_procedural_scene("cornell");
    const std::vector<FrameResult> ref = reference(scene, 256);
    double ref_mean = 0.0, ref_var = 0.0;
    const Image& m = ref[0].find("final")->image;
    const Image& se = ref[0].find("standard_error")->image;
    for (std::size_t i = 0; i < m.data.size(); ++i) {
        ref_mean += m.data[i];
        ref_var += static_cast<double>(se.data[i]) * se.data[i];
    }
    const double n = static_cast<double>(m.data.size());
    ref_mean /= n;
    RenderSettings s;
    s.width = 24;
    s.height = 16;
    s.frame_count = 256;
    s.time_step = 0.0f;
    double sum = 0.0, sum2 = 0.0;
    for (const FrameResult& f : render(&scene, "pathtrace", s)) {
        double frame_mean = 0.0;
        for (float v : f.find("final")->image.data) frame_mean += v;
        frame_mean /= n;
        sum += frame_mean;
        sum2 += frame_mean * frame_mean;
    }
    const double mean = sum / 256.0;
    const double se_frames = std::sqrt(std::max(0.0, sum2 / 256.0 - mean * mean) / 255.0);
    const double bound = 5.0 * std::sqrt(se_frames * se_frames + ref_var / (n * n)) +
                         0.02 * ref_mean;  // + 2% for centre vs area sampling at the edges
    MESSAGE("image mean: reference " << ref_mean << ", 1-spp frames " << mean << " +- "
                                     << se_frames);
    CHECK(std::fabs(mean - ref_mean) < bound);
}

TEST_CASE(
    "pathtrace-reference jitter: per-pixel rotations make an edge's region mean converge "
    "at its standard error's rate, the shared jitter does not") {
    // A vertical edge at 0.3 of every pixel of a column of M pixels: a sample covers the pixel
    // when its jitter x < 0.3. The coverage estimate of one pixel from N samples has the standard
    // error sqrt(0.3 * 0.7 / N); the mean over the M pixels, with independent pixels,
    // sqrt(0.3 * 0.7 / (N M)).
    const int n = 64, m = 1024;
    const double single = std::sqrt(0.3 * 0.7 / n), region = std::sqrt(0.3 * 0.7 / (n * m));
    for (const ReferenceJitter mode : {ReferenceJitter::per_pixel, ReferenceJitter::shared}) {
        double sum = 0.0;
        std::vector<double> pixel_estimates;
        for (int p = 0; p < m; ++p) {
            int covered = 0;
            for (int s = 0; s < n; ++s) {
                const Offset2 j = reference_jitter(s, p * 37, mode);
                REQUIRE((j.x >= 0.0f && j.x < 1.0f && j.y >= 0.0f && j.y < 1.0f));
                covered += j.x < 0.3f ? 1 : 0;
            }
            pixel_estimates.push_back(static_cast<double>(covered) / n);
            sum += pixel_estimates.back();
        }
        const double error = std::fabs(sum / m - 0.3);
        if (mode == ReferenceJitter::per_pixel) {
            CHECK(error < 4.0 * region);  // within 4 standard errors of the region mean
            // and the pixels' estimates do differ (their spread is about the single error)
            double spread = 0.0;
            for (const double e : pixel_estimates) spread += (e - sum / m) * (e - sum / m);
            CHECK(std::sqrt(spread / m) > 0.5 * single);
        } else {
            // every pixel makes the same error: the region mean is one pixel's estimate
            for (const double e : pixel_estimates) REQUIRE(e == pixel_estimates.front());
            CHECK(error == std::fabs(pixel_estimates.front() - 0.3));
        }
    }
    // per-pixel is the shared sequence rotated: the same points in pixel 0's frame of reference
    // differ by the pixel's offset, modulo 1
    const Offset2 a = reference_jitter(5, 12, ReferenceJitter::per_pixel);
    const Offset2 b = reference_jitter(5, 12, ReferenceJitter::shared);
    const float r = rand_unit(0xfffffffeu, 12u, 0u);
    CHECK(a.x == (b.x + r >= 1.0f ? b.x + r - 1.0f : b.x + r));
}

TEST_CASE(
    "MIS (mis=power): the power heuristic, the same expectation as NEE alone, less noise "
    "on a glossy floor, and no change without emissive triangles") {
    CHECK(mis_power_weight(1.0f, 1.0f) == 0.5f);
    CHECK(mis_power_weight(3.0f, 1.0f) == doctest::Approx(0.9f).epsilon(1e-6));
    CHECK(mis_power_weight(1.0f, 3.0f) == doctest::Approx(0.1f).epsilon(1e-6));
    CHECK(mis_power_weight(0.0f, 2.0f) == 0.0f);
    CHECK(mis_power_weight(0.0f, 0.0f) == 1.0f);
    // no overflow: a light density of 1e30 against a BSDF's 0.3, and the complement
    CHECK(mis_power_weight(1e30f, 0.3f) == 1.0f);
    CHECK(mis_power_weight(0.3f, 1e30f) == 0.0f);
    CHECK(mis_power_weight(1e-30f, 1e-30f) == 0.5f);
    // glossy-floor: two emissive triangles and a point light, seen in the glossy floor
    const Scene glossy = make_procedural_scene("glossy-floor");
    const auto render_mis = [](const Scene& scene, const char* mis, int spp, const char* mode) {
        RenderSettings s;
        s.width = 32;
        s.height = 18;
        s.requested = {"all"};
        s.params.set("mis", mis);
        s.params.set("max_bounces", "2");
        if (std::string(mode) == "pathtrace-reference") s.params.set("spp", std::to_string(spp));
        return render(&scene, mode, s).at(0);
    };
    const FrameResult off = render_mis(glossy, "off", 512, "pathtrace-reference");
    const FrameResult power = render_mis(glossy, "power", 512, "pathtrace-reference");
    const Image& a = off.find("final")->image;
    const Image& b = power.find("final")->image;
    const Image& sa = off.find("standard_error")->image;
    const Image& sb = power.find("standard_error")->image;
    double mean_a = 0.0, mean_b = 0.0, var_a = 0.0, var_b = 0.0, se_a = 0.0, se_b = 0.0;
    const auto n = static_cast<double>(a.data.size());
    for (std::size_t k = 0; k < a.data.size(); ++k) {
        mean_a += a.data[k] / n;
        mean_b += b.data[k] / n;
        var_a += static_cast<double>(sa.data[k]) * sa.data[k] / (n * n);
        var_b += static_cast<double>(sb.data[k]) * sb.data[k] / (n * n);
        se_a += sa.data[k] / n;
        se_b += sb.data[k] / n;
    }
    const double z = (mean_a - mean_b) / std::sqrt(var_a + var_b);
    MESSAGE("image mean: NEE " << mean_a << ", MIS " << mean_b << " (z = " << z
                               << "); mean standard error per pixel " << se_a << " -> " << se_b);
    CHECK(std::fabs(z) < 4.0);
    CHECK(se_b < 0.9 * se_a);
    // Without emissive triangles (checker-room: a point and a quad light) nothing changes
    const Scene room = make_procedural_scene("checker-room");
    for (const char* mode : {"pathtrace", "pathtrace-reference"}) {
        CAPTURE(mode);
        const Image x = render_mis(room, "off", 4, mode).find("final")->image;
        const Image y = render_mis(room, "power", 4, mode).find("final")->image;
        CHECK(std::memcmp(x.data.data(), y.data.data(), x.data.size() * sizeof(float)) == 0);
    }
    CHECK_THROWS_WITH_AS(
        [] {
            RenderSettings s;
            s.width = 8;
            s.height = 8;
            s.params.set("mis", "balance");
            const Scene scene = make_procedural_scene("cornell");
            render(&scene, "pathtrace", s);
        }(),
        doctest::Contains("parameter 'mis'"), Error);
}
