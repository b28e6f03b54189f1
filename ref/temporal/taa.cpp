#include "ref/temporal/taa.h"

#include <algorithm>
#include <cmath>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/temporal/taa_avx.h"

namespace fovref {

const char* taa_decision_name(TaaDecision decision) {
    switch (decision) {
        case TaaDecision::first: return "first frame: the current pixel";
        case TaaDecision::stationary: return "stationary camera: the history at the pixel, kept";
        case TaaDecision::kept: return "kept (depths consistent)";
        case TaaDecision::rejected: return "rejected: the current pixel";
        case TaaDecision::periphery: return "inconsistent beyond the periphery radius: kept, age 2";
        case TaaDecision::clamped: return "outside the 3x3 neighbourhood's box: clamped to it";
    }
    return "?";
}

bool taa_taps(int width, int height, glm::vec2 q, TaaTaps& t) {
    // Taps further than one pixel outside the screen have no weight on it (and far-off points
    // would overflow an int).
    if (!(q.x > -1.0f && q.y > -1.0f && q.x < static_cast<float>(width) + 1.0f &&
          q.y < static_cast<float>(height) + 1.0f))
        return false;
    const float sx = q.x - 0.5f, sy = q.y - 0.5f;  // in (-1.5, W + 0.5): taa_floor_int applies
    const int x0 = taa_floor_int(sx), y0 = taa_floor_int(sy);
    const float fx = sx - static_cast<float>(x0), fy = sy - static_cast<float>(y0);
    t = {{x0, x0 + 1, x0, x0 + 1},
         {y0, y0, y0 + 1, y0 + 1},
         {(1.0f - fx) * (1.0f - fy), fx * (1.0f - fy), (1.0f - fx) * fy, fx * fy}};
    return true;
}

float taa_sample(const Image& image, glm::vec2 q, float* out) {
    const int channels = image.channels;
    FOVREF_CHECK(channels <= 4, "a TAA sample of more than 4 channels");
    for (int c = 0; c < channels; ++c) out[c] = 0.0f;
    TaaTaps t;
    if (!taa_taps(image.width, image.height, q, t)) return 0.0f;
    float sum = 0.0f, acc[4] = {0, 0, 0, 0};
    for (int k = 0; k < 4; ++k) {
        if (!t.on_screen(k, image.width, image.height)) continue;
        sum += t.w[k];
        for (int c = 0; c < channels; ++c) acc[c] += t.w[k] * image.at(t.x[k], t.y[k], c);
    }
    if (!(sum > 0.0f)) return 0.0f;
    for (int c = 0; c < channels; ++c) out[c] = acc[c] / sum;
    return sum;
}

TaaReprojection taa_reprojection(const Camera& camera, float tan_half, const Camera& previous,
                                 float previous_tan_half, int width, int height) {
    TaaReprojection k;
    k.width = width;
    k.height = height;
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    k.sx_scale = tan_half * (w / h);
    k.sy_scale = tan_half;
    // A vector in the previous camera's axes: (v . R', -(v . U'), v . F').
    const auto axes = [&](glm::vec3 v) {
        return glm::vec3(glm::dot(v, previous.right), -glm::dot(v, previous.up),
                         glm::dot(v, previous.forward));
    };
    k.o = axes(camera.position - previous.position);
    k.f = axes(camera.forward);
    k.r = axes(camera.right);
    k.u = axes(camera.up);
    k.a = {(0.5f * w) / (previous_tan_half * (w / h)), (0.5f * h) / previous_tan_half};
    return k;
}

bool taa_reproject(const TaaReprojection& k, int x, int y, float z, glm::vec2& previous_point,
                   float& previous_depth) {
    const float w = static_cast<float>(k.width), h = static_cast<float>(k.height);
    const glm::vec2 c = pixel_centre(x, y);
    const float sx = ((2.0f * c.x) / w - 1.0f) * k.sx_scale;
    const float sy = ((2.0f * c.y) / h - 1.0f) * k.sy_scale;
    const glm::vec3 d = k.f + sx * k.r - sy * k.u;
    const glm::vec3 q = k.o + z * d;
    previous_depth = q.z;
    if (!(q.z > 0.0f)) return false;
    previous_point = {q.x * (k.a.x / q.z) + 0.5f * w, q.y * (k.a.y / q.z) + 0.5f * h};
    return true;
}

bool taa_reproject(const Camera& camera, float tan_half, const Camera& previous,
                   float previous_tan_half, int width, int height, int x, int y, float z,
                   glm::vec2& previous_point, float& previous_depth) {
    return taa_reproject(
        taa_reprojection(camera, tan_half, previous, previous_tan_half, width, height), x, y, z,
        previous_point, previous_depth);
}

namespace {

// taa_sample of the history (3 channels) and the previous depth at the same point in one pass:
// the same taps, weights and operations, so the same bits as two taa_sample calls.
float sample_history(const TaaState& previous, glm::vec2 q, glm::vec3& history, float& depth) {
    history = glm::vec3(0.0f);
    depth = 0.0f;
    const Image& image = previous.history;
    TaaTaps t;
    if (!taa_taps(image.width, image.height, q, t)) return 0.0f;
    float sum = 0.0f, r = 0.0f, g = 0.0f, b = 0.0f, z = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (!t.on_screen(k, image.width, image.height)) continue;
        const std::size_t pixel = static_cast<std::size_t>(t.y[k]) * image.width + t.x[k];
        const float* c = &image.data[pixel * 3];
        sum += t.w[k];
        r += t.w[k] * c[0];
        g += t.w[k] * c[1];
        b += t.w[k] * c[2];
        z += t.w[k] * previous.depth.data[pixel];
    }
    if (!(sum > 0.0f)) return 0.0f;
    history = {r / sum, g / sum, b / sum};
    depth = z / sum;
    return sum;
}

// Signed distance of p from the border of the rectangle [x0, x1] x [y0, y1]: inside, the
// distance to the nearest side; outside, minus the distance to the rectangle.
float border_distance(glm::vec2 p, float x0, float y0, float x1, float y1) {
    const float dx = std::max({x0 - p.x, p.x - x1, 0.0f});
    const float dy = std::max({y0 - p.y, p.y - y1, 0.0f});
    if (dx > 0.0f || dy > 0.0f) return -std::sqrt(dx * dx + dy * dy);
    return std::min({p.x - x0, x1 - p.x, p.y - y0, y1 - p.y});
}

bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

glm::vec3 rgb_at(const Image& image, int x, int y) {
    return {image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)};
}

