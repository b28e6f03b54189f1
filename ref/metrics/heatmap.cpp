#include "ref/metrics/heatmap.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "ref/core/error.h"
#include "ref/image/image_io.h"

namespace fovref {

namespace {

// matplotlib's "inferno" colour map (Nathaniel J. Smith, Stefan van der Walt; CC0) sampled at
// 33 equally spaced points, sRGB 8-bit; linear interpolation between neighbours.
constexpr std::uint8_t inferno[33][3] = {
    {0, 0, 4},       {4, 3, 18},      {11, 7, 36},    {21, 11, 55},   {33, 12, 74},
    {47, 10, 91},    {61, 9, 101},    {74, 12, 107},  {87, 16, 110},  {100, 21, 110},
    {113, 25, 110},  {125, 30, 109},  {138, 34, 106}, {151, 39, 102}, {163, 44, 97},
    {176, 49, 91},   {188, 55, 84},   {199, 62, 76},  {210, 70, 68},  {219, 80, 59},
    {228, 90, 49},   {235, 102, 40},  {241, 115, 29}, {246, 128, 19}, {249, 142, 9},
    {251, 157, 7},   {252, 172, 17},  {251, 188, 33}, {249, 203, 53}, {245, 219, 76},
    {242, 234, 105}, {243, 246, 138}, {252, 255, 164}};

// 3x5 glyphs, rows top to bottom, 3 bits per row (bit 2 = left column).
struct Glyph {
    char c;
    std::uint8_t rows[5];
};
constexpr Glyph glyphs[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}}, {'3', {7, 1, 7, 1, 7}},
    {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}}, {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}},
    {'8', {7, 5, 7, 5, 7}}, {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'+', {0, 2, 7, 2, 0}}, {'e', {3, 5, 7, 4, 3}}, {'x', {0, 5, 2, 5, 0}}, {' ', {0, 0, 0, 0, 0}}};

void put(Image& image, int x, int y, glm::vec3 colour) {
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    for (int c = 0; c < 3; ++c) image.at(x, y, c) = colour[c];
}

std::string scale_label(float value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", static_cast<double>(value));
    return text;
}

}  // namespace

glm::vec3 heatmap_colour(float t) {
    t = t > 0.0f ? (t < 1.0f ? t : 1.0f) : 0.0f;
    const float position = t * 32.0f;
    const int i = std::min(static_cast<int>(position), 31);
    const float f = position - static_cast<float>(i);
    glm::vec3 colour;
    for (int c = 0; c < 3; ++c) {
        const float lo = static_cast<float>(inferno[i][c]) / 255.0f;
        const float hi = static_cast<float>(inferno[i + 1][c]) / 255.0f;
        colour[c] = srgb_decode(lo + (hi - lo) * f);
    }
    return colour;
}

void draw_text(Image& image, int x, int y, const std::string& text, glm::vec3 colour, int scale) {
    int pen = x;
    for (const char ch : text) {
        const Glyph* glyph = nullptr;
        for (const Glyph& g : glyphs)
            if (g.c == ch) glyph = &g;
        if (glyph)
            for (int row = 0; row < 5; ++row)
                for (int col = 0; col < 3; ++col)
                    if (glyph->rows[row] & (4 >> col))
                        for (int sy = 0; sy < scale; ++sy)
                            for (int sx = 0; sx < scale; ++sx)
                                put(image, pen + col * scale + sx, y + row * scale + sy, colour);
        pen += 4 * scale;
    }
}

float heatmap_scale(const Image& values, const HeatmapSettings& settings) {
    if (settings.scale_max > 0.0f) return settings.scale_max;
    float largest = 0.0f;
    for (const float v : values.data)
        if (std::isfinite(v)) largest = std::max(largest, v);
    return largest;
}

