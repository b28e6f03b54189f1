// TAA (ref/temporal/taa.h, SPEC §7) on hand-worked cases: the first frame, a stationary camera
// converging to the average of its frames, the age cap, reprojection of a pure rotation against
// the analytic projection, depth rejection and the periphery rule, neighbourhood clamping, and a
// non-finite history that never reaches the output.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "ref/temporal/taa.h"
#include "tests/image/image_test_util.h"

using namespace fovref;

namespace {

Image random_color(int w, int h, test::SplitMix64& rng) {
    Image image(w, h, 3, 0.0f);
    for (float& v : image.data) v = static_cast<float>(rng.below(1 << 16)) * 0x1p-16f;
    return image;
}

struct Frame {
    Image out, age;
    TaaStats stats;
};

Frame run_taa(const TaaParams& p, const Image& color, const Image& depth, const Camera& camera,
              const TaaState& previous, glm::vec2 gaze = {0.0f, 0.0f}) {
    Frame f;
    taa(p, {color, depth, camera, gaze}, previous, f.out, f.age, f.stats);
    return f;
}

Camera yawed(float degrees) {
    const double a = degrees * 3.14159265358979323846 / 180.0;
    const glm::vec3 forward{static_cast<float>(-std::sin(a)), 0.0f,
                            static_cast<float>(-std::cos(a))};
    return look_at({0.0f, 1.0f, 4.0f}, glm::vec3{0.0f, 1.0f, 4.0f} + forward, {0, 1, 0}, 40.0f);
}

// A 30 x 30 frame whose camera moved 0.5 forward: a surface at current depth 2 was at previous
// depth 2.5; colour 0.25 now, history 0.75 of age 4 (the history's depth set by each test).
struct ForwardStep {
    static constexpr int w = 30, h = 30;
    Camera previous = yawed(0.0f), camera = moved(previous);
    Image color{w, h, 3, 0.25f}, depth{w, h, 1, 2.0f};
    TaaState state = history(previous);

    static Camera moved(Camera c) {
        c.position += 0.5f * c.forward;
        return c;
    }
    static TaaState history(const Camera& previous) {
        TaaState s;
        s.valid = true;
        s.camera = previous;
        s.history = Image(w, h, 3, 0.75f);
        s.age = Image(w, h, 1, 4.0f);
        return s;
    }
};

}  // namespace

TEST_CASE("TAA: the first frame is the current frame with age 1") {
    test::SplitMix64 rng(1);
    const Image color = random_color(8, 5, rng);
    const Image depth(8, 5, 1, 2.0f);
    const Frame f = run_taa({}, color, depth, yawed(0.0f), {});
    CHECK(f.out == color);
    CHECK(f.age == Image(8, 5, 1, 1.0f));
}

TEST_CASE("TAA: a stationary camera averages its frames, the age stops at the cap") {
    // out_k = out_(k-1) (1 - 1/k) + c_k / k is the running mean of c_1 .. c_k while k <= 20:
    // after 16 frames the output is the mean of the 16 within the rounding of 16 float updates
    // (each within 2 ulp of its exact value: |error| <= 16 * 2 * 2^-24 relative to values <= 1).
    test::SplitMix64 rng(2);
    const int w = 6, h = 4;
    const Camera camera = yawed(10.0f);
    const Image depth(w, h, 1, 3.0f);
    TaaState state;
    std::vector<double> sum(static_cast<std::size_t>(w) * h * 3, 0.0);
    Frame f;
    for (int k = 1; k <= 16; ++k) {
        const Image color = random_color(w, h, rng);
        for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += color.data[i];
        f = run_taa({}, color, depth, camera, state);
        if (k > 1) CHECK(f.stats.reprojection_skipped == w * h);
        if (k > 1) CHECK(f.stats.kept == w * h);
        state = next_taa_state(f.out, f.age, depth, camera);
    }
    CHECK(f.age == Image(w, h, 1, 16.0f));
    double worst = 0.0;
    for (std::size_t i = 0; i < sum.size(); ++i)
        worst = std::max(worst, std::fabs(f.out.data[i] - sum[i] / 16.0));
    MESSAGE("worst |TAA - mean of 16 frames| = ", worst);
    CHECK(worst <= 16 * 2 * 0x1p-24);
    // 30 frames: the age stays at 20, the weight of the new frame is 1/20.
    for (int k = 17; k <= 30; ++k) {
        f = run_taa({}, random_color(w, h, rng), depth, camera, state);
        state = next_taa_state(f.out, f.age, depth, camera);
    }
    CHECK(f.age == Image(w, h, 1, 20.0f));
    const Image color = random_color(w, h, rng);
    const Frame g = run_taa({}, color, depth, camera, state);
    const float expected =
        state.history.at(2, 1, 0) * (1.0f - 1.0f / 20.0f) + color.at(2, 1, 0) * (1.0f / 20.0f);
    CHECK(g.out.at(2, 1, 0) == expected);
}