// Karis's clamp: the history per channel within the current 3x3 neighbourhood's min and max.
glm::vec3 clamp_to_neighbourhood(const Image& color, int x, int y, glm::vec3 history) {
    glm::vec3 lo = rgb_at(color, x, y), hi = lo;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            const glm::vec3 v = rgb_at(color, std::clamp(x + dx, 0, color.width - 1),
                                       std::clamp(y + dy, 0, color.height - 1));
            lo = glm::min(lo, v);
            hi = glm::max(hi, v);
        }
    return glm::clamp(history, lo, hi);
}

}  // namespace

TaaConstants taa_constants(const TaaInputs& in, const TaaState& previous) {
    TaaConstants k;
    k.tan_half = tan_half_vfov(in.camera);
    k.previous_tan_half = previous.valid ? tan_half_vfov(previous.camera) : k.tan_half;
    const float width = static_cast<float>(in.color.width);
    const float height = static_cast<float>(in.color.height);
    k.diagonal = std::sqrt(width * width + height * height);
    k.stationary = previous.valid && in.camera == previous.camera;
    if (previous.valid)
        k.reprojection = taa_reprojection(in.camera, k.tan_half, previous.camera,
                                          k.previous_tan_half, in.color.width, in.color.height);
    return k;
}

namespace {

// The history of pixel (x, y) in the previous frame (SPEC §7): with a stationary camera the
// history at the pixel itself, never rejected; otherwise reprojected by the current depth and
// sampled bilinearly, with the depth test's verdict in `consistent`. False when there is no
// history to use (no surface, reprojected off screen, no history tap): the pixel is rejected.
bool previous_history(const TaaParams& params, const TaaInputs& in, const TaaState& previous,
                      const TaaConstants& k, int x, int y, TaaPixelRecord& r, bool& consistent) {
    if (k.stationary) {
        r.decision = TaaDecision::stationary;
        r.history = rgb_at(previous.history, x, y);
        r.age_previous = previous.age.at(x, y);
        return true;
    }
    const float z = in.depth.at(x, y);
    // A NaN or infinite current depth is no surface, and counted with the non-finite.
    r.history_nonfinite = !std::isfinite(z);
    const bool reprojected =
        z > 0.0f && std::isfinite(z) &&
        taa_reproject(k.reprojection, x, y, z, r.previous_point, r.previous_depth);
    if (reprojected)
        r.reprojection_margin = border_distance(r.previous_point, -0.5f, -0.5f,
                                                static_cast<float>(in.color.width) + 0.5f,
                                                static_cast<float>(in.color.height) + 0.5f);
    if (!reprojected ||
        sample_history(previous, r.previous_point, r.history, r.history_depth) <= 0.0f) {
        r.history = glm::vec3(0.0f);
        r.history_depth = 0.0f;
        return false;
    }
    // p' lies within a pixel of the screen here (sample_history had a tap).
    if (params.rejection == TaaRejection::depth)
        r.depth_margin =
            (params.tau * r.previous_depth - std::fabs(r.previous_depth - r.history_depth)) /
            r.previous_depth;
    const int px = std::clamp(taa_floor_int(r.previous_point.x), 0, in.color.width - 1);
    const int py = std::clamp(taa_floor_int(r.previous_point.y), 0, in.color.height - 1);
    r.age_previous = previous.age.at(px, py);
    consistent = std::fabs(r.previous_depth - r.history_depth) <= params.tau * r.previous_depth;
    r.decision = TaaDecision::kept;
    return true;
}

// Karis's clamp of the history to the box of `in.bounds` (clamp-buffer) or of the current 3x3
// neighbourhood (clamp-screen); the decision says whether it moved.
void clamp_history(const TaaInputs& in, int x, int y, TaaPixelRecord& r) {
    const glm::vec3 unclamped = r.history;
    if (in.bounds) {
        const glm::vec3 lo{in.bounds->at(x, y, 0), in.bounds->at(x, y, 1), in.bounds->at(x, y, 2)};
        const glm::vec3 hi{in.bounds->at(x, y, 3), in.bounds->at(x, y, 4), in.bounds->at(x, y, 5)};
        r.history = glm::clamp(r.history, lo, hi);
    } else {
        r.history = clamp_to_neighbourhood(in.color, x, y, r.history);
    }
    // Inside the box the history is kept as it is; outside it is clamped (counted apart).
    r.decision = r.history == unclamped ? TaaDecision::kept : TaaDecision::clamped;
}

}  // namespace

