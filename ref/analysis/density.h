// Sampling density of a log-polar map (Lund §5.2 `mid_range_res`; SPEC §5.6): how many rays per
// screen pixel the buffer spends along the radius and along the circle, at the middle of each
// error ring, next to the visual acuity (Koskela's model) for comparison. `fovref density`
// prints and plots it; the mip resolve's level uses the same texels per pixel.
//
//   texels per pixel at distance r from the gaze: texels_per_pixel of the map
//     (ref/log_polar/map.h, the map's Jacobian);
//   rays per pixel on each axis = s (Lund reports 1/s, the pixels between adjacent rays, as his
//   "resolution"); inside the gaze circle both are 1 (one ray per pixel).
//   ring k's middle: e = (inner + outer) / 2 degrees, r = d_px tan(e) pixels (dm::tan).
//   acuity (Koskela P3/P4): m(e) = 1 for e <= 5.79 deg, 7.49 / (0.3 e + 1)^2 beyond (relative
//   to the fovea).
// Binary32 with the deterministic functions, like the passes.
#pragma once

#include <vector>

#include "ref/log_polar/map.h"
#include "ref/metrics/rings.h"

namespace fovref {

/// Koskela's relative visual acuity at eccentricity e (degrees).
float relative_acuity(float eccentricity_deg);

struct DensityRow {
    int ring = 0;
    float inner_deg = 0.0f, outer_deg = 0.0f, middle_deg = 0.0f;
    float radius_px = 0.0f;            ///< r = d_px tan(middle)
    bool in_gaze_buffer = false;       ///< r < r_G
    float radial_rays_per_px = 0.0f;   ///< s_u (1 in the gaze buffer)
    float angular_rays_per_px = 0.0f;  ///< s_v (1 in the gaze buffer)
    float acuity = 0.0f;               ///< m(middle)
};

/// One row per ring of `layout` (which must share the map's gaze and viewing distance).
std::vector<DensityRow> ring_density(const LogPolarMap& map, const RingLayout& layout);

}  // namespace fovref