Image heatmap(const Image& values, const HeatmapSettings& settings) {
    if (values.channels != 1)
        throw Error("heatmap: needs a 1-channel error map, got " + std::to_string(values.channels) +
                    " channels");
    if (settings.rings &&
        (settings.rings->width != values.width || settings.rings->height != values.height))
        throw Error("heatmap: the ring layout does not match the map's size");
    const float scale = heatmap_scale(values, settings);
    const int text_scale = values.height >= 400 ? 2 : 1;
    const int bar_width = 6 * text_scale + 4;
    const int panel = settings.legend ? bar_width + 6 + 9 * 4 * text_scale : 0;
    Image out(values.width + panel, values.height, 3, 0.0f);
    const glm::vec3 white(1.0f), magenta(1.0f, 0.0f, 1.0f);

    // The map, through a 4096-entry table of heatmap_colour (nearest entry): the sRGB decode
    // per pixel would dominate the time, and 4096 steps are below what 8-bit PNGs resolve.
    constexpr int steps = 4096;
    static const std::vector<glm::vec3> table = [] {
        std::vector<glm::vec3> t(steps);
        for (int i = 0; i < steps; ++i)
            t[static_cast<std::size_t>(i)] =
                heatmap_colour(static_cast<float>(i) / static_cast<float>(steps - 1));
        return t;
    }();
    for (int y = 0; y < values.height; ++y)
        for (int x = 0; x < values.width; ++x) {
            const float v = values.at(x, y);
            if (!std::isfinite(v)) {
                put(out, x, y, magenta);
                continue;
            }
            float t = scale > 0.0f ? v / scale : 0.0f;
            t = t > 0.0f ? (t < 1.0f ? t : 1.0f) : 0.0f;
            put(out, x, y,
                table[static_cast<std::size_t>(t * static_cast<float>(steps - 1) + 0.5f)]);
        }
    // Ring boundaries: a pixel whose ring differs from its right or lower neighbour.
    if (settings.rings) {
        const auto& ring = settings.rings->ring;
        const auto w = static_cast<std::size_t>(values.width);
        for (int y = 0; y < values.height; ++y)
            for (int x = 0; x < values.width; ++x) {
                const std::size_t p = static_cast<std::size_t>(y) * w + static_cast<std::size_t>(x);
                const bool right = x + 1 < values.width && ring[p] != ring[p + 1];
                const bool below = y + 1 < values.height && ring[p] != ring[p + w];
                if (!(right || below)) continue;
                // Blend 25% white over the error colour, so errors on a boundary stay visible.
                for (int c = 0; c < 3; ++c) out.at(x, y, c) = 0.75f * out.at(x, y, c) + 0.25f;
            }
    }
    if (!settings.legend) return out;

    // Legend: a colour bar (top = scale, bottom = 0) and three scale values.
    const int x0 = values.width + 4;
    for (int y = 0; y < values.height; ++y) {
        const float t = values.height > 1
                            ? 1.0f - static_cast<float>(y) / static_cast<float>(values.height - 1)
                            : 1.0f;
        for (int x = 0; x < bar_width; ++x) put(out, x0 + x, y, heatmap_colour(t));
    }
    const int text_x = x0 + bar_width + 3;
    const int glyph_height = 5 * text_scale;
    draw_text(out, text_x, 0, scale_label(scale), white, text_scale);
    draw_text(out, text_x, values.height - glyph_height, "0", white, text_scale);
    if (values.height >= 4 * glyph_height)
        draw_text(out, text_x, (values.height - glyph_height) / 2, scale_label(scale * 0.5f), white,
                  text_scale);
    return out;
}

void mark_pixels(Image& image, int map_width, int map_height, const std::vector<glm::ivec2>& pixels,
                 glm::vec3 colour) {
    // Rings big and thick enough to survive the report's downscaling (a 1280-wide map is shown at
    // 640 px): radius 1/64 of the map's larger side, thickness a quarter of it.
    const int radius = std::max(3, std::max(map_width, map_height) / 64);
    const int thickness = std::max(1, radius / 4);
    auto put = [&](int x, int y) {
        if (x < 0 || y < 0 || x >= map_width || y >= map_height) return;
        for (int c = 0; c < 3; ++c) image.at(x, y, c) = colour[c];
    };
    for (const glm::ivec2& p : pixels) {
        put(p.x, p.y);
        for (int dy = -radius; dy <= radius; ++dy)
            for (int dx = -radius; dx <= radius; ++dx)
                if (std::max(std::abs(dx), std::abs(dy)) > radius - thickness)  // square ring
                    put(p.x + dx, p.y + dy);
    }
}

Image id_mismatch_image(const Image& background, const Image& mismatch_map) {
    FOVREF_CHECK(
        background.channels == 3 && mismatch_map.channels == 1 &&
            background.width == mismatch_map.width && background.height == mismatch_map.height,
        "id_mismatch_image: an RGB background and a 1-channel map of the same size "
        "expected, got " +
            std::to_string(background.width) + "x" + std::to_string(background.height) + "x" +
            std::to_string(background.channels) + " and " + std::to_string(mismatch_map.width) +
            "x" + std::to_string(mismatch_map.height) + "x" +
            std::to_string(mismatch_map.channels));
    Image out(background.width, background.height, 3, 0.0f);
    for (std::size_t p = 0; p < background.pixel_count(); ++p) {
        const float grey = 0.2126f * background.data[3 * p] + 0.7152f * background.data[3 * p + 1] +
                           0.0722f * background.data[3 * p + 2];
        for (std::size_t c = 0; c < 3; ++c) out.data[3 * p + c] = 0.15f + 0.35f * grey;
    }
    for (const float kind : {1.0f, 2.0f}) {  // edge markers first, interior ones on top
        std::vector<glm::ivec2> pixels;
        for (int y = 0; y < out.height; ++y)
            for (int x = 0; x < out.width; ++x)
                if (mismatch_map.at(x, y) == kind) pixels.emplace_back(x, y);
        mark_pixels(out, out.width, out.height, pixels,
                    kind == 1.0f ? edge_marker_colour : interior_marker_colour);
    }
    return out;
}

}  // namespace fovref
