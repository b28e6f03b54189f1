// TAA in the modes (ref/temporal/stages.h, SPEC §6-7): sequences of basic, cfov, kfr, ckfov and
// stereo-lp with each TAA variant. A static camera converges to the mean of its 16 jittered frames;
// a moving camera turns the jitter off; the first frame is the current frame; resuming from the
// previous frame's buffers gives the bits of the whole sequence; a disocclusion is rejected where
// the depth changes and kept where it does not; the buffer-space clamp box holds pass 2's value;
// the TAA depth of a composite mode is the gaze buffer's (= basic's) inside the gaze circle.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>

#include "ref/core/halton.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "ref/temporal/taa.h"
#include "tests/stage/mode_test_util.h"

using namespace fovref;

namespace {

using test::buffer;
using test::scene_named;

std::vector<FrameResult> render_sequence(const std::string& scene, const std::string& mode,
                                         int frames, float time_step,
                                         std::map<std::string, std::string> params,
                                         int first_frame = 0, std::vector<Buffer> state = {},
                                         int width = 64, int height = 36) {
    return test::render_all(scene, mode, width, height, frames, std::move(params), time_step,
                            first_frame, std::move(state));
}

using test::same_bits;

// 64 x 36, `frames` frames of a static camera, TAA with depth rejection (the render's settings).
RenderSettings static_depth_taa(int frames) {
    RenderSettings s;
    s.width = 64;
    s.height = 36;
    s.frame_count = frames;
    s.time_step = 0.0f;
    s.params.set("taa", "depth");
    return s;
}

}  // namespace

TEST_CASE("TAA modes: a static camera converges to the mean of its 16 jittered frames") {
    // checker-room's textured checker floor: with the camera still, frame k (k < 16 < the age
    // cap) outputs the running mean of the k + 1 shaded frames. 16 float updates, each within
    // 2 ulp of exact: |output - mean| <= 16 * 2 * 2^-24 * max(1, |values|) < 4e-6.
    for (const char* mode : {"basic", "cfov", "stereo-lp"}) {
        CAPTURE(mode);
        const std::vector<FrameResult> frames =
            render_sequence("checker-room", mode, 16, 0.0f, {{"taa", "depth"}});
        const std::string input = std::string(mode) == "basic" ? "shaded" : "resolved";
        const Image& out = buffer(frames[15], "final");
        double worst = 0.0, spread = 0.0;
        for (std::size_t i = 0; i < out.data.size(); ++i) {
            double sum = 0.0, lo = 1e30, hi = -1e30;
            for (const FrameResult& f : frames) {
                const double v = buffer(f, input).data[i];
                sum += v;
                lo = std::min(lo, v);
                hi = std::max(hi, v);
            }
            worst = std::max(worst, std::fabs(out.data[i] - sum / 16.0));
            spread = std::max(spread, hi - lo);
        }
        CHECK(worst < 4e-6);
        CHECK(spread > 0.05);  // the jitter moves the rays: the frames differ (checker edges)
        for (int k = 0; k < 16; ++k) {
            CAPTURE(k);
            CHECK(frames[k].counters.get("taa_jitter_index") == k);
            CHECK(frames[k].counters.get("taa_reprojection_skipped") == (k == 0 ? 0 : 64 * 36));
            CHECK(buffer(frames[k], "taa_age") == Image(64, 36, 1, static_cast<float>(k + 1)));
        }
    }
}

