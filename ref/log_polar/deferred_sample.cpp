#include "ref/log_polar/deferred_sample.h"

#include <cmath>

#include "ref/core/error.h"
#include "ref/raster/rasterizer.h"

namespace fovref {

TexelStatus deferred_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points,
                                   const LogPolarMap& map, const LpInverseTable& table,
                                   const RasterizedScreen& screen, int x, int y,
                                   FoveatedTraceStats& stats) {
    glm::vec2 p{0.0f};
    const TexelStatus status = begin_texel(buffer, screen_points, map, table, x, y, p, stats);
    if (status != TexelStatus::traced) return status;
    const int sx = static_cast<int>(std::floor(p.x)), sy = static_cast<int>(std::floor(p.y));
    // The G-buffer's pixel (sx, sy): background stays the texel's background values.
    write_rasterized_pixel(buffer.gbuffer, x, y, screen.scene, screen.frame, screen.previous_camera,
                           screen.previous_tan_half, screen.primitive_id.at(sx, sy), sx, sy);
    return status;
}

MaskedGBuffer sample_lp_gbuffer(const LogPolarMap& map, const RasterizedScreen& screen,
                                Image& screen_points, FoveatedTraceStats& stats,
                                glm::vec2 screen_offset) {
    FOVREF_CHECK_EQ(screen.primitive_id.width, map.screen_width, "screen G-buffer width");
    FOVREF_CHECK_EQ(screen.primitive_id.height, map.screen_height, "screen G-buffer height");
    FOVREF_CHECK(screen.frame.width == map.screen_width && screen.frame.height == map.screen_height,
                 "a rasterizer frame of another screen");
    MaskedGBuffer buffer(map.width, map.height);
    screen_points = Image(map.width, map.height, 2, 0.0f);
    const LpInverseTable table = lp_inverse_table(map, Offset2{}, screen_offset);
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x)
            deferred_gbuffer_texel(buffer, screen_points, map, table, screen, x, y, stats);
    return buffer;
}

glm::vec2 deferred_sample_offset(bool jitter_raster, Offset2 jitter) {
    if (!jitter_raster) return {jitter.x - 0.5f, jitter.y - 0.5f};
    const FixedPoint shift = raster_sample_shift(jitter);
    return -glm::vec2(static_cast<float>(shift.x), static_cast<float>(shift.y)) /
           static_cast<float>(raster_subpixel_scale);
}

}  // namespace fovref
