// BMFR (ref/bmfr/bmfr.h): the block grid, the fit against independent binary64 solves, the
// numerical robustness cases of SPEC §9 / issue 15 (flat walls, empty blocks, borders, NaN/Inf,
// zero albedo, noise amplitudes), the temporal accumulations and the TAA on analytic inputs.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/bmfr_params.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

// A W x H "wall": world position (s x, s y, z0) + bump, normal n, so a test controls how
// degenerate the features are.
struct WallFrame {
    Image radiance, albedo, normal, world;
};

WallFrame wall(int width, int height, float scale, glm::vec3 n, float z0) {
    WallFrame f;
    f.radiance = Image(width, height, 3);
    f.albedo = Image(width, height, 3, 0.5f);
    f.normal = Image(width, height, 3);
    f.world = Image(width, height, 3);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            f.world.at(x, y, 0) = scale * static_cast<float>(x);
            f.world.at(x, y, 1) = scale * static_cast<float>(y);
            f.world.at(x, y, 2) = z0;
            for (int c = 0; c < 3; ++c) f.normal.at(x, y, c) = n[c];
        }
    return f;
}

bool all_finite(const Image& image) {
    return std::all_of(image.data.begin(), image.data.end(),
                       [](float v) { return std::isfinite(v); });
}

// Solves the least-squares problem min |A w - b| over the given columns of a block matrix in
// binary64 through the normal equations (Gaussian elimination with partial pivoting).
std::vector<double> normal_equations(const BmfrBlockMatrix& m, const std::vector<int>& columns,
                                     int rhs) {
    const int n = static_cast<int>(columns.size());
    std::vector<double> ata(n * (n + 1), 0.0);
    for (int r = 0; r < m.rows; ++r)
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j)
                ata[i * (n + 1) + j] +=
                    static_cast<double>(m.at(r, columns[i])) * m.at(r, columns[j]);
            ata[i * (n + 1) + n] += static_cast<double>(m.at(r, columns[i])) * m.at(r, rhs);
        }
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i)
            if (std::fabs(ata[i * (n + 1) + k]) > std::fabs(ata[p * (n + 1) + k])) p = i;
        for (int j = 0; j <= n; ++j) std::swap(ata[k * (n + 1) + j], ata[p * (n + 1) + j]);
        for (int i = k + 1; i < n; ++i) {
            const double f = ata[i * (n + 1) + k] / ata[k * (n + 1) + k];
            for (int j = k; j <= n; ++j) ata[i * (n + 1) + j] -= f * ata[k * (n + 1) + j];
        }
    }
    std::vector<double> w(n);
    for (int i = n - 1; i >= 0; --i) {
        double v = ata[i * (n + 1) + n];
        for (int j = i + 1; j < n; ++j) v -= ata[i * (n + 1) + j] * w[j];
        w[i] = v / ata[i * (n + 1) + i];
    }
    return w;
}

// A block with well-conditioned random features (scaled features already in [0, 1]) and colours
// from `colour(row, features)`.
template <class Colour>
BmfrBlockMatrix random_block(std::uint32_t seed, Colour colour) {
    BmfrBlockMatrix m;
    for (int r = 0; r < bmfr_block_pixels; ++r) {
        m.at(r, 0) = 1.0f;
        for (int f = 1; f < bmfr_feature_count; ++f)
            m.at(r, f) =
                rand_unit(seed, static_cast<std::uint32_t>(r), static_cast<std::uint32_t>(f));
        for (int c = 0; c < 3; ++c) m.at(r, 10 + c) = colour(r, c, &m.at(r, 0));
    }
    return m;
}

BmfrParams float_params() {
    BmfrParams p;
    p.storage = BmfrStorage::single;
    return p;
}

}  // namespace

TEST_CASE(
    "bmfr grid: (ceil(W/32) + 1) x (ceil(H/32) + 1) cells, the authors' offsets, every "
    "pixel in exactly the cell that covers it") {
    CHECK(bmfr_block_offsets()[0] == glm::ivec2(-14, -14));
    CHECK(bmfr_block_offsets()[9] == glm::ivec2(-8, -16));
    CHECK(bmfr_block_offsets()[15] == glm::ivec2(-6, 4));
    for (int frame = 0; frame < 16; ++frame) {
        const BmfrGrid g = bmfr_grid(160, 96, frame);
        CHECK(g.cells_x == 6);
        CHECK(g.cells_y == 4);
        CHECK(g.offset == bmfr_block_offsets()[frame]);
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 160; ++x) {
                const glm::ivec2 c = g.cell_of(x, y);
                REQUIRE(c.x >= 0);
                REQUIRE(c.y >= 0);
                REQUIRE(c.x < g.cells_x);
                REQUIRE(c.y < g.cells_y);
                const glm::ivec2 o = g.origin(c.x, c.y);
                REQUIRE(x - o.x >= 0);
                REQUIRE(x - o.x < 32);
                REQUIRE(y - o.y >= 0);
                REQUIRE(y - o.y < 32);
            }
    }
    CHECK(bmfr_grid(1280, 720, 0).cells_x == 41);
    CHECK(bmfr_grid(1280, 720, 0).cells_y == 24);
}