TaaPixelRecord taa_pixel(const TaaParams& params, const TaaInputs& in, const TaaState& previous,
                         int x, int y, Image& out, Image& age, const TaaConstants* constants) {
    const TaaConstants k = constants ? *constants : taa_constants(in, previous);
    TaaPixelRecord r;
    const glm::vec3 current = rgb_at(in.color, x, y);
    const glm::vec2 centre = pixel_centre(x, y);
    r.previous_point = centre;
    const auto write = [&](glm::vec3 value, float a) {
        for (int c = 0; c < 3; ++c) out.at(x, y, c) = value[c];
        age.at(x, y) = a;
        r.age = a;
    };
    const auto reject = [&] {
        r.decision = TaaDecision::rejected;
        write(current, 1.0f);
        return r;
    };
    if (!previous.valid) {
        r.decision = TaaDecision::first;
        write(current, 1.0f);
        return r;
    }
    bool consistent = true;
    if (!previous_history(params, in, previous, k, x, y, r, consistent)) return reject();
    if (!finite3(r.history) || !std::isfinite(r.age_previous) || !std::isfinite(r.history_depth)) {
        r.history_nonfinite = true;
        return reject();
    }
    float age_new =
        std::min(std::max(r.age_previous, 1.0f) + 1.0f, static_cast<float>(params.age_cap));
    if (params.rejection == TaaRejection::clamp && r.decision != TaaDecision::stationary) {
        clamp_history(in, x, y, r);
    } else if (!consistent) {
        // The periphery rule (Lund §3.4.1): far from the gaze an inconsistent history is kept
        // with age 2 instead of rejected.
        if (!(gaze_distance(in.gaze, centre) > params.periphery * k.diagonal)) return reject();
        r.decision = TaaDecision::periphery;
        age_new = 2.0f;
    }
    const float w = 1.0f / age_new;
    write(r.history * (1.0f - w) + current * w, age_new);
    return r;
}

