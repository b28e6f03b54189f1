// Metrics (SPEC §10): MSE/RMSE/PSNR by hand, SSIM on analytic cases, against a brute-force
// 2-D window and against a value computed by scikit-image, the display transform, temporal error.
#include <doctest/doctest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "ref/metrics/metrics.h"
#include "ref/metrics/ssim.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

Image constant(int w, int h, int c, float v) { return Image(w, h, c, v); }

Image random_image(int w, int h, int c, std::uint64_t seed) {
    test::SplitMix64 rng(seed);
    Image image(w, h, c);
    for (float& v : image.data) v = rng.unit();
    return image;
}

// Brute-force SSIM at one valid pixel: direct 11x11 sums with 2-D weights w(i) w(j), as in
// Wang et al.'s ssim_index.m (filter2 'valid'), independent of the separable implementation.
double brute_force_ssim(const Image& a, const Image& b, int cx, int cy, int r = 5) {
    double g[64], total = 0;
    for (int k = -r; k <= r; ++k) total += g[k + r] = std::exp(-(k * k) / (2 * 1.5 * 1.5));
    double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
    for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i) {
            const double w = g[i + r] / total * (g[j + r] / total);
            const double va = a.at(cx + i, cy + j), vb = b.at(cx + i, cy + j);
            ma += w * va;
            mb += w * vb;
            saa += w * va * va;
            sbb += w * vb * vb;
            sab += w * va * vb;
        }
    saa -= ma * ma;
    sbb -= mb * mb;
    sab -= ma * mb;
    const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
    return (2 * ma * mb + c1) * (2 * sab + c2) / ((ma * ma + mb * mb + c1) * (saa + sbb + c2));
}

}  // namespace

TEST_CASE("mse/psnr: identical images give 0 and +inf") {
    const Image a = random_image(17, 9, 3, 1);
    CHECK(mse(a, a) == 0.0);
    CHECK(std::isinf(psnr(mse(a, a))));
    CHECK(psnr(0.0) > 0.0);
}

TEST_CASE("mse/psnr: constant offset by hand") {
    // 0.25 vs 0.5 on every channel: MSE = 0.0625, RMSE = 0.25, PSNR = 10 log10(16) = 12.0412 dB.
    const Image a = constant(8, 4, 3, 0.25f), b = constant(8, 4, 3, 0.5f);
    CHECK(mse(a, b) == 0.0625);
    CHECK(std::sqrt(mse(a, b)) == 0.25);
    CHECK(psnr(mse(a, b)) == doctest::Approx(12.041199826559248).epsilon(1e-14));
    // PSNR with another data range: 10 log10(4 / 0.0625) = 18.0618 dB.
    CHECK(psnr(0.0625, 2.0) == doctest::Approx(18.061799739838872).epsilon(1e-14));
    // One pixel of 4 differs by 1 in one of 3 channels: MSE = 1/12.
    Image c = constant(2, 2, 3, 0.0f), d = c;
    d.at(1, 1, 2) = 1.0f;
    CHECK(mse(c, d) == doctest::Approx(1.0 / 12.0).epsilon(1e-15));
}

TEST_CASE("mse: known noise level") {
    // +-delta with random signs: every squared error is delta^2 (0.125 is exact in binary32).
    test::SplitMix64 rng(7);
    Image a = random_image(64, 64, 3, 3), b = a;
    for (float& v : b.data) v += (rng.next() & 1) ? 0.125f : -0.125f;
    CHECK(mse(a, b) == doctest::Approx(0.015625).epsilon(1e-6));  // float rounding of a + delta
    // Uniform noise on [-h, h): variance h^2 / 3. 12288 samples: the sample variance's relative
    // standard error is ~sqrt(0.8 / 12288) = 0.8%; allow 4%.
    Image n = a;
    const float h = 0.1f;
    for (float& v : n.data) v += (2.0f * rng.unit() - 1.0f) * h;
    CHECK(mse(a, n) == doctest::Approx(0.01 / 3.0).epsilon(0.04));
}