TEST_CASE(
    "bmfr 64 x 64 blocks (bmfr_block=64, P2 §6.1): the grid, the offsets doubled, the "
    "noise's stride, a fit on a wall") {
    // (ceil(1280 / 64) + 1) x (ceil(720 / 64) + 1) = 21 x 13 cells
    CHECK(bmfr_grid(1280, 720, 0, nullptr, 64).cells_x == 21);
    CHECK(bmfr_grid(1280, 720, 0, nullptr, 64).cells_y == 13);
    for (int frame = 0; frame < 16; ++frame) {
        const BmfrGrid g = bmfr_grid(160, 96, frame, nullptr, 64);
        CHECK(g.offset == 2 * bmfr_block_offsets()[frame]);
        CHECK(g.origin(0, 0) == glm::ivec2(-32) + g.offset);
        for (int y = 0; y < 96; ++y)
            for (int x = 0; x < 160; ++x) {
                const glm::ivec2 c = g.cell_of(x, y), o = g.origin(c.x, c.y);
                REQUIRE(c.x < g.cells_x);
                REQUIRE(c.y < g.cells_y);
                REQUIRE((x - o.x >= 0 && x - o.x < 64 && y - o.y >= 0 && y - o.y < 64));
            }
    }
    // The noise's seed strides by the block's 4096 pixels: row 5 of feature 3 in frame 2 hashes
    // 5 + 3 4096 + 2 13 4096 = 118789
    const float r = static_cast<float>(jenkins_hash(118789u)) / 4294967295.0f;
    CHECK(bmfr_regularisation_noise(0.01f, BmfrNoiseHash::jenkins, 5, 3, 2, 4096) ==
          0.01f * 2.0f * (r - 0.5f));
    // A wall lit linearly in x and y: the fit of a 64 x 64 block (4096 rows, with the noise)
    // reproduces every row within 5e-3 (a flat wall is rank-deficient: the regularisation noise,
    // 0.01 on every feature, moves the fit by a few 1e-3; the 32 x 32 block of the same wall
    // below does the same)
    WallFrame f = wall(160, 160, 0.01f, glm::vec3(0, 0, 1), 2.0f);
    Image illumination(160, 160, 3);
    for (int y = 0; y < 160; ++y)
        for (int x = 0; x < 160; ++x)
            for (int c = 0; c < 3; ++c)
                illumination.at(x, y, c) = 0.2f + 0.004f * static_cast<float>(x) +
                                           0.001f * static_cast<float>(y * (c + 1));
    const BmfrGrid grid = bmfr_grid(160, 160, 3, nullptr, 64);
    BmfrBlockMatrix m, clean;
    bmfr_gather_block(float_params(), grid, 1, 1, illumination, f.world, f.normal, 3, true, m);
    bmfr_gather_block(float_params(), grid, 1, 1, illumination, f.world, f.normal, 3, false, clean);
    REQUIRE(m.rows == 4096);
    const auto worst_row = [](BmfrBlockMatrix& noisy, const BmfrBlockMatrix& noise_free) {
        const BmfrBlockFit fit = bmfr_solve_block(float_params(), noisy);
        double worst = 0.0;
        for (int row = 0; row < noise_free.rows; ++row)
            for (int c = 0; c < 3; ++c) {
                double v = 0.0;
                for (int i = 0; i < 10; ++i) v += fit.weights[c][i] * noise_free.at(row, i);
                worst = std::max(worst, std::fabs(v - noise_free.at(row, 10 + c)));
            }
        return worst;
    };
    const double worst64 = worst_row(m, clean);
    const BmfrGrid grid32 = bmfr_grid(160, 160, 3);
    BmfrBlockMatrix m32, clean32;
    bmfr_gather_block(float_params(), grid32, 2, 2, illumination, f.world, f.normal, 3, true, m32);
    bmfr_gather_block(float_params(), grid32, 2, 2, illumination, f.world, f.normal, 3, false,
                      clean32);
    REQUIRE(m32.rows == 1024);
    const double worst32 = worst_row(m32, clean32);
    MESSAGE("largest row error of the wall's fit: 64 x 64 " << worst64 << ", 32 x 32 " << worst32);
    CHECK(worst64 < 5e-3);
    CHECK(worst32 < 5e-3);
    // refused values
    CHECK(test::contains(test::error_message([] {
                             parse_bmfr_params(Params(std::map<std::string, std::string>{
                                 {"denoise", "bmfr"}, {"bmfr_block", "48"}}));
                         }),
                         "parameter 'bmfr_block'"));
}

TEST_CASE("bmfr: a block without data is gathered as the same zero matrix wherever it lies") {
    // bmfr_fit solves one such block and reuses its fit for the others: that needs every empty
    // block's matrix, ranges included, to be the same bits, whatever the matrix held before
    WallFrame f = wall(96, 96, 0.01f, glm::vec3(0, 0, 1), 2.0f);
    // no data anywhere but in the first rows; blocks (1, 1) and (2, 2) lie below them
    Image illumination(96, 96, 3, 0.5f), valid(96, 96, 1, 0.0f), everywhere(96, 96, 1, 1.0f);
    for (int x = 0; x < 96; ++x) valid.at(x, 0) = 1.0f;
    const BmfrGrid grid = bmfr_grid(96, 96, 3);
    BmfrBlockMatrix fresh, reused;
    bmfr_gather_block(float_params(), grid, 1, 1, illumination, f.world, f.normal, 3, true, fresh,
                      &valid);
    bmfr_gather_block(float_params(), grid, 0, 0, illumination, f.world, f.normal, 3, true, reused,
                      &everywhere);
    CHECK(reused.data_rows > 0);
    bmfr_gather_block(float_params(), grid, 2, 2, illumination, f.world, f.normal, 3, true, reused,
                      &valid);
    CHECK(fresh.data_rows == 0);
    CHECK(reused.data_rows == 0);
    CHECK(std::memcmp(fresh.a.data(), reused.a.data(), fresh.a.size() * sizeof(float)) == 0);
    CHECK(std::all_of(fresh.a.begin(), fresh.a.end(), [](float v) { return v == 0.0f; }));
    CHECK(std::memcmp(fresh.feature_min, reused.feature_min, sizeof fresh.feature_min) == 0);
    CHECK(std::memcmp(fresh.feature_max, reused.feature_max, sizeof fresh.feature_max) == 0);
}

TEST_CASE("bmfr_mirror: -1 -> 0, W -> W - 1, reflected again for images narrower than a block") {
    CHECK(bmfr_mirror(-1, 10) == 0);
    CHECK(bmfr_mirror(-3, 10) == 2);
    CHECK(bmfr_mirror(10, 10) == 9);
    CHECK(bmfr_mirror(12, 10) == 7);
    CHECK(bmfr_mirror(5, 10) == 5);
    for (int size : {1, 2, 3, 7})
        for (int i = -70; i < 70; ++i) {
            const int m = bmfr_mirror(i, size);
            REQUIRE(m >= 0);
            REQUIRE(m < size);
        }
    CHECK(bmfr_mirror(-1, 1) == 0);
    CHECK(bmfr_mirror(45, 1) == 0);
}