void taa(const TaaParams& params, const TaaInputs& in, const TaaState& previous, Image& out,
         Image& age, TaaStats& stats, Image* margin) {
    const int width = in.color.width, height = in.color.height;
    FOVREF_CHECK_EQ(in.color.channels, 3, "TAA colour channels");
    FOVREF_CHECK(in.depth.width == width && in.depth.height == height,
                 "TAA depth of another size than the colour");
    if (previous.valid)
        FOVREF_CHECK(previous.history.same_shape(in.color) && previous.age.width == width &&
                         previous.age.height == height && previous.depth.width == width &&
                         previous.depth.height == height,
                     "a TAA history of another size than the frame");
    FOVREF_CHECK(params.age_cap >= 1, "TAA age cap below 1");
    if (in.bounds)
        FOVREF_CHECK(
            in.bounds->width == width && in.bounds->height == height && in.bounds->channels == 6,
            "TAA clamp bounds of another shape than the frame");
    // Every pixel of out and age is written below (each decision writes both).
    keep_or_make(out, width, height, 3);
    keep_or_make(age, width, height, 1);
    if (margin) *margin = Image(width, height, 2, 0.0f);
    const TaaConstants constants = taa_constants(in, previous);
    // Eight pixels at a time where the AVX path covers the frame (the same bits: taa_avx.h);
    // taa_pixel, the reference, does the rest of each row, the first frame and --scalar.
    const bool avx = taa_avx_applies(in, previous);
    for (int y = 0; y < height; ++y)
        for (int x = avx ? taa_row_avx(params, in, previous, constants, y, out, age, margin, stats)
                         : 0;
             x < width; ++x) {
            const TaaPixelRecord r = taa_pixel(params, in, previous, x, y, out, age, &constants);
            if (margin) {
                margin->at(x, y, 0) = r.depth_margin;
                margin->at(x, y, 1) = r.reprojection_margin;
            }
            switch (r.decision) {
                case TaaDecision::first: break;
                case TaaDecision::stationary:
                    ++stats.reprojection_skipped;
                    ++stats.kept;
                    break;
                case TaaDecision::kept: ++stats.kept; break;
                case TaaDecision::rejected: ++stats.rejected; break;
                case TaaDecision::periphery: ++stats.periphery_kept; break;
                case TaaDecision::clamped: ++stats.clamped; break;
            }
            if (r.history_nonfinite) ++stats.nonfinite_history;
        }
}

TaaState next_taa_state(Image out, Image age, const Image& depth, const Camera& camera) {
    TaaState s;
    s.valid = true;
    s.history = std::move(out);
    s.age = std::move(age);
    s.depth = depth;
    s.camera = camera;
    return s;
}

}  // namespace fovref