TEST_CASE("TAA: reprojection of a pure rotation matches the analytic projection at any depth") {
    const int w = 64, h = 36;
    const Camera previous = yawed(0.0f), camera = yawed(7.5f);
    const double tan_half = std::tan(20.0 * 3.14159265358979323846 / 180.0);
    for (const auto& pixel : {std::pair{32, 18}, std::pair{5, 30}, std::pair{60, 2}})
        for (const float z : {0.5f, 3.0f, 40.0f}) {
            const int x = pixel.first, y = pixel.second;
            glm::vec2 q;
            float depth = 0.0f;
            REQUIRE(taa_reproject(camera, tan_half_vfov(camera), previous, tan_half_vfov(previous),
                                  w, h, x, y, z, q, depth));
            // The pixel's direction in binary64, then the previous camera's projection.
            const double sx = (2.0 * (x + 0.5) / w - 1.0) * tan_half * w / h;
            const double sy = (2.0 * (y + 0.5) / h - 1.0) * tan_half;
            const glm::dvec3 F(camera.forward), R(camera.right), U(camera.up);
            const glm::dvec3 d = F + sx * R - sy * U;
            const glm::dvec3 F0(previous.forward), R0(previous.right), U0(previous.up);
            const double qx =
                (glm::dot(d, R0) / glm::dot(d, F0) / (tan_half * w / h) + 1.0) * w / 2;
            const double qy = (1.0 - glm::dot(d, U0) / glm::dot(d, F0) / tan_half) * h / 2;
            INFO("pixel ", x, ",", y, " z ", z);
            CHECK(std::fabs(q.x - qx) <= 2e-3);  // float path, 64 px wide: a few ulp of the ray
            CHECK(std::fabs(q.y - qy) <= 2e-3);
        }
}

TEST_CASE("TAA: depth rejection where the depth changes, the periphery rule beyond diagonal / 3") {
    // The camera moves 0.5 forward: a surface at current depth 2 was at previous depth 2.5.
    ForwardStep f0;
    const int w = ForwardStep::w, h = ForwardStep::h;
    const Camera& camera = f0.camera;
    const Image &color = f0.color, &depth = f0.depth;
    TaaState& state = f0.state;
    const glm::vec2 gaze{15.0f, 15.0f};
    // History depth 2.5 (what the previous camera saw there): kept; the blend with age 5.
    state.depth = Image(w, h, 1, 2.5f);
    Frame f = run_taa({}, color, depth, camera, state, gaze);
    CHECK(f.stats.kept == w * h);
    CHECK(f.age.at(15, 15) == 5.0f);
    CHECK(f.out.at(15, 15, 0) == 0.75f * (1.0f - 0.2f) + 0.25f * 0.2f);
    // History depth 4 (another surface): rejected near the gaze (the current pixel, age 1), kept
    // with age 2 beyond diagonal / 3 = 14.1 px from it (a corner pixel is 20.5 px away).
    state.depth = Image(w, h, 1, 4.0f);
    f = run_taa({}, color, depth, camera, state, gaze);
    CHECK(f.out.at(15, 15, 1) == 0.25f);
    CHECK(f.age.at(15, 15) == 1.0f);
    CHECK(f.age.at(0, 0) == 2.0f);
    CHECK(f.out.at(0, 0, 2) == 0.75f * 0.5f + 0.25f * 0.5f);
    CHECK(f.stats.rejected > 0);
    CHECK(f.stats.periphery_kept > 0);
    CHECK(f.stats.rejected + f.stats.periphery_kept == w * h);
    // Within tau = 1%: 2.52 against 2.5 is kept; 2.53 is not.
    state.depth = Image(w, h, 1, 2.52f);
    CHECK(run_taa({}, color, depth, camera, state, gaze).stats.kept == w * h);
    state.depth = Image(w, h, 1, 2.53f);
    CHECK(run_taa({}, color, depth, camera, state, gaze).stats.kept == 0);
    // No surface at the pixel (depth 0): nothing to reproject, rejected.
    f = run_taa({}, color, Image(w, h, 1, 0.0f), camera, state, gaze);
    CHECK(f.stats.rejected == w * h);
}