TEST_CASE(
    "bmfr fit: colours that are an exact combination of the features are reproduced to "
    "float precision") {
    const float truth[3][10] = {{0.3f, 0.1f, -0.2f, 0.05f, 0.7f, -0.4f, 0.2f, 0.1f, 0.3f, -0.1f},
                                {1.0f, 0.0f, 0.5f, 0.0f, -0.3f, 0.2f, 0.6f, -0.2f, 0.0f, 0.4f},
                                {0.0f, 0.2f, 0.2f, 0.2f, 0.1f, 0.1f, 0.1f, 0.5f, -0.5f, 0.25f}};
    BmfrBlockMatrix m = random_block(11u, [&](int, int c, const float* t) {
        float s = 0.0f;
        for (int i = 0; i < 10; ++i) s += truth[c][i] * t[i];
        return s;
    });
    const BmfrBlockMatrix original = m;
    const BmfrBlockFit fit = bmfr_solve_block(float_params(), m);
    CHECK(fit.pivots_zeroed == 0);
    double worst = 0.0;
    for (int r = 0; r < bmfr_block_pixels; ++r)
        for (int c = 0; c < 3; ++c) {
            double s = 0.0;
            for (int i = 0; i < 10; ++i)
                s += static_cast<double>(fit.weights[c][i]) * original.at(r, i);
            worst = std::max(worst, std::fabs(s - original.at(r, 10 + c)));
        }
    // The colours are below 3; float QR of a matrix with condition number ~30: a few 1e-6.
    CHECK(worst < 2e-5);
    for (int c = 0; c < 3; ++c)
        for (int i = 0; i < 10; ++i)
            CHECK(fit.weights[c][i] == doctest::Approx(truth[c][i]).epsilon(1e-3).scale(1.0));
}

TEST_CASE(
    "bmfr fit: the QR solve agrees with a binary64 normal-equations solve on random "
    "well-conditioned blocks") {
    const std::vector<int> columns = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    double worst_float = 0.0, worst_half = 0.0;
    for (std::uint32_t seed = 1; seed <= 20; ++seed) {
        const auto colour = [&](int r, int c, const float* t) {
            return 0.5f * t[1 + c] + t[4] * t[5] +
                   rand_unit(seed + 100u, static_cast<std::uint32_t>(r),
                             static_cast<std::uint32_t>(c));
        };
        for (BmfrStorage storage : {BmfrStorage::single, BmfrStorage::half}) {
            BmfrBlockMatrix m = random_block(seed, colour);
            if (storage == BmfrStorage::half)
                for (float& v : m.a) v = static_cast<float>(static_cast<double>(v));  // as given
            BmfrParams params;
            params.storage = storage;
            const BmfrBlockMatrix original = m;
            const BmfrBlockFit fit = bmfr_solve_block(params, m);
            for (int c = 0; c < 3; ++c) {
                const std::vector<double> w = normal_equations(original, columns, 10 + c);
                for (int i = 0; i < 10; ++i) {
                    const double e = std::fabs(fit.weights[c][i] - w[i]);
                    (storage == BmfrStorage::single ? worst_float : worst_half) =
                        std::max(storage == BmfrStorage::single ? worst_float : worst_half, e);
                }
            }
        }
    }
    // Stated bounds: binary32 storage, condition number of the block ~30, |w| < 3: 1e-4;
    // binary16 storage rounds every updated value to 11 bits (relative 2^-11 per column step).
    MESSAGE("max |w_QR - w_normal| float storage " << worst_float << ", half storage "
                                                   << worst_half);
    CHECK(worst_float < 1e-4);
    CHECK(worst_half < 0.1);
}

TEST_CASE(
    "bmfr fit: a flat wall is rank-deficient, stochastic regularisation keeps the fit "
    "finite and close to the least-squares fit") {
    // Constant normal and z: features n, w_z and w_z^2 are constant (collinear with column 0).
    WallFrame f = wall(64, 64, 0.01f, glm::vec3(0, 0, 1), 2.0f);
    Image illumination(64, 64, 3);
    for (int y = 0; y < 64; ++y)
        for (int x = 0; x < 64; ++x)
            for (int c = 0; c < 3; ++c)
                illumination.at(x, y, c) =
                    0.2f + 0.01f * static_cast<float>(x) + 0.002f * static_cast<float>(y * (c + 1));
    const BmfrGrid grid = bmfr_grid(64, 64, 3);
    BmfrParams params = float_params();

    SUBCASE("without noise and without the pivot guard the solve divides by ~0") {
        BmfrBlockMatrix m;
        bmfr_gather_block(params, grid, 1, 1, illumination, f.world, f.normal, 3, false, m);
        params.pivot_epsilon = 0.0f;
        const BmfrBlockFit fit = bmfr_solve_block(params, m);
        // a division by ~0 gives weights beyond 1e4 or overflows (then zeroed and counted)
        bool exploded = fit.weights_nonfinite > 0;
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 10; ++i)
                exploded = exploded || !std::isfinite(fit.weights[c][i]) ||
                           std::fabs(fit.weights[c][i]) > 1e4f;
        CHECK(exploded);
    }
    SUBCASE(
        "with the noise: finite weights, the fitted block within 1e-3 of the binary64 "
        "least-squares fit over the independent features") {
        BmfrBlockMatrix m, clean;
        bmfr_gather_block(params, grid, 1, 1, illumination, f.world, f.normal, 3, true, m);
        bmfr_gather_block(params, grid, 1, 1, illumination, f.world, f.normal, 3, false, clean);
        const BmfrBlockFit fit = bmfr_solve_block(params, m);
        CHECK(fit.pivots_zeroed == 0);
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < 10; ++i) REQUIRE(std::isfinite(fit.weights[c][i]));
        // the independent columns: 1, w_x, w_y, w_x^2, w_y^2
        const std::vector<int> independent = {0, 4, 5, 7, 8};
        double worst = 0.0;
        for (int c = 0; c < 3; ++c) {
            const std::vector<double> w = normal_equations(clean, independent, 10 + c);
            for (int r = 0; r < bmfr_block_pixels; ++r) {
                double ls = 0.0, ours = 0.0;
                for (std::size_t k = 0; k < independent.size(); ++k)
                    ls += w[k] * clean.at(r, independent[k]);
                for (int i = 0; i < 10; ++i) ours += fit.weights[c][i] * clean.at(r, i);
                worst = std::max(worst, std::fabs(ls - ours));
            }
        }
        MESSAGE("flat wall: max |fit - least squares| = " << worst);
        // The regression sees features perturbed by up to 0.01 and is evaluated without the
        // perturbation: an error of the order of the noise amplitude times the colour scale (1).
        CHECK(worst < 1e-2);
    }
}