TEST_CASE("ssim: identical images give exactly 1, constant images need no division by zero") {
    const Image a = luma(random_image(32, 24, 3, 11));
    const SsimMap map = ssim_map(a, a);
    CHECK(map.width == 22);
    CHECK(map.height == 14);
    CHECK(map.mean == 1.0);
    // Constant images: zero variances, SSIM = (2ab + C1) / (a^2 + b^2 + C1) (luminance term).
    for (const auto& [va, vb] : {std::pair{0.0f, 0.0f}, {0.0f, 1.0f}, {0.3f, 0.6f}}) {
        const SsimMap m = ssim_map(constant(16, 16, 1, va), constant(16, 16, 1, vb));
        const double x = va, y = vb, c1 = 1e-4;
        CHECK(std::isfinite(m.mean));
        CHECK(m.mean == doctest::Approx((2 * x * y + c1) / (x * x + y * y + c1)).epsilon(1e-12));
    }
}

TEST_CASE("ssim: separable filter equals the brute-force 2-D window") {
    const Image a = random_image(30, 21, 1, 21);
    Image b = a;
    test::SplitMix64 rng(5);
    for (float& v : b.data) v = v * 0.8f + 0.2f * rng.unit();
    const SsimMap map = ssim_map(a, b);
    double worst = 0;
    for (int y = 5; y < 16; ++y)
        for (int x = 5; x < 25; ++x)
            worst = std::max(worst, std::fabs(map.at_image(x, y) - brute_force_ssim(a, b, x, y)));
    MESSAGE("largest |separable - brute force| = " << worst);
    CHECK(worst < 1e-12);  // both binary64; only the summation order differs
    // Another radius takes the general (not unrolled) filter path.
    SsimSettings small;
    small.radius = 3;
    const SsimMap map3 = ssim_map(a, b, small);
    CHECK(map3.width == 24);
    worst = 0;
    for (int y = 3; y < 18; ++y)
        for (int x = 3; x < 27; ++x)
            worst =
                std::max(worst, std::fabs(map3.at_image(x, y) - brute_force_ssim(a, b, x, y, 3)));
    CHECK(worst < 1e-12);
}

TEST_CASE("ssim: the AVX and SSE2 filter kernels give the same bits") {
    // Widths with every remainder mod 4 and a map wider than one 512-column strip. Where the
    // CPU lacks AVX both runs take the SSE2 kernel and the test still checks determinism.
    for (const int w : {11, 12, 13, 14, 15, 16, 17, 530, 531}) {
        const Image a = random_image(w, 13, 1, static_cast<std::uint64_t>(w));
        const Image b = random_image(w, 13, 1, static_cast<std::uint64_t>(w) + 100);
        SsimSettings sse;
        sse.allow_avx = false;
        const SsimMap fast = ssim_map(a, b), plain = ssim_map(a, b, sse);
        REQUIRE(fast.values.size() == plain.values.size());
        bool same = true;
        for (std::size_t i = 0; i < fast.values.size(); ++i)
            same = same && std::memcmp(&fast.values[i], &plain.values[i], sizeof(double)) == 0;
        CHECK_MESSAGE(same, "width " << w);
        CHECK(std::memcmp(&fast.mean, &plain.mean, sizeof(double)) == 0);
    }
}

TEST_CASE("ssim: equals scikit-image's structural_similarity on a fixed image") {
    // Reference: skimage 0.19.3 structural_similarity(a, b, gaussian_weights=True, sigma=1.5,
    // use_sample_covariance=False, data_range=1.0) on these binary32 images as float64:
    // 0.9936071663265187. SPEC §10 asks for agreement to 1e-6.
    Image a(48, 40, 1), b(48, 40, 1);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 48; ++x) {
            const std::int64_t k =
                ((x * std::int64_t{73856093}) ^ (y * std::int64_t{19349663})) % 1000;
            a.at(x, y) = static_cast<float>(k) / 1000.0f;
            b.at(x, y) = a.at(x, y) + static_cast<float>((x * 7 + y * 13) % 11 - 5) * 0.01f;
        }
    CHECK(ssim_map(a, b).mean == doctest::Approx(0.9936071663265187).epsilon(1e-9));
}