TEST_CASE("TAA modes: the first frame is the current frame, a moving camera has no jitter") {
    const std::map<std::string, std::string> none;
    for (const char* mode : {"basic", "cfov", "kfr", "stereo-lp"}) {
        for (const char* variant : {"depth", "clamp-screen", "clamp-buffer"}) {
            if (std::string(mode) == "basic" && std::string(variant) == "clamp-buffer") continue;
            CAPTURE(mode);
            CAPTURE(variant);
            const std::vector<FrameResult> taa =
                render_sequence("checker-room", mode, 3, 0.1f, {{"taa", variant}});
            const std::vector<FrameResult> plain =
                render_sequence("checker-room", mode, 3, 0.1f, none);
            const std::string input = std::string(mode) == "basic" ? "shaded" : "resolved";
            const std::string output = taa[0].find("taa_color") != nullptr ? "taa_color" : "final";
            CHECK(same_bits(buffer(taa[0], output), buffer(taa[0], input)));
            CHECK(buffer(taa[0], "taa_age") == Image(64, 36, 1, 1.0f));
            // Frame 0 counts as stationary (jittered, Halton point 0); frames 1 and 2 move: no
            // jitter, so their pass-2 image equals the render without TAA bit for bit.
            CHECK(taa[0].counters.get("taa_jitter_index") == 0);
            // Pass 2's output without TAA: "resolved" when a filter follows, else "final".
            const std::string plain_name = plain[0].find("resolved") ? "resolved" : "final";
            CHECK_FALSE(same_bits(buffer(taa[0], input), buffer(plain[0], plain_name)));
            for (int k = 1; k < 3; ++k) {
                CAPTURE(k);
                CHECK(taa[k].counters.get("taa_jitter_index") == -1);
                CHECK(taa[k].counters.get("taa_reprojection_skipped") == 0);
                CHECK(same_bits(buffer(taa[k], input), buffer(plain[k], plain_name)));
            }
        }
    }
}

TEST_CASE("TAA modes: resuming from the previous frame's buffers gives the sequence's bits") {
    const std::pair<const char*, const char*> cases[] = {{"basic", "clamp-screen"},
                                                         {"cfov", "clamp-buffer"},
                                                         {"kfr", "depth"},
                                                         {"ckfov", "depth"},
                                                         {"stereo-lp", "clamp-buffer"}};
    for (const auto& c : cases) {
        const std::string mode = c.first;
        const std::map<std::string, std::string> params = {{"taa", c.second}};
        CAPTURE(mode);
        // A static start (jittered frames), then the camera moves: time step 0.1 from frame 0.
        const std::vector<FrameResult> whole =
            render_sequence("checker-room", mode, 5, 0.1f, params);
        const std::vector<FrameResult> resumed =
            render_sequence("checker-room", mode, 2, 0.1f, params, 3, whole[2].buffers);
        REQUIRE(resumed.size() == 2);
        for (int k = 0; k < 2; ++k) {
            const FrameResult& a = whole[static_cast<std::size_t>(3 + k)];
            const FrameResult& b = resumed[static_cast<std::size_t>(k)];
            CHECK(b.frame == a.frame);
            REQUIRE(a.buffers.size() == b.buffers.size());
            for (std::size_t i = 0; i < a.buffers.size(); ++i) {
                CAPTURE(a.buffers[i].name);
                CHECK(same_bits(a.buffers[i].image, b.buffers[i].image));
            }
        }
        // Without the previous frame's state the render refuses, naming --resume.
        CHECK_THROWS_WITH_AS(render_sequence("checker-room", mode, 1, 0.1f, params, 3),
                             doctest::Contains("--resume"), Error);
    }
    // A static camera: the resumed frames are jittered (Halton point (f + 5) mod 16) and take
    // the stationary path.
    for (const char* mode : {"basic", "cfov", "kfr", "stereo-lp"}) {
        CAPTURE(mode);
        const std::map<std::string, std::string> params = {{"taa", "depth"},
                                                           {"taa_jitter_start", "5"}};
        const std::vector<FrameResult> whole =
            render_sequence("checker-room", mode, 5, 0.0f, params);
        const std::vector<FrameResult> resumed =
            render_sequence("checker-room", mode, 2, 0.0f, params, 3, whole[2].buffers);
        for (int k = 0; k < 2; ++k) {
            const FrameResult& a = whole[static_cast<std::size_t>(3 + k)];
            const FrameResult& b = resumed[static_cast<std::size_t>(k)];
            CHECK(b.counters.get("taa_jitter_index") == 8 + k);
            CHECK(b.counters.get("taa_reprojection_skipped") == 64 * 36);
            REQUIRE(a.buffers.size() == b.buffers.size());
            for (std::size_t i = 0; i < a.buffers.size(); ++i) {
                CAPTURE(a.buffers[i].name);
                CHECK(same_bits(a.buffers[i].image, b.buffers[i].image));
            }
        }
    }
}

