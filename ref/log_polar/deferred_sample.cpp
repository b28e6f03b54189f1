#include "ref/log_polar/deferred_sample.h"

#include <cmath>
#include <utility>

#include "ref/core/error.h"
#include "ref/raster/rasterizer.h"

namespace fovref {

TexelStatus deferred_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points,
                                   const LogPolarMap& map, const LpInverseTable& table,
                                   const ScreenGBuffer& screen, int x, int y,
                                   FoveatedTraceStats& stats) {
    glm::vec2 p{0.0f};
    const TexelStatus status = begin_texel(buffer, screen_points, map, table, x, y, p, stats);
    if (status != TexelStatus::traced) return status;
    const int sx = static_cast<int>(std::floor(p.x)), sy = static_cast<int>(std::floor(p.y));
    GBuffer& g = buffer.gbuffer;
    const std::pair<Image*, const Image*> channels[] = {
        {&g.view_depth, &screen.view_depth},
        {&g.hit_distance, &screen.hit_distance},
        {&g.world_position, &screen.world_position},
        {&g.shading_normal, &screen.shading_normal},
        {&g.geometric_normal, &screen.geometric_normal},
        {&g.albedo, &screen.albedo},
        {&g.material_id, &screen.material_id},
        {&g.primitive_id, &screen.primitive_id},
        {&g.motion, &screen.motion}};
    for (const auto& [to, from] : channels)
        for (int c = 0; c < to->channels; ++c) to->at(x, y, c) = from->at(sx, sy, c);
    return status;
}

MaskedGBuffer sample_lp_gbuffer(const LogPolarMap& map, const ScreenGBuffer& screen,
                                Image& screen_points, FoveatedTraceStats& stats,
                                glm::vec2 screen_offset) {
    FOVREF_CHECK_EQ(screen.primitive_id.width, map.screen_width, "screen G-buffer width");
    FOVREF_CHECK_EQ(screen.primitive_id.height, map.screen_height, "screen G-buffer height");
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