TEST_CASE(
    "bmfr robustness: empty (sky) blocks, constant colours, borders, NaN/Inf radiance, zero "
    "albedo, noise amplitudes 1e-4..1 give finite output") {
    for (BmfrStorage storage : {BmfrStorage::half, BmfrStorage::single}) {
        BmfrParams params;
        params.storage = storage;
        SUBCASE("sky: every feature and colour zero") {
            WallFrame f = wall(70, 40, 0.0f, glm::vec3(0.0f), 0.0f);
            f.albedo = Image(70, 40, 3, 0.0f);
            BmfrHistory history;
            BmfrStats stats;
            for (int frame = 0; frame < 3; ++frame) {
                const BmfrFrame out =
                    bmfr_denoise_frame(params, f.radiance, f.albedo, Image{}, f.normal, f.world,
                                       ViewProjection{}, frame, history, stats);
                CHECK(all_finite(out.output));
                CHECK(*std::max_element(out.output.data.begin(), out.output.data.end()) == 0.0f);
            }
        }
        SUBCASE("constant colour on a flat wall is reproduced, at the borders too") {
            WallFrame f = wall(70, 40, 0.05f, glm::vec3(0, 1, 0), 1.0f);
            f.radiance = Image(70, 40, 3, 0.25f);  // illumination 0.5
            BmfrHistory history;
            BmfrStats stats;
            const BmfrFrame out =
                bmfr_denoise_frame(params, f.radiance, f.albedo, Image{}, f.normal, f.world,
                                   ViewProjection{}, 0, history, stats);
            double worst = 0.0;
            for (float v : out.fitted.data) worst = std::max(worst, std::fabs(v - 0.5));
            MESSAGE("constant: max |fitted - 0.5| = " << worst);
            CHECK(worst < (storage == BmfrStorage::half ? 2e-3 : 1e-4));
        }
        SUBCASE("NaN and Inf radiance, zero albedo") {
            WallFrame f = wall(50, 33, 0.02f, glm::vec3(0, 0, 1), 1.0f);
            for (int i = 0; i < 50 * 33; ++i) {
                const float v =
                    i % 7 == 0 ? NAN : (i % 11 == 0 ? INFINITY : (i % 13 == 0 ? -INFINITY : 0.3f));
                f.radiance.data[static_cast<std::size_t>(i) * 3] = v;
                f.radiance.data[static_cast<std::size_t>(i) * 3 + 1] = 0.3f;
                f.radiance.data[static_cast<std::size_t>(i) * 3 + 2] = 0.3f;
                if (i % 5 == 0) f.albedo.data[static_cast<std::size_t>(i) * 3] = 0.0f;
            }
            f.world.at(3, 3, 0) = NAN;
            f.normal.at(4, 4, 1) = INFINITY;
            BmfrHistory history;
            BmfrStats stats;
            for (int frame = 0; frame < 2; ++frame) {
                const BmfrFrame out =
                    bmfr_denoise_frame(params, f.radiance, f.albedo, Image{}, f.normal, f.world,
                                       ViewProjection{}, frame, history, stats);
                CHECK(all_finite(out.illumination));
                CHECK(all_finite(out.fitted));
                CHECK(all_finite(out.output));
            }
            CHECK(stats.nonfinite_inputs > 0);
        }
        SUBCASE(
            "noise amplitudes 1e-4 .. 1: finite, and the fit is closer to the truth than the "
            "noisy input") {
            for (float amplitude : {1e-4f, 1e-3f, 1e-2f, 1e-1f, 1.0f}) {
                WallFrame f = wall(96, 64, 0.02f, glm::vec3(0, 0, 1), 1.0f);
                Image truth(96, 64, 3);
                for (int y = 0; y < 64; ++y)
                    for (int x = 0; x < 96; ++x)
                        for (int c = 0; c < 3; ++c) {
                            const float t = 0.5f + 0.3f * f.world.at(x, y, 0) -
                                            0.2f * f.world.at(x, y, 1) * f.world.at(x, y, 1);
                            truth.at(x, y, c) = t;
                            const float u = rand_unit(1u, static_cast<std::uint32_t>(y * 96 + x),
                                                      static_cast<std::uint32_t>(c));
                            f.radiance.at(x, y, c) = 0.5f * (t + amplitude * 2.0f * (u - 0.5f));
                        }
                BmfrHistory history;
                BmfrStats stats;
                const BmfrFrame out =
                    bmfr_denoise_frame(params, f.radiance, f.albedo, Image{}, f.normal, f.world,
                                       ViewProjection{}, 0, history, stats);
                REQUIRE(all_finite(out.output));
                double noisy = 0.0, fitted = 0.0;
                for (std::size_t i = 0; i < truth.data.size(); ++i) {
                    noisy += std::pow(out.illumination.data[i] - truth.data[i], 2.0);
                    fitted += std::pow(out.fitted.data[i] - truth.data[i], 2.0);
                }
                CAPTURE(amplitude);
                const double n = static_cast<double>(truth.data.size());
                MESSAGE("noise " << amplitude << ": RMSE noisy " << std::sqrt(noisy / n)
                                 << ", fitted " << std::sqrt(fitted / n));
                // A least-squares fit of 10 features over 1024 pixels keeps about sqrt(10/1024)
                // ~ 0.1 of white noise; the regularisation (0.01 on the features) adds a floor of
                // about 5e-4: below that noise the input can be closer than the fit.
                CHECK(std::sqrt(fitted / n) < 1e-3 + 0.1 * std::sqrt(noisy / n));
                if (amplitude >= 1e-2f) CHECK(fitted < noisy);
            }
        }
    }
}

