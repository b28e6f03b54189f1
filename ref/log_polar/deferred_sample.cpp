#include "ref/log_polar/deferred_sample.h"

#include <cmath>

#include "ref/core/error.h"
#include "ref/raster/raster_avx.h"
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
    if (!raster_fragments_avx_applies()) {
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                deferred_gbuffer_texel(buffer, screen_points, map, table, screen, x, y, stats);
        return buffer;
    }
    // deferred_gbuffer_texel with the sampled pixels' fragments computed eight at a time
    // (raster_fragments_avx: raster_fragment's bits); each texel's writes are its own.
    RasterSite sites[8];
    int texels[8][2];
    int batched = 0;
    const auto flush = [&] {
        RasterFragment fragment[8];
        bool hit[8];
        raster_fragments_avx(screen.scene, screen.frame, sites, batched, fragment, hit);
        for (int l = 0; l < batched; ++l)
            if (hit[l])
                write_rasterized_fragment(buffer.gbuffer, texels[l][0], texels[l][1], screen.scene,
                                          screen.frame, screen.previous_camera,
                                          screen.previous_tan_half, sites[l], fragment[l]);
        batched = 0;
    };
    for (int y = 0; y < map.height; ++y)
        for (int x = 0; x < map.width; ++x) {
            glm::vec2 p{0.0f};
            if (begin_texel(buffer, screen_points, map, table, x, y, p, stats) !=
                TexelStatus::traced)
                continue;
            const int sx = static_cast<int>(std::floor(p.x)),
                      sy = static_cast<int>(std::floor(p.y));
            if (!rasterized_site(screen.scene, screen.primitive_id.at(sx, sy), sx, sy,
                                 sites[batched]))
                continue;
            texels[batched][0] = x;
            texels[batched][1] = y;
            if (++batched == 8) flush();
        }
    if (batched > 0) flush();
    return buffer;
}

glm::vec2 deferred_sample_offset(bool jitter_raster, Offset2 jitter) {
    if (!jitter_raster) return {jitter.x - 0.5f, jitter.y - 0.5f};
    const FixedPoint shift = raster_sample_shift(jitter);
    return -glm::vec2(static_cast<float>(shift.x), static_cast<float>(shift.y)) /
           static_cast<float>(raster_subpixel_scale);
}

}  // namespace fovref
