#include "ref/log_polar/trace.h"
#include "ref/core/vec.h"

#include <algorithm>
#include <cmath>

namespace fovref {

TexelStatus begin_texel(MaskedGBuffer& buffer, Image& screen_points, const LogPolarMap& map,
                        const LpInverseTable& table, int x, int y, glm::vec2& p,
                        FoveatedTraceStats& stats) {
    const TexelStatus status = lp_texel_status(map, table, x, y, p);
    screen_points.at(x, y, 0) = p.x;
    screen_points.at(x, y, 1) = p.y;
    if (status == TexelStatus::off_screen) {
        ++stats.texels_off_screen;
    } else if (status == TexelStatus::inside_gaze) {
        ++stats.texels_inside_gaze;
    } else {
        ++stats.texels_traced;
        buffer.valid.at(x, y) = 1.0f;
    }
    return status;
}

TexelStatus lp_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points, const LogPolarMap& map,
                             const LpInverseTable& table, const PrimaryView& view, int x, int y,
                             FoveatedTraceStats& stats) {
    glm::vec2 p{0.0f};
    const TexelStatus status = begin_texel(buffer, screen_points, map, table, x, y, p, stats);
    if (status == TexelStatus::traced)
        raycast_sample(buffer.gbuffer, x, y, p, map.screen_width, map.screen_height, view,
                       stats.rays);
    return status;
}

MaskedGBuffer trace_lp_gbuffer(const LogPolarMap& map, const PrimaryView& view,
                               Image& screen_points, FoveatedTraceStats& stats, Offset2 jitter) {
    MaskedGBuffer buffer(map.width, map.height);
    screen_points = Image(map.width, map.height, 2, 0.0f);
    const LpInverseTable table = lp_inverse_table(map, jitter);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x)
            lp_gbuffer_texel(buffer, screen_points, map, table, view, x, y, stats);
    return buffer;
}

ScreenWindow gaze_window(const LogPolarMap& map) {
    ScreenWindow w;
    w.screen_width = map.screen_width;
    w.screen_height = map.screen_height;
    // In double: the gaze may lie far off screen.
    const double r = static_cast<double>(map.gaze_radius) + 1.0;
    const auto clip = [](double value, int size) {
        return static_cast<int>(std::clamp(value, 0.0, static_cast<double>(size)));
    };
    w.x0 = std::min(clip(std::floor(map.gaze.x - r), map.screen_width), map.screen_width - 1);
    w.y0 = std::min(clip(std::floor(map.gaze.y - r), map.screen_height), map.screen_height - 1);
    w.width = std::max(clip(std::ceil(map.gaze.x + r), map.screen_width) - w.x0, 1);
    w.height = std::max(clip(std::ceil(map.gaze.y + r), map.screen_height) - w.y0, 1);
    return w;
}

bool gaze_gbuffer_pixel(MaskedGBuffer& buffer, const ScreenWindow& window, const LogPolarMap& map,
                        const PrimaryView& view, int x, int y, FoveatedTraceStats& stats,
                        Offset2 jitter) {
    const glm::vec2 centre = pixel_centre(x, y);
    if (!inside_gaze_circle(map, centre)) return false;
    ++stats.gaze_pixels_traced;
    buffer.valid.at(x - window.x0, y - window.y0) = 1.0f;
    raycast_window_pixel(buffer.gbuffer, window, view, x, y, stats.rays, jitter);
    return true;
}

MaskedGBuffer trace_gaze_gbuffer(const LogPolarMap& map, const PrimaryView& view,
                                 FoveatedTraceStats& stats, Offset2 jitter) {
    const ScreenWindow window = gaze_window(map);
    MaskedGBuffer buffer(window.width, window.height);
    if (!map.has_gaze_buffer()) return buffer;
    for (int y = window.y0; y < window.y0 + window.height; ++y)
        for (int x = window.x0; x < window.x0 + window.width; ++x)
            gaze_gbuffer_pixel(buffer, window, map, view, x, y, stats, jitter);
    return buffer;
}

Image ray_pixels(int width, int height, const Image& lp_valid, const Image& screen_points) {
    Image pixels(lp_valid.width, lp_valid.height, 2, -1.0f);
    for (int j = 0; j < lp_valid.height; ++j)
        for (int i = 0; i < lp_valid.width; ++i) {
            if (lp_valid.at(i, j) == 0.0f) continue;
            // A traced texel's point is on screen; a point that is not (or not finite: a
            // corrupted buffer) is not counted rather than written out of bounds.
            const float px = screen_points.at(i, j, 0), py = screen_points.at(i, j, 1);
            if (!(px >= 0.0f && px < static_cast<float>(width) && py >= 0.0f &&
                  py < static_cast<float>(height)))
                continue;
            pixels.at(i, j, 0) = std::floor(px);
            pixels.at(i, j, 1) = std::floor(py);
        }
    return pixels;
}

Image ray_position_counts(int width, int height, const Image& lp_valid, const Image& screen_points,
                          const Image* gaze_valid, const ScreenWindow& gaze) {
    Image counts(width, height, 1, 0.0f);
    const Image pixels = ray_pixels(width, height, lp_valid, screen_points);
    for (int j = 0; j < pixels.height; ++j)
        for (int i = 0; i < pixels.width; ++i)
            if (pixels.at(i, j, 0) >= 0.0f)
                counts.at(static_cast<int>(pixels.at(i, j, 0)),
                          static_cast<int>(pixels.at(i, j, 1))) += 1.0f;
    if (gaze_valid)
        for (int j = 0; j < gaze_valid->height; ++j)
            for (int i = 0; i < gaze_valid->width; ++i)
                if (gaze_valid->at(i, j) != 0.0f) counts.at(gaze.x0 + i, gaze.y0 + j) += 1.0f;
    return counts;
}

}  // namespace fovref
