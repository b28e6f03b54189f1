#include "ref/log_polar/resolve.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/resolve_avx.h"
#include "ref/log_polar/trace.h"

namespace fovref {

namespace {

float lerp(float a, float b, float t) { return a + t * (b - a); }

/// One row of the lookup: lerp in u over the traced taps; returns the row's weight. (Inlined
/// into every lookup: pass 2 runs it twice per screen pixel.)
[[gnu::always_inline]] inline float sample_row(const Image& buffer, const BilinearLookup& l, int j,
                                               const bool traced[2], float* out) {
    const int channels = buffer.channels;
    if (traced[0] && traced[1]) {
        for (int c = 0; c < channels; ++c)
            out[c] = lerp(buffer.at(l.i0, j, c), buffer.at(l.i1, j, c), l.fu);
        return 1.0f;
    }
    if (traced[0] || traced[1]) {
        const int i = traced[0] ? l.i0 : l.i1;
        for (int c = 0; c < channels; ++c) out[c] = buffer.at(i, j, c);
        return traced[0] ? 1.0f - l.fu : l.fu;
    }
    return 0.0f;
}

}  // namespace

BilinearLookup lp_bilinear_index(int w, int h, glm::vec2 uv) {
    BilinearLookup l;
    l.uv = uv;
    // lp_forward gives a finite u and v in [0, h); anything else is a caller's bug.
    FOVREF_CHECK(std::isfinite(uv.x) && uv.y >= -1.0f && uv.y <= static_cast<float>(h) + 1.0f,
                 "bilinear lookup outside the buffer's angular range");
    // u: clamped to the first and last texel centres.
    const float s = std::clamp(uv.x, 0.5f, static_cast<float>(w) - 0.5f) - 0.5f;
    const float i0 = std::floor(s);
    l.i0 = static_cast<int>(i0);
    l.i1 = std::min(l.i0 + 1, w - 1);
    l.fu = s - i0;
    // v: wraps (v is in [0, h) from lp_forward; a lookup outside is wrapped the same way).
    const float t = uv.y - 0.5f;
    const float j0 = std::floor(t);
    l.fv = t - j0;
    // floor(v - 1/2) lies in [-2, h] (checked above): wrapped by adding or subtracting h.
    l.j0 = static_cast<int>(j0);
    while (l.j0 < 0) l.j0 += h;
    while (l.j0 >= h) l.j0 -= h;
    l.j1 = l.j0 + 1 == h ? 0 : l.j0 + 1;
    return l;
}

BilinearLookup lp_bilinear_taps(const Image& valid, glm::vec2 uv) {
    BilinearLookup l = lp_bilinear_index(valid.width, valid.height, uv);
    l.traced[0] = valid.at(l.i0, l.j0) != 0.0f;
    l.traced[1] = valid.at(l.i1, l.j0) != 0.0f;
    l.traced[2] = valid.at(l.i0, l.j1) != 0.0f;
    l.traced[3] = valid.at(l.i1, l.j1) != 0.0f;
    return l;
}

bool sample_lp_bilinear(const Image& buffer, const Image& valid, glm::vec2 uv, float* out,
                        BilinearLookup* lookup) {
    const int channels = buffer.channels;
    FOVREF_CHECK(buffer.width == valid.width && buffer.height == valid.height,
                 "a validity mask of another size than its buffer");
    BilinearLookup l = lp_bilinear_taps(valid, uv);
    FOVREF_CHECK(channels <= 4, "bilinear lookup of a buffer with more than 4 channels");
    if (!lookup && l.traced[0] && l.traced[1] && l.traced[2] && l.traced[3]) {
        // Every tap traced (most lookups): the general path below with both row weights 1
        // written out, the same operations. fv < 1, so W0 = 1 - fv > 0; W1 = fv > 0 unless fv = 0,
        // when the general path takes row 0 alone.
        const float* a = &buffer.data[buffer.index(l.i0, l.j0)];
        const float* b = &buffer.data[buffer.index(l.i1, l.j0)];
        const float* c = &buffer.data[buffer.index(l.i0, l.j1)];
        const float* d = &buffer.data[buffer.index(l.i1, l.j1)];
        for (int k = 0; k < channels; ++k) {
            const float r0 = lerp(a[k], b[k], l.fu);
            out[k] = l.fv > 0.0f ? lerp(r0, lerp(c[k], d[k], l.fu), l.fv) : r0;
        }
        return true;
    }

    float row0[4] = {0, 0, 0, 0}, row1[4] = {0, 0, 0, 0};
    const float w0 = sample_row(buffer, l, l.j0, &l.traced[0], row0);
    const float w1 = sample_row(buffer, l, l.j1, &l.traced[2], row1);
    l.row_weight[0] = (1.0f - l.fv) * w0;
    l.row_weight[1] = l.fv * w1;
    bool any = true;
    if (l.row_weight[0] > 0.0f && l.row_weight[1] > 0.0f) {
        l.t = w0 == w1 ? l.fv : l.row_weight[1] / (l.row_weight[0] + l.row_weight[1]);
        for (int c = 0; c < channels; ++c) out[c] = lerp(row0[c], row1[c], l.t);
    } else if (l.row_weight[0] > 0.0f) {
        l.t = 0.0f;
        for (int c = 0; c < channels; ++c) out[c] = row0[c];
    } else if (l.row_weight[1] > 0.0f) {
        l.t = 1.0f;
        for (int c = 0; c < channels; ++c) out[c] = row1[c];
    } else {
        any = false;
        for (int c = 0; c < channels; ++c) out[c] = 0.0f;
    }
    if (lookup) *lookup = l;
    return any;
}

GazeInput gaze_input(const LogPolarMap& map, const Image* image) {
    GazeInput gaze;
    if (!image) return gaze;
    gaze.image = image;
    gaze.window = gaze_window(map);
    FOVREF_CHECK_EQ(image->width, gaze.window.width, "gaze buffer width");
    FOVREF_CHECK_EQ(image->height, gaze.window.height, "gaze buffer height");
    return gaze;
}

bool reads_gaze_buffer(const LogPolarMap& map, const GazeInput& gaze, int x, int y) {
    if (!gaze.image) return false;
    const ScreenWindow& w = gaze.window;
    // Outside the window no pixel centre is inside the circle (gaze_window), so only the
    // window's pixels need the distance.
    if (x < w.x0 || y < w.y0 || x >= w.x0 + w.width || y >= w.y0 + w.height) return false;
    return inside_gaze_circle(map, pixel_centre(x, y));
}

bool gaze_pixel(const LogPolarMap& map, const GazeInput& gaze, int x, int y, float* pixel,
                int channels, ResolveStats& stats) {
    if (!reads_gaze_buffer(map, gaze, x, y)) return false;
    ++stats.pixels_from_gaze;
    for (int c = 0; c < channels; ++c)
        pixel[c] = gaze.image->at(x - gaze.window.x0, y - gaze.window.y0, c);
    return true;
}

ForwardTable forward_table(const LogPolarMap& map, int mip_levels) {
    ForwardTable table;
    table.map = map;
    table.mip_levels = mip_levels;
    const std::size_t pixels = static_cast<std::size_t>(map.screen_width) * map.screen_height;
    table.uv.resize(pixels);
    if (mip_levels > 0) table.mip_lambda.resize(pixels);
    for (int y = 0; y < map.screen_height; ++y)
        for (int x = 0; x < map.screen_width; ++x) {
            const glm::vec2 c = pixel_centre(x, y);
            const std::size_t k = static_cast<std::size_t>(y) * map.screen_width + x;
            table.uv[k] = lp_forward(map, c);
            if (mip_levels > 0) table.mip_lambda[k] = mip_lambda(map, c);
        }
    return table;
}

void resolve_pixel(const LogPolarMap& map, const ResolveInputs& in, Image& out, int x, int y,
                   ResolveStats& stats, BilinearLookup* lookup, const ForwardTable* table) {
    float* pixel = &out.at(x, y, 0);
    if (gaze_pixel(map, in.gaze, x, y, pixel, out.channels, stats)) return;
    ++stats.pixels_from_buffer;
    const glm::vec2 centre = pixel_centre(x, y);
    const glm::vec2 uv = table ? table->uv[static_cast<std::size_t>(y) * map.screen_width + x]
                               : lp_forward(map, centre);
    if (!sample_lp_bilinear(in.buffer, in.buffer_valid, uv, pixel, lookup))
        ++stats.pixels_untraced_taps;
}

Image resolve_log_polar(const LogPolarMap& map, const ResolveInputs& in, ResolveStats& stats,
                        const ForwardTable* table, Image storage) {
    if (table) FOVREF_CHECK(table->map == map, "a forward table made for another map");
    FOVREF_CHECK_EQ(in.buffer.width, map.width, "log-polar buffer width");
    FOVREF_CHECK_EQ(in.buffer.height, map.height, "log-polar buffer height");
    FOVREF_CHECK_EQ(in.buffer_valid.width, map.width, "validity mask width");
    if (in.gaze.image) FOVREF_CHECK(in.gaze.window == gaze_window(map), "a gaze buffer's window");
    Image out = std::move(storage);  // every pixel is written below
    keep_or_make(out, map.screen_width, map.screen_height, in.buffer.channels);
    // Eight pixels at a time where the AVX path covers the resolve (the same bits:
    // resolve_avx.h); resolve_pixel, the reference, does the rest.
    const bool avx = resolve_avx_applies(map, in, table);
    for (int y = 0; y < map.screen_height; ++y)
        for (int x = avx ? resolve_row_avx(map, in, *table, out, y, stats) : 0;
             x < map.screen_width; ++x)
            resolve_pixel(map, in, out, x, y, stats, nullptr, table);
    return out;
}

std::vector<glm::ivec2> resolve_pixel_taps(const LogPolarMap& map, int x, int y, bool& from_gaze) {
    const glm::vec2 centre = pixel_centre(x, y);
    from_gaze = inside_gaze_circle(map, centre);
    if (from_gaze) {
        const ScreenWindow window = gaze_window(map);
        return {{x - window.x0, y - window.y0}};
    }
    const BilinearLookup l =
        lp_bilinear_taps(Image(map.width, map.height, 1, 1.0f), lp_forward(map, centre));
    std::vector<glm::ivec2> taps;
    for (const glm::ivec2& tap : {glm::ivec2(l.i0, l.j0), glm::ivec2(l.i1, l.j0),
                                  glm::ivec2(l.i0, l.j1), glm::ivec2(l.i1, l.j1)})
        if (std::find(taps.begin(), taps.end(), tap) == taps.end()) taps.push_back(tap);
    return taps;
}

}  // namespace fovref
