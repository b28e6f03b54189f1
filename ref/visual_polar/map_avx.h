// The forward map's angle form (vp_forward_angle) of eight screen points at a time with AVX2: the
// same bits as vp_forward_angle, which stays the readable reference (docs/visual-polar.md, "The
// forward map in lanes"). Each lane performs the reference's operations in its order: the
// distance r = sqrt(dx dx + dy dy) and the angle theta = dm::atan2(dy, dx) (its binary64
// arithmetic: two argument halvings, the odd polynomial, the quadrant), + 2 pi if negative, and
// the column: i_f r / (s P(u0)) in the fovea, else P^-1(r / s) as vp_cdf finds it (the largest
// float u with P(u) < e, from a window of floats around a tabulated guess) mapped to the
// buffer's rho. A lane the lanes do not settle (a point on the gaze's row or column, a distance
// that is not finite, an answer more than 8 floats beyond the window, e <= P(2^-16)) runs
// vp_forward_angle itself, as does every lane where SIMD is off, the CPU lacks AVX2 or the map
// is log-polar.
#pragma once

#include <cstddef>

#include "ref/visual_polar/map.h"

namespace fovref {

/// vp_polar and vp_forward_radius of the points (x[l], y[l]) into (u[l], r[l], theta[l]) for
/// the lanes l set in `lane_bits` (any map: the formulas of Visual-Polar's own map); the other
/// lanes' outputs are left as they are. Returns the lanes computed in lanes (the rest ran the
/// reference functions).
int vp_polar_lanes(const VisualPolarMap& map, const float* x, const float* y, int lane_bits,
                   float* u, float* r, float* theta);

/// vp_polar_lanes over the points (x[k], y[k]), k < count, into (u[k], r[k], theta[k]): every
/// group of eight's angle first, then their distances' columns (so that no search branch lies
/// between the angles' binary64 divisions, which then overlap from group to group); the same bits
/// as vp_polar and vp_forward_radius point by point.
void vp_polar_span(const VisualPolarMap& map, const float* x, const float* y, std::size_t count,
                   float* u, float* r, float* theta);

/// vp_forward_angle(map, (x[l], y[l])) into (u[l], t[l]) for the lanes l set in `lane_bits`
/// (bit l: lane l, l < 8); the other lanes' outputs are left as they are. Returns the lanes
/// computed in lanes (the rest ran vp_forward_angle).
int vp_forward_angle_lanes(const VisualPolarMap& map, const float* x, const float* y, int lane_bits,
                           float* u, float* t);

}  // namespace fovref