TEST_CASE("ssim: more noise, lower SSIM, symmetric in its arguments") {
    const Image a = random_image(40, 40, 1, 31);
    double previous = 1.0;
    for (const float amount : {0.05f, 0.1f, 0.2f, 0.4f}) {
        Image b = a;
        test::SplitMix64 rng(9);
        for (float& v : b.data) v += amount * (rng.unit() - 0.5f);
        const double s = ssim_map(a, b).mean;
        CHECK(s < previous);
        CHECK(s == ssim_map(b, a).mean);  // the formula is symmetric term by term
        previous = s;
    }
}

TEST_CASE("ssim/mse: bad input is an error, not a crash") {
    using test::contains;
    using test::error_message;
    CHECK(contains(error_message([] { mse(Image(2, 2, 3), Image(2, 3, 3)); }), "differ in shape"));
    CHECK(contains(error_message([] { ssim_map(Image(10, 20, 1), Image(10, 20, 1)); }),
                   "smaller than the 11x11 window"));
    CHECK(
        contains(error_message([] { ssim_map(Image(20, 20, 3), Image(20, 20, 3)); }), "1-channel"));
    CHECK(contains(error_message([] { luma(Image(2, 2, 2)); }), "1- or 3-channel"));
    SsimSettings bad;
    bad.data_range = 0;
    CHECK(contains(error_message([&] { ssim_map(Image(20, 20, 1), Image(20, 20, 1), bad); }),
                   "data range"));
}

TEST_CASE("luma, display transform, error maps") {
    Image rgb(1, 1, 3);
    rgb.data = {1.0f, 0.0f, 0.0f};
    CHECK(luma(rgb).data[0] == 0.2126f);
    rgb.data = {1.0f, 1.0f, 1.0f};
    CHECK(luma(rgb).data[0] == doctest::Approx(1.0f).epsilon(1e-7));
    Image values(5, 1, 1);
    values.data = {-1.0f, 0.0f, 0.5f, 2.0f, std::numeric_limits<float>::quiet_NaN()};
    const Image d = to_display(values);
    CHECK(d.data[0] == 0.0f);
    CHECK(d.data[1] == 0.0f);
    CHECK(d.data[2] == doctest::Approx(0.735356983).epsilon(1e-6));  // sRGB(0.5)
    CHECK(d.data[3] == 1.0f);
    CHECK(d.data[4] == 0.0f);
    Image a = constant(2, 1, 3, 0.0f), b = a;
    b.at(1, 0, 0) = 0.5f;
    b.at(1, 0, 2) = -0.25f;
    const Image se = squared_error_map(a, b), ae = abs_error_map(a, b);
    CHECK(se.at(0, 0) == 0.0f);
    CHECK(se.at(1, 0) == static_cast<float>((0.25 + 0.0625) / 3));
    CHECK(ae.at(1, 0) == 0.5f);
}

TEST_CASE("temporal error: mean absolute luma change between consecutive frames") {
    std::vector<Image> frames = {constant(4, 4, 1, 0.0f), constant(4, 4, 1, 0.5f),
                                 constant(4, 4, 1, 0.25f)};
    CHECK(temporal_error(frames) == 0.375);  // (0.5 + 0.25) / 2
    CHECK(temporal_error({constant(4, 4, 3, 0.5f)}) == 0.0);
    frames.push_back(constant(5, 4, 1, 0.0f));
    CHECK(test::contains(test::error_message([&] { temporal_error(frames); }), "shape"));
}