TEST_CASE("TAA: clamping keeps the history inside the current 3x3 neighbourhood") {
    const int w = 5, h = 5;
    Camera previous = yawed(0.0f), camera = previous;
    camera.position += 0.1f * camera.right;
    Image color(w, h, 3, 0.5f);
    color.at(1, 2, 0) = 0.25f;  // neighbourhood of (2, 2): red in [0.25, 0.6]
    color.at(3, 3, 0) = 0.6f;
    TaaState state;
    state.valid = true;
    state.camera = previous;
    state.history = Image(w, h, 3, 0.9f);
    state.age = Image(w, h, 1, 1.0f);
    state.depth = Image(w, h, 1, 100.0f);  // inconsistent: clamping ignores depth
    TaaParams p;
    p.rejection = TaaRejection::clamp;
    const Image depth(w, h, 1, 2.0f);
    const Frame f = run_taa(p, color, depth, camera, state);
    Image out(w, h, 3, 0.0f), age(w, h, 1, 0.0f);
    const TaaPixelRecord r = taa_pixel(p, {color, depth, camera, {}}, state, 2, 2, out, age);
    CHECK(out.at(2, 2, 0) == f.out.at(2, 2, 0));
    CHECK(r.decision == TaaDecision::clamped);
    CHECK(r.history.x == 0.6f);  // red: the neighbourhood's max
    CHECK(r.history.y == 0.5f);  // green: all 0.5
    CHECK(f.age.at(2, 2) == 2.0f);
    CHECK(f.out.at(2, 2, 1) == 0.5f * 0.5f + 0.5f * 0.5f);
    CHECK(f.stats.clamped > 0);
}

TEST_CASE("TAA: a non-finite history never reaches the output") {
    const int w = 4, h = 3;
    const Camera camera = yawed(0.0f);
    const Image color(w, h, 3, 0.5f), depth(w, h, 1, 2.0f);
    TaaState state = next_taa_state(Image(w, h, 3, 0.1f), Image(w, h, 1, 3.0f), depth, camera);
    state.history.at(1, 1, 2) = std::numeric_limits<float>::quiet_NaN();
    state.history.at(2, 1, 0) = std::numeric_limits<float>::infinity();
    state.age.at(3, 2) = std::numeric_limits<float>::infinity();
    const Frame f = run_taa({}, color, depth, camera, state);
    for (const float v : f.out.data) CHECK(std::isfinite(v));
    CHECK(f.out.at(1, 1, 2) == 0.5f);
    CHECK(f.out.at(2, 1, 0) == 0.5f);
    CHECK(f.stats.nonfinite_history == 3);
    CHECK(f.stats.rejected == 3);
}