TEST_CASE(
    "bmfr phase I: a static camera averages the first frames, then an exponential moving "
    "average, spp counts to 255") {
    WallFrame f = wall(8, 8, 0.1f, glm::vec3(0, 0, 1), 1.0f);
    Camera camera = look_at({0.35f, 0.35f, 3.0f}, {0.35f, 0.35f, 1.0f}, {0, 1, 0}, 40.0f);
    const ViewProjection vp = view_projection(camera, 8, 8);
    BmfrParams params;
    BmfrHistory history;
    BmfrStats stats;
    const float values[5] = {1.0f, 3.0f, 2.0f, 6.0f, 4.0f};
    double sum = 0.0;
    for (int frame = 0; frame < 300; ++frame) {
        const float v = values[frame % 5];
        Image illumination(8, 8, 3, v);
        const BmfrAccumulation a =
            bmfr_accumulate_noisy(params, illumination, f.world, f.normal, history, stats);
        if (frame < 5) {
            sum += v;
            CHECK(a.accumulated.at(4, 4) == doctest::Approx(sum / (frame + 1)).epsilon(1e-6));
            CHECK(a.spp.at(4, 4) == static_cast<float>(frame + 1));
        }
        if (frame == 299) CHECK(a.spp.at(4, 4) == 255.0f);
        if (frame > 0) CHECK(a.accept.at(4, 4) != 0.0f);
        history.valid = true;
        history.view_projection = vp;
        history.world_position = f.world;
        history.normal = f.normal;
        history.accumulated_noisy = a.accumulated;
        history.spp = a.spp;
    }
}

TEST_CASE(
    "bmfr reprojection: bmfr_project agrees with the camera's own projection "
    "(project_to_screen) to a thousandth of a pixel") {
    const Camera camera = look_at({0.3f, 1.2f, 3.5f}, {0.0f, 0.8f, 0.0f}, {0, 1, 0}, 50.0f);
    const ViewProjection vp = view_projection(camera, 320, 180);
    const float tan_half = tan_half_vfov(camera);
    for (std::uint32_t i = 0; i < 1000; ++i) {
        const glm::vec3 p(rand_unit(5, i, 0) * 2 - 1, rand_unit(5, i, 1) * 2,
                          rand_unit(5, i, 2) * 2 - 1);
        glm::vec2 screen, pixel;
        float depth;
        REQUIRE(project_to_screen(camera, tan_half, 320, 180, p, screen, depth));
        REQUIRE(bmfr_project(vp, 320, 180, p, pixel));
        CHECK(std::fabs(pixel.x - (screen.x - 0.5f)) < 1e-3f);
        CHECK(std::fabs(pixel.y - (screen.y - 0.5f)) < 1e-3f);
    }
    glm::vec2 pixel;
    CHECK_FALSE(bmfr_project(vp, 320, 180, camera.position - camera.forward, pixel));
    // bmfr_behind_camera=project (the authors' code): divided by the negative w, the point
    // 0.3 right of the axis 1 behind the camera lands mirrored, left of the centre:
    // x = (0.3 / (tan W/H) / -1 + 1) 0.5 W - 0.5
    const glm::vec3 behind = camera.position - camera.forward + 0.3f * camera.right;
    REQUIRE(bmfr_project(vp, 320, 180, behind, pixel, glm::vec2(0.5f), true));
    const double sx = tan_half * (320.0 / 180.0);
    CHECK(pixel.x == doctest::Approx((-0.3 / sx + 1.0) * 0.5 * 320.0 - 0.5).epsilon(1e-4));
    CHECK(pixel.y == doctest::Approx(0.5 * 180.0 - 0.5).epsilon(1e-4));
    // w about 0 (in the camera's plane): no projection, or one far off the image (no tap)
    if (bmfr_project(vp, 320, 180, camera.position + camera.right, pixel, glm::vec2(0.5f), true))
        CHECK(std::fabs(pixel.x) > 1e5f);
    Params params;
    params.set("denoise", "bmfr");
    CHECK_FALSE(parse_bmfr_params(params, "none").params.project_behind_camera);
    params.set("bmfr_behind_camera", "project");
    CHECK(parse_bmfr_params(params, "none").params.project_behind_camera);
}

TEST_CASE(
    "bmfr TAA: YCoCg clamping keeps a constant image, the first frame takes the new "
    "colour, history is blended 0.2 / 0.8") {
    BmfrParams params;
    BmfrStats stats;
    Image display(6, 5, 3, 0.5f), previous(6, 5, 2);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 6; ++x) {
            previous.at(x, y, 0) = static_cast<float>(x);
            previous.at(x, y, 1) = static_cast<float>(y);
        }
    CHECK(bmfr_taa(params, display, previous, Image{}, stats) == display);
    Image history(6, 5, 3, 0.5f);
    CHECK(bmfr_taa(params, display, previous, history, stats) == display);
    // a history inside the neighbourhood's range is blended, not clamped
    Image varied = display;
    varied.at(2, 2, 1) = 0.7f;
    history.at(2, 2, 1) = 0.6f;
    const Image out = bmfr_taa(params, varied, previous, history, stats);
    CHECK(out.at(2, 2, 1) == doctest::Approx(0.2 * 0.7 + 0.8 * 0.6).epsilon(1e-6));
    // a history far outside is clamped into the box: the result lies within the neighbourhood
    history.at(2, 2, 1) = 5.0f;
    const Image clamped = bmfr_taa(params, varied, previous, history, stats);
    CHECK(clamped.at(2, 2, 1) <= 0.7f + 1e-6f);
}

