// The Visual-Polar map (docs/visual-polar.md; ref/visual_polar/map.h) as the resolve needs it,
// written from the docs with the GPU's own sqrt, atan and log2:
//   P(u) = 25.09 u^4 + 0.1680 u^3 + 27.61 u^2 + 23.87 u + 3.232 for u > u0 = 0.0965, 18.64 sqrt(u)
//     below (Horner, binary32, not contracted: `precise`);
//   P^-1(e) by bisection on [0, 1], at most 64 steps, until the midpoint equals an endpoint;
//   forward radius: r < s P(u0): u = i_f r / (s P(u0)); else U = P^-1(r / s),
//     u = w (rho_f + (U - u0)(1 - rho_f) / (1 - u0)), rho_f = i_f / w.
// The pyramid's layout (ref/visual_polar/resolve.h): level k is w x ceil(h / 2^k), the levels one
// after the other in one buffer; column i has ceil(n_i / 2^k) rows at level k.
// Both shaders of the resolve (vp_resolve_mips.comp, vp_resolve.comp) take these push constants
// (VpResolveParameters in passes/vp_resolve.cpp).
layout(push_constant) uniform Parameters {
    int screen_width, screen_height;  // W x H
    int width, height;                // the buffer w x h
    int fovea_columns;                // i_f
    int channels;                     // of vp_color
    int levels;                       // of the pyramid: 1 + ceil(log2(max n_i))
    int mip;                          // 1: resolve=mip, 0: bilinear
    float gaze_x, gaze_y;
    float scale;         // s, pixels per model degree
    float fovea_radius;  // s P(u0), pixels
} p;

const float two_pi = 6.28318530717958647692;
const float vp_u0 = 0.0965;

// The fitted inverse CDF P(u) in model degrees.
float vp_inverse_cdf(float u) {
    if (u <= vp_u0) return 18.64 * sqrt(max(u, 0.0));
    precise float value = (((25.09 * u + 0.1680) * u + 27.61) * u + 23.87) * u + 3.232;
    return value;
}

// P^-1(e) by bisection in binary32; 0 for e <= 0, 1 for e >= P(1).
float vp_cdf(float e) {
    if (!(e > 0.0)) return 0.0;
    if (e >= vp_inverse_cdf(1.0)) return 1.0;
    float lo = 0.0, hi = 1.0;
    for (int step = 0; step < 64; ++step) {
        const float mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi) break;
        if (vp_inverse_cdf(mid) < e)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

// The column coordinate u (texel centres at + 1/2) of a screen point at distance r from the gaze.
float vp_forward_radius(float r) {
    if (r < p.fovea_radius) return float(p.fovea_columns) * r / p.fovea_radius;
    const float big_u = vp_cdf(r / p.scale);
    const float rho_f = float(p.fovea_columns) / float(p.width);
    precise float rho = rho_f + (big_u - vp_u0) * (1.0 - rho_f) / (1.0 - vp_u0);
    return float(p.width) * rho;
}

// Rows of a column of `rows` rows at pyramid level `level`: ceil-halved `level` times.
int vp_mip_rows(int rows, int level) {
    for (int k = 0; k < level; ++k) rows = (rows + 1) / 2;
    return rows;
}

// The first level at which a column of `rows` rows has one row: ceil(log2(rows)).
int vp_mip_last_level(int rows) {
    int level = 0;
    for (; rows > 1; ++level) rows = (rows + 1) / 2;
    return level;
}

// The first texel of pyramid level `level` in the level-after-level buffer.
int vp_level_offset(int level) {
    int offset = 0, rows = p.height;
    for (int k = 0; k < level; ++k) {
        offset += p.width * rows;
        rows = (rows + 1) / 2;
    }
    return offset;
}
