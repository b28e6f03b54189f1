#include "ref/analysis/density.h"

#include <algorithm>

#include "ref/core/dmath.h"

namespace fovref {

float relative_acuity(float e) {
    if (e <= 5.79f) return 1.0f;
    const float d = 0.3f * e + 1.0f;
    return 7.49f / (d * d);
}

std::vector<DensityRow> ring_density(const LogPolarMap& map, const RingLayout& layout) {
    std::vector<DensityRow> rows;
    for (int k = 0; k < layout.count; ++k) {
        DensityRow row;
        row.ring = k;
        row.inner_deg = layout.inner(k);
        row.outer_deg = layout.outer(k);
        row.middle_deg = (row.inner_deg + row.outer_deg) * 0.5f;
        row.radius_px = layout.distance_px * dm::tan(dm::radians(row.middle_deg));
        row.acuity = relative_acuity(row.middle_deg);
        row.in_gaze_buffer = map.has_gaze_buffer() && row.radius_px < map.gaze_radius;
        if (row.in_gaze_buffer) {
            row.radial_rays_per_px = row.angular_rays_per_px = 1.0f;
        } else {
            const TexelsPerPixel s = texels_per_pixel(map, std::max(row.radius_px, 0x1p-10f));
            row.radial_rays_per_px = s.radial;
            row.angular_rays_per_px = s.angular;
        }
        rows.push_back(row);
    }
    return rows;
}

}  // namespace fovref