namespace {

// A 64 x 48 tilted wall with noisy radiance (0.25 + 0.2 rand), and one frame of BMFR on it with
// no history (frame 2 of the noise's seed).
WallFrame noisy_wall() {
    WallFrame f = wall(64, 48, 0.03f, glm::vec3(0.6f, 0.0f, 0.8f), 1.0f);
    for (int i = 0; i < 64 * 48 * 3; ++i)
        f.radiance.data[static_cast<std::size_t>(i)] =
            0.25f + 0.2f * rand_unit(3u, static_cast<std::uint32_t>(i), 0u);
    return f;
}

BmfrFrame first_frame(const BmfrParams& params, const WallFrame& f) {
    BmfrHistory history;
    BmfrStats stats;
    return bmfr_denoise_frame(params, f.radiance, f.albedo, Image{}, f.normal, f.world,
                              ViewProjection{}, 2, history, stats);
}

}  // namespace

TEST_CASE("bmfr: the same inputs give the same bits, half and float storage differ only slightly") {
    const WallFrame f = noisy_wall();
    const auto run = [&](BmfrStorage storage) {
        BmfrParams params;
        params.storage = storage;
        return first_frame(params, f);
    };
    const BmfrFrame a = run(BmfrStorage::half), b = run(BmfrStorage::half),
                    c = run(BmfrStorage::single);
    CHECK(bit_equal(a.output, b.output));
    CHECK(bit_equal(a.fit.weights, b.fit.weights));
    CHECK_FALSE(bit_equal(a.fitted, c.fitted));
    double worst = 0.0;
    for (std::size_t i = 0; i < a.fitted.data.size(); ++i)
        worst =
            std::max(worst, static_cast<double>(std::fabs(a.fitted.data[i] - c.fitted.data[i])));
    MESSAGE("half vs float storage: max |fitted difference| = " << worst);
    CHECK(worst < 0.02);
}

TEST_CASE(
    "bmfr phase I: a frame's pixel offset moves the reprojected pixel by exactly its "
    "difference from the centre, the demodulated input is taken as the illumination") {
    WallFrame f = wall(16, 16, 0.1f, glm::vec3(0, 0, 1), 1.0f);
    Camera camera = look_at({0.75f, 0.75f, 3.0f}, {0.75f, 0.75f, 1.0f}, {0, 1, 0}, 40.0f);
    BmfrHistory history;
    history.valid = true;
    history.view_projection = view_projection(camera, 16, 16);
    history.world_position = f.world;
    history.normal = f.normal;
    history.accumulated_noisy = Image(16, 16, 3, 1.0f);
    history.spp = Image(16, 16, 1, 1.0f);
    BmfrParams centre, offset;
    offset.pixel_offset = {0.25f, 0.75f};  // the authors' pixel_offsets[frame]
    BmfrStats stats;
    const Image illumination(16, 16, 3, 2.0f);
    const BmfrAccumulation a =
        bmfr_accumulate_noisy(centre, illumination, f.world, f.normal, history, stats);
    const BmfrAccumulation b =
        bmfr_accumulate_noisy(offset, illumination, f.world, f.normal, history, stats);
    int checked = 0;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) {
            // q - 0.25 and q - 0.5 are exact for |q| < 2^21: the difference is exactly 0.25
            CHECK(b.previous_pixel.at(x, y, 0) == a.previous_pixel.at(x, y, 0) + 0.25f);
            CHECK(b.previous_pixel.at(x, y, 1) == a.previous_pixel.at(x, y, 1) - 0.25f);
            ++checked;
        }
    CHECK(checked == 256);
    // --demodulated: colour / max(albedo, floor) as given gives bmfr_demodulate's bits
    BmfrParams demodulated;
    demodulated.demodulated_input = true;
    Image colour(16, 16, 3);
    for (std::size_t i = 0; i < colour.data.size(); ++i) {
        f.radiance.data[i] = 0.37f * static_cast<float>(i % 7);
        f.albedo.data[i] = i % 5 == 0 ? 0.001f : 0.3f + 0.1f * static_cast<float>(i % 3);
        colour.data[i] = f.radiance.data[i] / std::max(f.albedo.data[i], centre.albedo_floor);
    }
    const Image from_radiance = bmfr_demodulate(centre, f.radiance, f.albedo, Image(), stats);
    const Image as_given = bmfr_demodulate(demodulated, colour, f.albedo, Image(), stats);
    CHECK(std::memcmp(from_radiance.data.data(), as_given.data.data(),
                      from_radiance.data.size() * sizeof(float)) == 0);
}

// The per-value passes written into storage that holds a value none of them takes (a stage's
// recycled storage): every value is written, the bits those of fresh storage; storage of another
// shape is not used.
TEST_CASE("bmfr: demodulation, remodulation and linearisation write every value of their storage") {
    test::SplitMix64 rng(77);
    Image radiance(19, 7, 3), albedo(19, 7, 3), emission(19, 7, 3);
    for (Image* image : {&radiance, &albedo, &emission})
        for (float& v : image->data) v = rng.uniform(-0.5f, 3.0f);
    radiance.data[5] = std::nanf("");
    albedo.data[11] = INFINITY;
    for (const bool separate : {false, true}) {
        CAPTURE(separate);
        BmfrParams params;
        params.separate_emission = separate;
        const Image& e = separate ? emission : Image();
        BmfrStats stats;
        const Image fresh = bmfr_demodulate(params, radiance, albedo, e, stats);
        const Image into =
            bmfr_demodulate(params, radiance, albedo, e, stats, test::unwritten_storage(19, 7, 3));
        CHECK(test::same_bits_nan_aside(into, fresh));
        CHECK(test::same_bits_nan_aside(
            bmfr_demodulate(params, radiance, albedo, e, stats, test::unwritten_storage(3, 3, 3)),
            fresh));
        const Image display = bmfr_remodulate(params, fresh, albedo, e);
        CHECK(test::same_bits_nan_aside(
            bmfr_remodulate(params, fresh, albedo, e, test::unwritten_storage(19, 7, 3)), display));
        CHECK(test::same_bits_nan_aside(bmfr_linearize(display, test::unwritten_storage(19, 7, 3)),
                                        bmfr_linearize(display)));
    }
}

