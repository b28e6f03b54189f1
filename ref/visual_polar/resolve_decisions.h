// The threshold decisions of the Visual-Polar resolve and their margins, for diffing a port
// (docs/visual-polar.md, "The resolve's decisions"; the log-polar resolve's are
// ref/log_polar/resolve_decisions.h, whose buffers these fill).
//
// For each screen pixel, with u, r and theta its polar coordinates (vp_polar_pixel):
//   tap        (i0, j0): i0 = floor(clamp(s, 0, w - 1)) with s = u - 1/2 (vp_rho_columns), and
//              column i0's first row at its level l0, j0 = floor(t) wrapped with
//              t = v_i0 / 2^l0 - 1/2 and v_i0 = (n_i0 theta) / 2 pi (vp_phi_rows);
//   mip_level  (l0 of column i0, l0 of column i1 or -1 when i1 has no weight),
//              l0 = floor(vp_mip_level(n, r)); only with the phi mips.
// Margins:
//   tap_margin  the smaller of s's distance from the nearest integer in [1, w - 1] (columns,
//               texels) and t's from the nearest integer (rows of level l0);
//   mip_margin  the smallest, over the columns read, of the unclamped level's
//               (vp_mip_lambda) distance from the nearest integer in [1, L_c] (levels).
#pragma once

#include "ref/log_polar/resolve_decisions.h"
#include "ref/visual_polar/resolve.h"

namespace fovref {

/// The decisions of the Visual-Polar resolve for `table`'s map (`mip`: with the phi mips).
ResolveDecisions vp_resolve_decisions(const VpForwardTable& table, bool mip);

}  // namespace fovref