TEST_CASE("TAA: a non-finite depth, previous or current, is rejected, also in the periphery") {
    // A moving camera, the gaze far away so that every pixel is beyond the periphery radius: a
    // NaN previous depth fails the depth test, which the flicker rule would otherwise keep.
    const int w = 4, h = 3;
    const Camera previous = yawed(0.0f), camera = yawed(0.5f);
    const Image color(w, h, 3, 0.5f);
    Image depth(w, h, 1, 2.0f);
    depth.at(0, 0) = std::numeric_limits<float>::infinity();
    TaaState state =
        next_taa_state(Image(w, h, 3, 0.1f), Image(w, h, 1, 3.0f),
                       Image(w, h, 1, std::numeric_limits<float>::quiet_NaN()), previous);
    const Frame f = run_taa({}, color, depth, camera, state, {1000.0f, 1000.0f});
    for (const float v : f.out.data) CHECK(v == 0.5f);
    CHECK(f.stats.periphery_kept == 0);
    CHECK(f.stats.rejected == w * h);
    CHECK(f.stats.nonfinite_history == w * h);
}

TEST_CASE("TAA: bilinear history samples renormalise over the taps on the screen") {
    Image image(3, 2, 1, 0.0f);
    image.at(0, 0) = 1.0f;
    image.at(1, 0) = 3.0f;
    image.at(0, 1) = 5.0f;
    image.at(1, 1) = 7.0f;
    float v = 0.0f;
    CHECK(taa_sample(image, {1.0f, 1.0f}, &v) == 1.0f);  // the four taps, equal weights
    CHECK(v == 4.0f);
    CHECK(taa_sample(image, {0.5f, 0.5f}, &v) == 1.0f);  // a pixel centre: that pixel
    CHECK(v == 1.0f);
    CHECK(taa_sample(image, {0.25f, 0.5f}, &v) == 0.75f);  // a tap off screen: dropped
    CHECK(v == 1.0f);
    CHECK(taa_sample(image, {-5.0f, 1.0f}, &v) == 0.0f);  // nothing on screen
    CHECK(taa_sample(image, {1e30f, 1.0f}, &v) == 0.0f);
    CHECK(taa_sample(image, {std::numeric_limits<float>::quiet_NaN(), 1.0f}, &v) == 0.0f);
}

// The stationary-camera rule (no reprojection when the camera has not moved) against the same
// frame with the rule turned off (the frame's constants say "not stationary"), depth rejection:
// the reprojection of a static camera lands within 1e-5 px of each pixel centre but not always
// exactly on it (measured: within 1.9e-6 px), so the bilinear history mixes in that much of a
// neighbour and the output differs from the rule's exact history read by at most that much
// (here ~1e-6, the history being random); ages and decisions agree.
// So the rule is not a pure skip: it is the exact answer the reprojection approximates
// (docs/temporal.md). Sky pixels (depth 0), whose history the rule keeps and the reprojection
// rejects, are excluded and counted.
TEST_CASE("TAA: the stationary rule agrees with reprojection to 2e-6 (depth mode)") {
    test::SplitMix64 rng(7);
    const int w = 40, h = 24;
    const Camera camera = yawed(20.0f);
    Image depth(w, h, 1, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            depth.at(x, y) = (x + y) % 11 == 0 ? 0.0f
                                               : 2.0f + 0.37f * static_cast<float>(x) +
                                                     0.11f * static_cast<float>(y);
    TaaState previous;
    previous.valid = true;
    previous.history = random_color(w, h, rng);
    previous.age = Image(w, h, 1, 3.0f);
    previous.depth = depth;
    previous.camera = camera;
    const Image color = random_color(w, h, rng);
    const TaaInputs in{color, depth, camera, {20.0f, 12.0f}};
    const TaaConstants rule = taa_constants(in, previous);
    REQUIRE(rule.stationary);
    TaaConstants reproject = rule;
    reproject.stationary = false;
    const TaaParams params;  // depth rejection
    Image out_rule(w, h, 3), age_rule(w, h, 1), out_full(w, h, 3), age_full(w, h, 1);
    int compared = 0, sky = 0, differ = 0;
    double offset = 0.0, largest = 0.0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            taa_pixel(params, in, previous, x, y, out_rule, age_rule, &rule);
            const TaaPixelRecord r =
                taa_pixel(params, in, previous, x, y, out_full, age_full, &reproject);
            if (depth.at(x, y) == 0.0f) {
                ++sky;
                continue;
            }
            ++compared;
            CHECK(r.decision == TaaDecision::kept);
            CHECK(age_rule.at(x, y) == age_full.at(x, y));
            offset = std::max(offset, std::fabs(r.previous_point.x - (x + 0.5)));
            offset = std::max(offset, std::fabs(r.previous_point.y - (y + 0.5)));
            bool same = true;
            for (int c = 0; c < 3; ++c) {
                const float a = out_rule.at(x, y, c), b = out_full.at(x, y, c);
                same = same && a == b;
                largest = std::max(largest, std::fabs(static_cast<double>(a) - b));
            }
            differ += same ? 0 : 1;
        }
    MESSAGE("stationary rule vs reprojection: "
            << differ << " of " << compared << " pixels differ, by at most " << largest
            << "; reprojection within " << offset << " px of the centres");
    CHECK(offset < 1e-5);
    // the history is random in [0, 1): a neighbour mixed in with weight <= offset moves it by
    // at most offset, times (1 - 1/age) in the blend
    CHECK(largest <= offset + 1e-7);
    CHECK(compared > 800);
    CHECK(sky > 50);
}

