#version 450
// The Visual-Polar resolve, part 2: one invocation per screen pixel (docs/visual-polar.md,
// "Resolve"; ref/visual_polar/resolve.h), over the pyramid vp_resolve_mips.comp built.
//   c = (x + 1/2, y + 1/2), r = |c - g|, u the forward map's column coordinate, theta = atan
//   (+ 2 pi if negative), with the GPU's sqrt and atan;
//   rho, clamped: s = clamp(u, 1/2, w - 1/2) - 1/2, columns floor(s) and the next, fx = s - i0;
//   each column c on its own rows: v_c = (n_c theta) / 2 pi; level lambda_c = clamp(log2(n_c /
//   (2 pi max(r, 2^-10))), 0, L_c) (0 with resolve=bilinear); levels floor(lambda_c) and the
//   next sampled at v_c / 2^l along phi (texel centres at + 1/2, rows wrap, traced taps only,
//   renormalised) and lerped with the fraction; the columns lerped with fx over those with a
//   value; none: black. lerp(a, b, t) = a + t (b - a), not contracted (`precise`).
// `decisions` receives the decisions each pixel took, (i0, j0, l0 of column i0, l0 of column i1
// or -1 without a weight): the first column and column i0's first row at its level, which the
// diff compares with resolve_tap and resolve_mip_level.
// -DINJECT_BUG injects a typical porting bug: phi treated like rho, clamped instead of wrapped at
// 2 pi: atan's (-pi, pi] kept as it is and the rows clamped to the edge (a sampler's
// CLAMP_TO_EDGE for REPEAT), so the half-plane below theta = 0 reads the column's first row.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "vp_map.glsl"
layout(std430, binding = 0) readonly buffer Colour { float colour[]; };
layout(std430, binding = 1) readonly buffer Valid { float valid[]; };
layout(std430, binding = 2) readonly buffer ColumnRows { int column_rows[]; };
layout(std430, binding = 3) writeonly buffer Result { float result[]; };
layout(std430, binding = 4) writeonly buffer Decisions { vec4 decisions[]; };

vec4 lerp(vec4 a, vec4 b, float t) {
    precise vec4 value = a + t * (b - a);
    return value;
}

// Column `column` of a level (first texel `from`, `rows` rows there) at row coordinate v, over
// the traced taps; false when no traced tap has a weight. `first`: the first row, j0.
bool sample_phi(int from, int column, int rows, float v, out vec4 value, out int first) {
    const float t = v - 0.5;
    const float j0f = floor(t);
    const float fv = t - j0f;
#ifdef INJECT_BUG
    const int j0 = clamp(int(j0f), 0, rows - 1);
    const int j1 = clamp(int(j0f) + 1, 0, rows - 1);
#else
    int j0 = int(j0f);
    if (j0 < 0) j0 += rows;
    if (j0 >= rows) j0 -= rows;
    const int j1 = j0 + 1 == rows ? 0 : j0 + 1;
#endif
    first = j0;
    const int t0 = from + j0 * p.width + column, t1 = from + j1 * p.width + column;
    const bool traced0 = valid[t0] != 0.0;              // weight 1 - fv > 0
    const bool traced1 = fv > 0.0 && valid[t1] != 0.0;  // weight fv
    vec4 a = vec4(0.0), b = vec4(0.0);
    for (int c = 0; c < p.channels; ++c) {
        a[c] = colour[t0 * p.channels + c];
        b[c] = colour[t1 * p.channels + c];
    }
    value = traced0 && traced1 ? lerp(a, b, fv) : traced0 ? a : traced1 ? b : vec4(0.0);
    return traced0 || traced1;
}

// One column at the pixel's angle on its own rows: levels floor(lambda) and the next lerped.
// `first`: level floor(lambda)'s first row.
bool sample_column(int column, float v, float lambda, out vec4 value, out int first) {
    const int rows = column_rows[column];
    const int last = vp_mip_last_level(rows);
    const int l0 = int(floor(lambda));
    const int l1 = min(l0 + 1, last);
    const float f = lambda - float(l0);
    vec4 a, b = vec4(0.0);
    int unused;
    const bool have_a =
        sample_phi(vp_level_offset(l0), column, vp_mip_rows(rows, l0), ldexp(v, -l0), a, first);
    const bool have_b =
        l1 != l0 && f > 0.0 &&
        sample_phi(vp_level_offset(l1), column, vp_mip_rows(rows, l1), ldexp(v, -l1), b, unused);
    value = have_a && have_b ? lerp(a, b, f) : have_a ? a : b;
    return have_a || have_b;
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.screen_width || xy.y >= p.screen_height) return;

    // Polar coordinates of the pixel centre
    const vec2 centre = vec2(xy) + 0.5;
    const float dx = centre.x - p.gaze_x, dy = centre.y - p.gaze_y;
    precise float r = sqrt(dx * dx + dy * dy);
    const float u = vp_forward_radius(r);
    float theta = dx == 0.0 && dy == 0.0 ? 0.0 : atan(dy, dx);
#ifndef INJECT_BUG
    if (theta < 0.0) theta += two_pi;
#endif

    // The two columns along rho (clamped to the first and last texel centres)
    const float s = clamp(u, 0.5, float(p.width) - 0.5) - 0.5;
    const float i0f = floor(s);
    const int columns[2] = {int(i0f), min(int(i0f) + 1, p.width - 1)};
    const float fx = s - i0f;

    // Each column at the pixel's angle on its own rows, at its own phi level
    vec4 values[2] = {vec4(0.0), vec4(0.0)};
    bool have[2] = {false, false};
    vec4 decision = vec4(float(columns[0]), 0.0, 0.0, -1.0);
    for (int k = 0; k < 2; ++k) {
        if (k == 1 && (columns[1] == columns[0] || !(fx > 0.0))) break;
        const int n = column_rows[columns[k]];
        const float v = float(n) * theta / two_pi;
        float lambda = 0.0;
        if (p.mip != 0)
            lambda = clamp(log2(float(n) / (two_pi * max(r, 1.0 / 1024.0))), 0.0,
                           float(vp_mip_last_level(n)));
        int first;
        have[k] = sample_column(columns[k], v, lambda, values[k], first);
        if (k == 0) decision.y = float(first);
        decision[2 + k] = floor(lambda);
    }
    decisions[xy.y * p.screen_width + xy.x] = decision;

    // Lerp of the columns over those with a value (none: black)
    const vec4 pixel = have[0] && have[1] ? lerp(values[0], values[1], fx)
                       : have[0]          ? values[0]
                                          : values[1];
    const int out_index = (xy.y * p.screen_width + xy.x) * p.channels;
    for (int c = 0; c < p.channels; ++c) result[out_index + c] = pixel[c];
}