TEST_CASE(
    "bmfr phase I: the accept margins (bmfr_accept_margin) measure each test's distance "
    "from its limit, a tap exactly beyond the limit is rejected") {
    // A static camera; every pixel sees the point (0.35, 0.35, 1) and the history the point
    // moved by dz along the normal, so every tap's |P_k - P|^2 = dz^2 and the position margin
    // is |L^2 - dz^2| / L^2.
    const Camera camera = look_at({0.35f, 0.35f, 3.0f}, {0.35f, 0.35f, 1.0f}, {0, 1, 0}, 40.0f);
    WallFrame f = wall(8, 8, 0.0f, glm::vec3(0, 0, 1), 1.0f);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) f.world.at(x, y, 0) = f.world.at(x, y, 1) = 0.35f;
    BmfrParams params;
    BmfrStats stats;
    const Image illumination(8, 8, 3, 1.0f);
    BmfrHistory history;
    history.valid = true;
    history.view_projection = view_projection(camera, 8, 8);
    history.normal = f.normal;
    history.accumulated_noisy = illumination;
    history.spp = Image(8, 8, 1, 1.0f);
    const float limit2 = params.position_limit_squared;
    for (const float share : {0.25f, 0.81f, 1.21f}) {  // dz^2 = share x L^2
        history.world_position = f.world;
        const float dz = std::sqrt(share * limit2);
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x) history.world_position.at(x, y, 2) += dz;
        const BmfrAccumulation a =
            bmfr_accumulate_noisy(params, illumination, f.world, f.normal, history, stats);
        REQUIRE(a.accept_margin.channels == 3);
        const float dz2 = (1.0f + dz - 1.0f) * (1.0f + dz - 1.0f);
        CHECK(a.accept_margin.at(4, 4, 0) ==
              doctest::Approx(std::fabs(limit2 - dz2) / limit2).epsilon(1e-3));
        CHECK((a.accept.at(4, 4) != 0.0f) == (share < 1.0f));
        // the same normals: the normal test's margin is 1 (d^2 = 0) where it ran
        if (share < 1.0f) CHECK(a.accept_margin.at(4, 4, 1) == 1.0f);
        // the reprojected index's distance from the nearest integer (where the taps change)
        const float qx = a.previous_pixel.at(4, 4, 0), qy = a.previous_pixel.at(4, 4, 1);
        const float to_integer = std::min(
            {qx - std::floor(qx), std::ceil(qx) - qx, qy - std::floor(qy), std::ceil(qy) - qy});
        CHECK(a.accept_margin.at(4, 4, 2) == to_integer);
    }
    // Without a history no decision: the sentinel
    const BmfrAccumulation first =
        bmfr_accumulate_noisy(params, illumination, f.world, f.normal, BmfrHistory{}, stats);
    CHECK(first.accept_margin.at(4, 4, 0) == bmfr_no_margin);
}

TEST_CASE(
    "bmfr regularisation noise: the authors' Jenkins hash by default, Wang's on request "
    "(hand-computed in binary32)") {
    // seed = row + feature 1024 + frame 13 1024; r = hash(seed) / 4294967295.0f; noise =
    // 0.01 * 2 * (r - 0.5): values from an independent Python transcription
    CHECK(BmfrParams{}.noise_hash == BmfrNoiseHash::jenkins);
    CHECK(bmfr_regularisation_noise(0.01f, BmfrNoiseHash::jenkins, 0, 1, 0) == -0x1.2a2926p-8f);
    CHECK(bmfr_regularisation_noise(0.01f, BmfrNoiseHash::jenkins, 5, 3, 2) == -0x1.b7a6eap-9f);
    CHECK(bmfr_regularisation_noise(0.01f, BmfrNoiseHash::wang, 0, 1, 0) == 0x1.404dfcp-7f);
    CHECK(bmfr_regularisation_noise(0.01f, BmfrNoiseHash::wang, 5, 3, 2) == 0x1.d8bp-12f);
    // the parameter selects it, and refuses another name
    Params p;
    p.set("denoise", "bmfr");
    CHECK(parse_bmfr_params(p, "none").params.noise_hash == BmfrNoiseHash::jenkins);
    p.set("bmfr_noise_hash", "wang");
    CHECK(parse_bmfr_params(p, "none").params.noise_hash == BmfrNoiseHash::wang);
    p.set("bmfr_noise_hash", "pcg");
    CHECK_THROWS_WITH_AS(parse_bmfr_params(p, "none"), doctest::Contains("bmfr_noise_hash"), Error);
}

TEST_CASE(
    "bmfr remodulation: the authors' display exponent 0.454545 by default, 1/2.2 on "
    "request") {
    // 0.25^g by hand (binary64 of the binary32 exponents): 0.454545f = 0.45454499125...,
    // 1.0f / 2.2f = 0.45454543828...
    const Image filtered(1, 1, 3, 0.25f), albedo(1, 1, 3, 1.0f);
    BmfrParams params;
    CHECK(params.display_exponent == 0.454545f);
    const float authors = bmfr_remodulate(params, filtered, albedo, Image()).at(0, 0, 0);
    CHECK(authors == doctest::Approx(0.532520886735252).epsilon(1e-7));
    Params p;
    p.set("denoise", "bmfr");
    p.set("bmfr_gamma", "1/2.2");
    params = parse_bmfr_params(p, "none").params;
    CHECK(params.display_exponent == 1.0f / 2.2f);
    const float ours = bmfr_remodulate(params, filtered, albedo, Image()).at(0, 0, 0);
    CHECK(ours == doctest::Approx(0.5325205567205135).epsilon(1e-7));
    CHECK(ours < authors);
    p.set("bmfr_gamma", "2.2");
    CHECK_THROWS_WITH_AS(parse_bmfr_params(p, "none"), doctest::Contains("bmfr_gamma"), Error);
}