// The history is the previous frame's output buffer itself (FrameContext::carried), not a copy:
// render_each hands it back after the frame's callback, and the pass writes the next output into
// the storage of the history before; the bits are those of render(), which keeps copies of the
// frames (that they are those of the copies TAA kept before is the goldens' check: they were made
// with them). A callback that moves the output away leaves TAA without its history: a clear
// error.
TEST_CASE("TAA modes: the history is the previous frame's output, handed back, never copied") {
    for (const char* mode : {"basic", "cfov"}) {
        CAPTURE(mode);
        const RenderSettings s = static_depth_taa(4);
        const std::vector<FrameResult> kept = render(&scene_named("checker-room"), mode, s);
        std::vector<const float*> storage;
        render_each(&scene_named("checker-room"), find_mode(mode), s, [&](FrameResult& f) {
            CAPTURE(f.frame);
            const Image& out = buffer(f, "final");
            CHECK(same_bits(out, buffer(kept.at(static_cast<std::size_t>(f.frame)), "final")));
            storage.push_back(out.data.data());
        });
        REQUIRE(storage.size() == 4);
        CHECK(storage[2] == storage[0]);  // two images take turns: output, then history
        CHECK(storage[3] == storage[1]);
        CHECK(storage[1] != storage[0]);
        CHECK_THROWS_WITH_AS(
            render_each(&scene_named("checker-room"), find_mode(mode), s,
                        [](FrameResult& f) {
                            for (Buffer& b : f.buffers)
                                if (b.name == "final") Image taken = std::move(b.image);
                        }),
            doctest::Contains("TAA's history, the previous frame's buffer 'final', was not "
                              "handed back"),
            Error);
    }
}

// A carried buffer comes back as its stage wrote it, not as a later stage's read left it: a NaN
// and an infinity written into TAA's output after the stage (the render's after_stage hook, as a
// blend that overflowed would write one) are replaced by 0 where the Gaussian lerp reads them,
// yet the next frame's TAA finds them in its history and rejects those two pixels.
TEST_CASE("TAA modes: the history is the output as TAA wrote it, not as the lerp's read left it") {
    RenderSettings s = static_depth_taa(2);
    s.params.set("filters", "lerp");
    s.after_stage = [](const std::string& stage, FrameResult& result) {
        if (stage != "taa" || result.frame != 0) return;
        for (Buffer& b : result.buffers)
            if (b.name == "taa_color") {
                b.image.data[0] = std::nanf("");
                b.image.data[3 * 10 + 1] = INFINITY;
            }
    };
    const std::vector<FrameResult> frames = render(&scene_named("checker-room"), "cfov", s);
    REQUIRE(frames.size() == 2);
    CHECK(frames[0].counters.get("nonfinite_stage_inputs") == 2);  // the lerp read zeros
    CHECK(frames[1].counters.get("taa_history_nonfinite") == 2);
    CHECK(frames[1].counters.get("taa_history_rejected") == 2);
}