TEST_CASE(
    "TAA: the decision margins (taa_margin): their sign is the decision, their size the "
    "distance from the threshold") {
    // As above: the camera moves 0.5 forward, a surface at depth 2 was at 2.5 (tau = 1%).
    ForwardStep f0;
    const int w = ForwardStep::w, h = ForwardStep::h;
    const Camera& camera = f0.camera;
    const Image &color = f0.color, &depth = f0.depth;
    TaaState& state = f0.state;
    for (const float history_depth : {2.5f, 2.52f, 2.53f, 4.0f}) {
        state.depth = Image(w, h, 1, history_depth);
        Image out, age, margin;
        TaaStats stats;
        taa({}, {color, depth, camera, {15.0f, 15.0f}}, state, out, age, stats, &margin);
        REQUIRE(margin.channels == 2);
        // The centre pixel reprojects to about the centre (z' = 2.5): (0.01 z' - |z' - z_h|) / z'
        const float z = 2.5f;
        CHECK(margin.at(15, 15, 0) ==
              doctest::Approx((0.01f * z - std::fabs(z - history_depth)) / z).epsilon(1e-3));
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                // kept by the depth test exactly where its margin is >= 0
                const float dx = static_cast<float>(x) + 0.5f - 15.0f;
                const float dy = static_cast<float>(y) + 0.5f - 15.0f;
                const bool near_gaze = std::sqrt(dx * dx + dy * dy) <= 14.0f;
                if (near_gaze) CHECK((age.at(x, y) > 1.0f) == (margin.at(x, y, 0) >= 0.0f));
                // the reprojected point lies on the screen, at most 15.5 px from the border
                CHECK(margin.at(x, y, 1) > 0.0f);
                CHECK(margin.at(x, y, 1) <= 15.5f);
            }
    }
    // Clamp rejection makes no depth decision; the first frame none at all.
    TaaParams clamp;
    clamp.rejection = TaaRejection::clamp;
    Image out, age, margin;
    TaaStats stats;
    taa(clamp, {color, depth, camera, {15.0f, 15.0f}}, state, out, age, stats, &margin);
    CHECK(margin.at(3, 4, 0) == taa_no_margin);
    CHECK(margin.at(3, 4, 1) < taa_no_margin);
    taa({}, {color, depth, camera, {15.0f, 15.0f}}, TaaState{}, out, age, stats, &margin);
    CHECK(margin.at(3, 4, 0) == taa_no_margin);
    CHECK(margin.at(3, 4, 1) == taa_no_margin);
}
