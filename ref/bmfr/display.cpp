// BMFR's last steps: remodulation and tone mapping, the authors' YCoCg TAA (SPEC §9 items 9-10).
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/display_avx.h"
#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

glm::vec3 rgb_to_ycocg(glm::vec3 c) {
    return {c.x + 2.0f * c.y + c.z, 2.0f * c.x - 2.0f * c.z, -c.x + 2.0f * c.y - c.z};
}

glm::vec3 ycocg_to_rgb(glm::vec3 v) {
    return {((v.x + v.y) - v.z) * 0.25f, (v.x + v.z) * 0.25f, ((v.x - v.y) - v.z) * 0.25f};
}

glm::vec3 load3(const Image& image, int x, int y) {
    const float* p = &image.data[image.index(x, y)];
    return {p[0], p[1], p[2]};
}

// The authors' TAA of pixel (x, y) (bmfr_taa): the extents in YCoCg of its 3x3 box and 5-tap
// cross (`neighbour(dx, dy, sx, sy)` gives the pixel at offset (dx, dy), false when there is
// none), the history blended over the taps that `usable(k)` accepts (weights renormalised),
// clamped to the average of the two extents, then 0.2 new + 0.8 history into o. False when no
// tap counts (o keeps the new colour).
template <class Neighbour, class Usable>
bool taa_blend(const BmfrParams& params, const Image& display, const Image& ycocg,
               const Image& history, int x, int y, const BmfrTaps& taps, Neighbour neighbour,
               Usable usable, float* o) {
    glm::vec3 box_min(INFINITY), box_max(-INFINITY), cross_min(INFINITY), cross_max(-INFINITY);
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            int sx = 0, sy = 0;
            if (!neighbour(dx, dy, sx, sy)) continue;
            const glm::vec3 v = load3(ycocg, sx, sy);
            box_min = glm::min(box_min, v);
            box_max = glm::max(box_max, v);
            if (dx == 0 || dy == 0) {
                cross_min = glm::min(cross_min, v);
                cross_max = glm::max(cross_max, v);
            }
        }
    const glm::vec3 lo = (box_min + cross_min) * 0.5f;
    const glm::vec3 hi = (box_max + cross_max) * 0.5f;
    glm::vec3 h(0.0f);
    float total = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if (!usable(k)) continue;
        h += taps.w[k] * load3(history, taps.x[k], taps.y[k]);
        total += taps.w[k];
    }
    if (!(total > 0.0f)) return false;
    h = h / total;
    const glm::vec3 current = load3(display, x, y);
    const glm::vec3 clamped = ycocg_to_rgb(glm::clamp(rgb_to_ycocg(h), lo, hi));
    const glm::vec3 blended = current * params.taa_alpha + clamped * (1.0f - params.taa_alpha);
    o[0] = blended.x, o[1] = blended.y, o[2] = blended.z;
    return true;
}

// The TAA of traced texel (x, y) of a Visual-Polar buffer: neighbours on each column's own rows
// (wrapping), traced texels only; history taps on texels traced in the previous frame.
bool vp_taa_pixel(const BmfrParams& params, const Image& display, const Image& ycocg, glm::vec2 q,
                  const Image& history, const BmfrSpace& space, int x, int y, float* o) {
    const VisualPolarMap& map = *space.map;
    const int width = display.width;
    const float t = (static_cast<float>(y) + 0.5f) / static_cast<float>(vp_column_rows(map, x));
    const BmfrTaps taps = bmfr_vp_taps(space.history_map(), q);
    return taa_blend(
        params, display, ycocg, history, x, y, taps,
        [&](int dx, int dy, int& sx, int& sy) {
            sx = x + dx;
            if (sx < 0 || sx >= width) return false;
            const int rows = vp_column_rows(map, sx);
            const int base = std::min(static_cast<int>(t * static_cast<float>(rows)), rows - 1);
            sy = vp_wrap_row(base + dy, rows);
            return space.valid->at(sx, sy) != 0.0f;
        },
        [&](int k) {
            if (taps.x[k] < 0 || taps.y[k] < 0 || taps.x[k] >= width) return false;
            return !space.previous_valid || space.previous_valid->at(taps.x[k], taps.y[k]) != 0.0f;
        },
        o);
}

}  // namespace

