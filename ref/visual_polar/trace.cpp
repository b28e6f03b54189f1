#include "ref/visual_polar/trace.h"

#include <algorithm>
#include <optional>

#include "ref/core/error.h"

namespace fovref {

namespace {

// The primary ray through screen point p, written to texel (x, y) (valid 1).
void trace_texel(MaskedGBuffer& buffer, int x, int y, glm::vec2 p, int width, int height,
                 const PrimaryView& view, VpTraceStats& stats) {
    ++stats.texels_traced;
    buffer.valid.at(x, y) = 1.0f;
    raycast_sample(buffer.gbuffer, x, y, p, width, height, view, stats.rays);
}

}  // namespace

VpTexel vp_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points, const VisualPolarMap& map,
                         const PrimaryView& view, int x, int y, VpTraceStats& stats) {
    glm::vec2 p{0.0f};
    const VpTexel status = vp_texel_status(map, x, y, p);
    screen_points.at(x, y, 0) = p.x;
    screen_points.at(x, y, 1) = p.y;
    if (status == VpTexel::clipped) {
        ++stats.texels_clipped;
    } else if (status == VpTexel::off_screen) {
        ++stats.texels_off_screen;
    } else {
        trace_texel(buffer, x, y, p, map.screen_width, map.screen_height, view, stats);
    }
    return status;
}

VpTexelTable vp_texel_table(const VisualPolarMap& map) {
    VpTexelTable table{map, Image(map.width, map.height, 2, 0.0f), {}};
    table.status.reserve(static_cast<std::size_t>(map.width) * map.height);
    if (map.log_polar) {  // log-polar's own inverse map, texel by texel
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x) {
                glm::vec2 p{0.0f};
                table.status.push_back(vp_texel_status(map, x, y, p));
                table.screen_points.at(x, y, 0) = p.x;
                table.screen_points.at(x, y, 1) = p.y;
            }
        return table;
    }
    // vp_texel_status texel by texel with each column's rows and radius, and the rows' angles'
    // cosines and sines once per row count (VpRowAngles), the same bits
    const auto w = static_cast<std::size_t>(map.width);
    std::vector<int> rows(w);
    std::vector<float> radius(w);
    std::vector<std::optional<VpRowAngles>> angles(static_cast<std::size_t>(map.height) + 1);
    for (std::size_t i = 0; i < w; ++i) {
        rows[i] = vp_column_rows(map, static_cast<int>(i));
        radius[i] = vp_column_radius(map, static_cast<int>(i));
        auto& a = angles[static_cast<std::size_t>(rows[i])];
        if (!a) a.emplace(rows[i]);
    }
    for (int y = 0; y < map.height; ++y)
        for (std::size_t i = 0; i < w; ++i) {
            if (y >= rows[i]) {
                table.status.push_back(VpTexel::clipped);
                continue;
            }
            const VpRowAngles& a = *angles[static_cast<std::size_t>(rows[i])];
            const auto j = static_cast<std::size_t>(y);
            const glm::vec2 p = vp_texel_point(map, radius[i], a.cosine[j], a.sine[j]);
            table.status.push_back(vp_on_screen(map, p) ? VpTexel::traced : VpTexel::off_screen);
            float* point =
                &table.screen_points.data[table.screen_points.index(static_cast<int>(i), y)];
            point[0] = p.x, point[1] = p.y;
        }
    return table;
}

MaskedGBuffer trace_vp_gbuffer(const VisualPolarMap& map, const PrimaryView& view,
                               Image& screen_points, VpTraceStats& stats,
                               const VpTexelTable* table) {
    MaskedGBuffer buffer(map.width, map.height);
    if (!table) {
        screen_points = Image(map.width, map.height, 2, 0.0f);
        for (int y = 0; y < map.height; ++y)
            for (int x = 0; x < map.width; ++x)
                vp_gbuffer_texel(buffer, screen_points, map, view, x, y, stats);
        return buffer;
    }
    // vp_gbuffer_texel with the table's status and point; the fovea's columns (rows set by the
    // clip) by vp_gbuffer_texel itself where the table was made for another clip
    FOVREF_CHECK(table->map.same_forward(map), "a texel table made for another map");
    screen_points = table->screen_points;
    const int first_column = table->map == map ? 0 : std::min(map.fovea_columns, map.width);
    for (int y = 0; y < map.height; ++y) {
        for (int x = 0; x < first_column; ++x)
            vp_gbuffer_texel(buffer, screen_points, map, view, x, y, stats);
        for (int x = first_column; x < map.width; ++x) {
            const VpTexel status = table->status[static_cast<std::size_t>(y) * map.width + x];
            if (status == VpTexel::clipped) {
                ++stats.texels_clipped;
            } else if (status == VpTexel::off_screen) {
                ++stats.texels_off_screen;
            } else {
                const glm::vec2 p{screen_points.at(x, y, 0), screen_points.at(x, y, 1)};
                trace_texel(buffer, x, y, p, map.screen_width, map.screen_height, view, stats);
            }
        }
    }
    return buffer;
}

MaskedGBuffer trace_point_gbuffer(const std::vector<glm::vec2>& points, int width, int height,
                                  const PrimaryView& view, VpTraceStats& stats) {
    FOVREF_CHECK(!points.empty(), "trace_point_gbuffer: no points");
    MaskedGBuffer buffer(static_cast<int>(points.size()), 1);
    for (std::size_t k = 0; k < points.size(); ++k) {
        const glm::vec2 p = points[k];
        if (!(p.x >= 0.0f && p.y >= 0.0f && p.x < static_cast<float>(width) &&
              p.y < static_cast<float>(height))) {
            ++stats.texels_off_screen;
            continue;
        }
        trace_texel(buffer, static_cast<int>(k), 0, p, width, height, view, stats);
    }
    return buffer;
}

}  // namespace fovref