TEST_CASE(
    "bmfr_workgroup_sum: the authors' parallel_reduction_sum order, checked on sums that "
    "every other order rounds differently") {
    std::vector<float> partial(bmfr_workgroup_size, 0.0f);
    for (int t = 0; t < bmfr_workgroup_size; ++t) partial[static_cast<std::size_t>(t)] = 1.0f;
    CHECK(bmfr_workgroup_sum(partial.data()) == 256.0f);
    // step 1: s_0 + ((s_64 + s_128) + s_192): 1 + -1e8 rounds to -1e8 (the binary32 spacing
    // there is 8), so the 1 is lost; in row order (or binary64) the sum is 1
    std::fill(partial.begin(), partial.end(), 0.0f);
    partial[0] = 1e8f, partial[64] = 1.0f, partial[128] = -1e8f;
    CHECK(bmfr_workgroup_sum(partial.data()) == 0.0f);
    partial[64] = 0.0f, partial[192] = 1.0f;  // (0 + -1e8) + 1 = -1e8: lost again
    CHECK(bmfr_workgroup_sum(partial.data()) == 0.0f);
    partial[0] = 1.0f, partial[128] = 0.0f, partial[192] = 0.0f;
    partial[64] = 1e8f, partial[192] = -1e8f;  // 1 + ((1e8 + 0) + -1e8) = 1: kept
    CHECK(bmfr_workgroup_sum(partial.data()) == 1.0f);
    // step 2 for t < 8: s_t + (((s_t+8 + s_t+16) + ...) + s_t+56)
    std::fill(partial.begin(), partial.end(), 0.0f);
    partial[3] = 1.0f, partial[11] = 1e8f, partial[19] = -1e8f;  // 1 + ((1e8 - 1e8) + ...) = 1
    CHECK(bmfr_workgroup_sum(partial.data()) == 1.0f);
    partial[3] = 1e8f, partial[11] = 1.0f, partial[19] = -1e8f;  // 1e8 + ((1 - 1e8) ...) = 0
    CHECK(bmfr_workgroup_sum(partial.data()) == 0.0f);
    // step 3: ((((((s_0 + s_1) + s_2) + ...): 1e8 + 1 + -1e8 in t order loses the 1
    std::fill(partial.begin(), partial.end(), 0.0f);
    partial[0] = 1e8f, partial[1] = 1.0f, partial[2] = -1e8f;
    CHECK(bmfr_workgroup_sum(partial.data()) == 0.0f);
    partial[0] = 1e8f, partial[1] = -1e8f, partial[2] = 1.0f;  // (1e8 - 1e8) + 1 = 1
    CHECK(bmfr_workgroup_sum(partial.data()) == 1.0f);
}

TEST_CASE(
    "bmfr_sums=workgroup: the QR's sums in the authors' order change the weights' last bits "
    "only, the parameter selects it") {
    const WallFrame f = noisy_wall();
    const auto run = [&](BmfrSums sums) {
        BmfrParams params;
        params.sums = sums;
        return first_frame(params, f);
    };
    const BmfrFrame ours = run(BmfrSums::binary64), authors = run(BmfrSums::workgroup);
    CHECK_FALSE(bit_equal(ours.fit.weights, authors.fit.weights));
    double worst = 0.0;
    for (std::size_t i = 0; i < ours.fitted.data.size(); ++i)
        worst = std::max(
            worst, static_cast<double>(std::fabs(ours.fitted.data[i] - authors.fitted.data[i])));
    MESSAGE("binary64 vs workgroup sums: max |fitted difference| = " << worst);
    CHECK(worst > 0.0);
    CHECK(worst < 1e-3);
    Params p;
    p.set("denoise", "bmfr");
    CHECK(parse_bmfr_params(p, "none").params.sums == BmfrSums::binary64);
    p.set("bmfr_sums", "workgroup");
    CHECK(parse_bmfr_params(p, "none").params.sums == BmfrSums::workgroup);
    p.set("bmfr_sums", "float");
    CHECK_THROWS_WITH_AS(parse_bmfr_params(p, "none"),
                         doctest::Contains("'bmfr_sums': expected 'binary64' or 'workgroup'"),
                         Error);
}

TEST_CASE(
    "bmfr_remodulate: max(albedo, 0.01) by default (the demodulation's inverse), the albedo "
    "itself with 'albedo' (the authors' kernel)") {
    Image filtered(3, 1, 3, 0.25f), albedo(3, 1, 3);
    for (int ch = 0; ch < 3; ++ch) {
        albedo.at(0, 0, ch) = 0.0f;    // background: no albedo
        albedo.at(1, 0, ch) = 0.004f;  // below the floor
        albedo.at(2, 0, ch) = 0.5f;    // above it: the same either way
    }
    BmfrParams params;
    CHECK(params.remodulation_floor == 0.01f);
    const Image floor = bmfr_remodulate(params, filtered, albedo, Image());
    Params p;
    p.set("denoise", "bmfr");
    p.set("bmfr_remodulate", "albedo");
    params = parse_bmfr_params(p, "none").params;
    CHECK(params.remodulation_floor == 0.0f);
    const Image raw = bmfr_remodulate(params, filtered, albedo, Image());
    // (0.01 * 0.25)^0.454545 = 0.065652, (0.004 * 0.25)^0.454545 = 0.043288: by hand
    CHECK(floor.at(0, 0, 0) == doctest::Approx(0.065652).epsilon(1e-4));
    CHECK(floor.at(1, 0, 0) == floor.at(0, 0, 0));
    CHECK(raw.at(0, 0, 0) == 0.0f);
    CHECK(raw.at(1, 0, 0) == doctest::Approx(0.043288).epsilon(1e-4));
    CHECK(raw.at(2, 0, 1) == floor.at(2, 0, 1));
    p.set("bmfr_remodulate", "clamp");
    CHECK_THROWS_WITH_AS(parse_bmfr_params(p, "none"), doctest::Contains("bmfr_remodulate"), Error);
}