Image bmfr_remodulate(const BmfrParams& params, const Image& filtered, const Image& albedo,
                      const Image& emission, Image storage) {
    const bool separate = params.separate_emission && !emission.empty();
    FOVREF_CHECK(albedo.same_shape(filtered) && filtered.channels == 3 &&
                     (!separate || emission.same_shape(filtered)),
                 "bmfr_remodulate: the albedo or emission does not match the image");
    Image out = std::move(storage);  // every value is written below
    keep_or_make(out, filtered.width, filtered.height, 3);
    // the base b per value, then b^g for all at once (pow_fast_array: pow_fast's bits)
    for (std::size_t i = 0; i < out.data.size(); ++i) {
        const float a = std::isfinite(albedo.data[i]) ? albedo.data[i] : 0.0f;
        float linear = std::max(0.0f, filtered.data[i]) * std::max(a, params.remodulation_floor);
        if (separate && std::isfinite(emission.data[i])) linear = linear + emission.data[i];
        out.data[i] = std::max(0.0f, linear);
    }
    const auto powered = std::make_unique_for_overwrite<float[]>(out.data.size());
    dm::pow_fast_array(out.data.data(), params.display_exponent, powered.get(), out.data.size());
    for (std::size_t i = 0; i < out.data.size(); ++i)
        // b >= 1 gives b^g >= 1, clamped to 1 (its power is not used)
        out.data[i] = out.data[i] >= 1.0f ? 1.0f : std::clamp(powered[i], 0.0f, 1.0f);
    return out;
}

Image bmfr_taa(const BmfrParams& params, const Image& display, const Image& previous_pixel,
               const Image& history, BmfrStats& stats, const BmfrSpace& space, Image storage) {
    const int width = display.width, height = display.height;
    FOVREF_CHECK(previous_pixel.width == width && previous_pixel.height == height &&
                     previous_pixel.channels == 2 &&
                     (history.empty() || (history.width == width && history.height == height &&
                                          history.channels == 3)),
                 "bmfr_taa: buffers of different shapes");
    Image out = std::move(storage);  // every pixel is written below (the new colour first)
    keep_or_make(out, width, height, 3);
    const Image ycocg = history.empty() ? Image() : bmfr_ycocg(display);
    // The span of each row that the AVX2 path covers eight pixels at a time (the same bits:
    // display_avx.h); the reference does the rest of each row and every other frame.
    const BmfrTaaSpan span = bmfr_taa_avx_span(display, history, space);
    const auto reference = [&](int x0, int x1, int y) {
        for (int x = x0; x < x1; ++x)
            if (bmfr_taa_pixel(params, display, ycocg, previous_pixel, history, space, out, x, y))
                ++stats.taa_history_used;
    };
    for (int y = 0; y < height; ++y) {
        reference(0, span.first, y);
        if (span.first < span.end)
            bmfr_taa_row_avx(params, display, ycocg, previous_pixel, history, space, span, out, y,
                             stats.taa_history_used);
        reference(span.end, width, y);
    }
    return out;
}

Image bmfr_ycocg(const Image& display) {
    Image ycocg(display.width, display.height, 3);
    for (int y = 0; y < display.height; ++y)
        for (int x = 0; x < display.width; ++x) {
            const glm::vec3 v = rgb_to_ycocg(load3(display, x, y));
            float* p = &ycocg.data[ycocg.index(x, y)];
            p[0] = v.x, p[1] = v.y, p[2] = v.z;
        }
    return ycocg;
}

bool bmfr_taa_pixel(const BmfrParams& params, const Image& display, const Image& ycocg,
                    const Image& previous_pixel, const Image& history, const BmfrSpace& space,
                    Image& out, int x, int y) {
    const int width = display.width, height = display.height;
    const glm::vec3 current = load3(display, x, y);
    float* o = &out.data[out.index(x, y)];
    o[0] = current.x, o[1] = current.y, o[2] = current.z;
    if (history.empty()) return false;
    const glm::vec2 q(previous_pixel.at(x, y, 0), previous_pixel.at(x, y, 1));
    if (space.map) {
        if (space.valid->at(x, y) == 0.0f) return false;
        if (!(q.x >= -1.0f && q.x < static_cast<float>(width))) return false;
        return vp_taa_pixel(params, display, ycocg, q, history, space, x, y, o);
    }
    // Some tap of the reprojected point must be on the screen: floor(q) in [-1, W - 1]
    if (!(q.x >= -1.0f && q.y >= -1.0f && q.x < static_cast<float>(width) &&
          q.y < static_cast<float>(height)))
        return false;
    // The neighbours and the history's bilinear taps inside the image
    const BmfrTaps taps = bmfr_taps(q);
    return taa_blend(
        params, display, ycocg, history, x, y, taps,
        [&](int dx, int dy, int& sx, int& sy) {
            sx = x + dx, sy = y + dy;
            return sx >= 0 && sy >= 0 && sx < width && sy < height;
        },
        [&](int k) {
            return taps.x[k] >= 0 && taps.y[k] >= 0 && taps.x[k] < width && taps.y[k] < height;
        },
        o);
}

Image bmfr_linearize(const Image& display, Image storage) {
    Image out = std::move(storage);  // every value is written below
    keep_or_make(out, display.width, display.height, display.channels);
    for (std::size_t i = 0; i < out.data.size(); ++i) out.data[i] = std::max(display.data[i], 0.0f);
    dm::pow_fast_array(out.data.data(), 2.2f, out.data.data(), out.data.size());
    return out;
}

}  // namespace fovref