TEST_CASE("TAA modes: a disocclusion is rejected where the depth changes, kept where it does not") {
    // cornell with the camera moving 0.5 s of its path in one frame: the boxes uncover the walls
    // behind them. The primitive ids (which TAA never reads) say what the history shows: a
    // pixel whose four history taps saw its own triangle at its reprojected depth must be kept
    // (age 2); one whose four taps all saw other triangles at a depth more than 5 % away must be
    // rejected (age 1). The periphery rule is moved off the screen.
    const std::vector<FrameResult> f = render_sequence(
        "cornell", "basic", 2, 0.5f, {{"taa", "depth"}, {"taa_periphery", "100"}}, 0, {}, 160, 90);
    const Image& depth = buffer(f[1], "gbuffer_view_depth");
    const Image& id = buffer(f[1], "gbuffer_primitive_id");
    const Image& previous_id = buffer(f[0], "gbuffer_primitive_id");
    const Image& previous_depth = buffer(f[0], "gbuffer_view_depth");
    const Image& age = buffer(f[1], "taa_age");
    const Camera& camera = *f[1].camera;
    const Camera& previous = *f[0].camera;
    REQUIRE_FALSE(camera == previous);
    int kept = 0, rejected = 0, wrong = 0;
    for (int y = 0; y < depth.height; ++y)
        for (int x = 0; x < depth.width; ++x) {
            const float z = depth.at(x, y);
            if (!(z > 0.0f)) continue;
            glm::vec2 q;
            float zq = 0.0f;
            if (!taa_reproject(camera, tan_half_vfov(camera), previous, tan_half_vfov(previous),
                               depth.width, depth.height, x, y, z, q, zq))
                continue;
            const int x0 = static_cast<int>(std::floor(q.x - 0.5f));
            const int y0 = static_cast<int>(std::floor(q.y - 0.5f));
            if (x0 < 0 || y0 < 0 || x0 + 1 >= depth.width || y0 + 1 >= depth.height) continue;
            bool all_same = true, all_other = true;
            for (int k = 0; k < 4; ++k) {
                const int tx = x0 + (k & 1), ty = y0 + (k >> 1);
                const bool same = previous_id.at(tx, ty) == id.at(x, y);
                const float dz = std::fabs(previous_depth.at(tx, ty) - zq);
                all_same = all_same && same && dz <= 0.002f * zq;
                all_other = all_other && !same && dz > 0.05f * zq;
            }
            if (all_same) {
                ++kept;
                if (age.at(x, y) != 2.0f) ++wrong;
            } else if (all_other) {
                ++rejected;
                if (age.at(x, y) != 1.0f) ++wrong;
            }
        }
    CHECK(kept > 200);
    CHECK(rejected > 20);
    CHECK(wrong == 0);
}

TEST_CASE(
    "TAA modes: the buffer-space clamp box holds pass 2's value, the depth is the gaze "
    "buffer's inside the circle") {
    // kfr's mip resolve can lie outside the level-0 box: the box is widened to hold it.
    {
        const std::vector<FrameResult> kfr = render_sequence(
            "checker-room", "kfr", 2, 0.1f, {{"taa", "clamp-buffer"}}, 0, {}, 160, 90);
        const Image& bounds = buffer(kfr[1], "taa_bounds");
        const Image& resolved = buffer(kfr[1], "resolved");
        int outside = 0;
        for (int y = 0; y < resolved.height; ++y)
            for (int x = 0; x < resolved.width; ++x)
                for (int c = 0; c < 3; ++c)
                    if (!(bounds.at(x, y, c) <= resolved.at(x, y, c) &&
                          resolved.at(x, y, c) <= bounds.at(x, y, 3 + c)))
                        ++outside;
        CHECK(outside == 0);
        CHECK(kfr[1].find("taa_view_depth") == nullptr);  // kfr reads its G-buffer's depth
    }
    const std::vector<FrameResult> f =
        render_sequence("checker-room", "cfov", 2, 0.1f, {{"taa", "clamp-buffer"}}, 0, {}, 160, 90);
    const std::vector<FrameResult> basic =
        render_sequence("checker-room", "basic", 2, 0.1f, {}, 0, {}, 160, 90);
    // Bilinear pass 2 lies inside the unwidened box: every bound is the value of a texel of the
    // buffer or the gaze buffer (widening would have put pass 2's own value there instead).
    const Image& bounds = buffer(f[1], "taa_bounds");
    const Image& resolved = buffer(f[1], "resolved");
    std::set<float> texel_values[3];
    for (const char* name : {"lp_color", "gaze_color"}) {
        const Image& image = buffer(f[1], name);
        for (std::size_t i = 0; i < image.data.size(); ++i)
            texel_values[i % 3].insert(image.data[i]);
    }
    int outside = 0, not_texel = 0;
    for (int y = 0; y < resolved.height; ++y)
        for (int x = 0; x < resolved.width; ++x)
            for (int c = 0; c < 3; ++c) {
                const float v = resolved.at(x, y, c);
                if (v < bounds.at(x, y, c) || v > bounds.at(x, y, 3 + c)) ++outside;
                if (texel_values[c].count(bounds.at(x, y, c)) == 0 ||
                    texel_values[c].count(bounds.at(x, y, 3 + c)) == 0)
                    ++not_texel;
            }
    CHECK(outside == 0);
    CHECK(not_texel == 0);
    CHECK(f[1].counters.get("taa_history_clamped") > 0);
    // The TAA depth: the gaze buffer's own pixel inside the circle, which is basic's bit for bit
    // (no jitter: the camera moves); elsewhere the nearest traced texel's.
    const Image& z = buffer(f[1], "taa_view_depth");
    const Image& zb = buffer(basic[1], "gbuffer_view_depth");
    const Image& gaze_valid = buffer(f[1], "gaze_valid");
    const auto x0 = static_cast<int>(f[1].counters.get("gaze_window_x0"));
    const auto y0 = static_cast<int>(f[1].counters.get("gaze_window_y0"));
    int inside = 0, near = 0, far = 0;
    for (int y = 0; y < z.height; ++y)
        for (int x = 0; x < z.width; ++x) {
            const int i = x - x0, j = y - y0;
            if (i >= 0 && j >= 0 && i < gaze_valid.width && j < gaze_valid.height &&
                gaze_valid.at(i, j) != 0.0f) {
                ++inside;
                const float a = z.at(x, y), b = zb.at(x, y);
                CHECK(std::memcmp(&a, &b, sizeof a) == 0);
            } else if (std::fabs(z.at(x, y) - zb.at(x, y)) <= 0.1f * zb.at(x, y)) {
                ++near;
            } else {
                ++far;
            }
        }
    // Outside the circle the texels grow with the eccentricity: within 10 % of basic's depth
    // except across depth edges, where the nearest texel lies on the other surface (measured at
    // 160x90: 13 566 within, 46 not).
    CHECK(inside > 100);
    CHECK(far * 100 < near);
}

