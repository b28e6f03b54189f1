#include "ref/visual_polar/resolve_decisions.h"

#include <algorithm>
#include <cmath>

namespace fovref {

namespace {

constexpr float two_pi = 6.28318530717958647692f;  // as the resolve's

}  // namespace

ResolveDecisions vp_resolve_decisions(const VpForwardTable& table, bool mip) {
    const VisualPolarMap& map = table.map;
    const int sw = map.screen_width, sh = map.screen_height;
    ResolveDecisions d;
    d.tap = Image(sw, sh, 2, -1.0f);
    d.tap_margin = Image(sw, sh, 1, no_threshold);
    if (mip) {
        d.mip_level = Image(sw, sh, 2, -1.0f);
        d.mip_margin = Image(sw, sh, 1, no_threshold);
    }
    for (int y = 0; y < sh; ++y)
        for (int x = 0; x < sw; ++x) {
            const float* p = &table.polar.data[table.polar.index(x, y)];
            const float u = p[0], r = p[1], theta = p[2];
            const VpColumns rho = vp_rho_columns(map.width, u);
            float margin = floor_margin(u - 0.5f, 1, map.width - 1);
            float level_margin = no_threshold;
            for (int k = 0; k < rho.count; ++k) {
                const int column = k == 0 ? rho.i0 : rho.i1;
                const int n = vp_column_rows(map, column);
                int l0 = 0;
                if (mip) {
                    const float lambda = vp_mip_lambda(n, r);
                    const int last = vp_mip_last_level(n);
                    l0 = static_cast<int>(std::floor(vp_mip_level(n, r)));
                    d.mip_level.at(x, y, k) = static_cast<float>(l0);
                    level_margin = std::min(level_margin, floor_margin(lambda, 1, last));
                }
                if (k > 0) continue;
                // Column i0's row at level l0: v / 2^l0, exact (a power of two)
                const float v = static_cast<float>(n) * theta / two_pi;
                const float v_level = v * (1.0f / static_cast<float>(1 << l0));
                const VpRows phi = vp_phi_rows(vp_mip_rows(n, l0), v_level);
                d.tap.at(x, y, 0) = static_cast<float>(rho.i0);
                d.tap.at(x, y, 1) = static_cast<float>(phi.j0);
                margin = std::min(margin, wrap_margin(v_level - 0.5f));
            }
            d.tap_margin.at(x, y) = margin;
            if (mip) d.mip_margin.at(x, y) = level_margin;
        }
    return d;
}

}  // namespace fovref