TEST_CASE(
    "TAA modes: kfr's jittered rasterizer supersamples a static camera: the error against "
    "the 16-sample ground truth falls with the frames") {
    // Meng/Karis: the rasterized G-buffer samples at the frame's Halton point, each texel copies
    // the pixel whose jittered sample is nearest, and TAA averages them. With raster_jitter=lookup
    // (the texels' points shifted instead) the rasterizer always samples the pixel centres, so
    // the average never sees between them.
    const std::vector<FrameResult> reference =
        test::render_all("checker-room", "ground-truth", 64, 36, 1, {}, 0.0f, 0, {});
    const Image& truth = buffer(reference[0], "final");
    const auto rmse = [&](const Image& image) {
        double sum = 0.0;
        for (std::size_t i = 0; i < image.data.size(); ++i)
            sum += (image.data[i] - truth.data[i]) * (image.data[i] - truth.data[i]);
        return std::sqrt(sum / static_cast<double>(image.data.size()));
    };
    std::map<std::string, std::vector<double>> errors;
    for (const char* jitter : {"raster", "lookup"}) {
        const std::vector<FrameResult> frames = render_sequence(
            "checker-room", "kfr", 16, 0.0f, {{"taa", "depth"}, {"raster_jitter", jitter}});
        for (const FrameResult& f : frames) errors[jitter].push_back(rmse(buffer(f, "taa_color")));
    }
    const std::vector<double>& raster = errors["raster"];
    const std::vector<double>& lookup = errors["lookup"];
    MESSAGE("kfr taa_color RMSE against the ground truth, frames 0, 3, 7, 15: raster "
            << raster[0] << ", " << raster[3] << ", " << raster[7] << ", " << raster[15]
            << "; lookup " << lookup[0] << ", " << lookup[3] << ", " << lookup[7] << ", "
            << lookup[15]);
    CHECK(raster[15] < 0.9 * raster[0]);
    CHECK(raster[7] < raster[0]);
    CHECK(raster[15] < lookup[15]);
}
