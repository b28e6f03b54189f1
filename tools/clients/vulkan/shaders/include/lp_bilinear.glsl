// Pass 2's bilinear lookup in a log-polar buffer over its traced texels (docs/foveation.md,
// "Pass 2"; ref/log_polar/resolve.cpp), split into its two halves so that a shader keeps its own
// buffers (GLSL cannot pass them):
//   lp_bilinear_taps   the four taps of buffer coordinates (u, v) in a w x h buffer:
//                      s = clamp(u, 1/2, w - 1/2) - 1/2, i0 = floor(s), i1 = min(i0 + 1, w - 1),
//                      fu = s - i0; t = v - 1/2, j0 = floor(t) mod h, j1 = (j0 + 1) mod h
//                      (v wraps: it is the angle), fv = t - floor(t)
//   lp_bilinear_blend  the lerps over the traced taps: a row with both taps traced is
//                      lerp(c(i0), c(i1), fu) with weight 1, with one that tap with weight 1 - fu
//                      (i0) or fu (i1); W0 = (1 - fv) w(j0), W1 = fv w(j1); both > 0:
//                      lerp(row0, row1, t), t = fv when w(j0) = w(j1), else W1 / (W0 + W1); one:
//                      that row; none: black (returns false)
// lerp(a, b, t) = a + t (b - a), per channel, `precise` (unfused, as the reference). Up to four
// channels in a vec4 (the channels are independent, so vec4 arithmetic is the reference's).

struct LpTaps {
    int i0, i1, j0, j1;
    float fu, fv;
};

LpTaps lp_bilinear_taps(vec2 uv, int width, int height) {
    LpTaps taps;
    const float s = clamp(uv.x, 0.5, float(width) - 0.5) - 0.5;
    const float i0 = floor(s);
    taps.i0 = int(i0);
    taps.i1 = min(taps.i0 + 1, width - 1);
    taps.fu = s - i0;
    const float t = uv.y - 0.5;
    const float j0 = floor(t);
    taps.fv = t - j0;
    taps.j0 = ((int(j0) % height) + height) % height;
    taps.j1 = taps.j0 + 1 == height ? 0 : taps.j0 + 1;
    return taps;
}

vec4 lp_lerp(vec4 a, vec4 b, float t) {
    precise vec4 value = a + t * (b - a);
    return value;
}

// One row: both taps traced -> their lerp, weight 1; one -> that tap, weight 1 - fu or fu
float lp_bilinear_row(float fu, bool traced0, bool traced1, vec4 c0, vec4 c1, out vec4 row) {
    row = vec4(0.0);
    if (traced0 && traced1) {
        row = lp_lerp(c0, c1, fu);
        return 1.0;
    }
    if (traced0 || traced1) {
        row = traced0 ? c0 : c1;
        return traced0 ? 1.0 - fu : fu;
    }
    return 0.0;
}

// The lookup from the taps' values c and traced flags, in the order (i0, j0), (i1, j0),
// (i0, j1), (i1, j1); false (black) when no traced tap has a non-zero weight
bool lp_bilinear_blend(LpTaps taps, bvec4 traced, vec4 c[4], out vec4 value) {
    vec4 row0, row1;
    const float w0 = lp_bilinear_row(taps.fu, traced.x, traced.y, c[0], c[1], row0);
    const float w1 = lp_bilinear_row(taps.fu, traced.z, traced.w, c[2], c[3], row1);
    const float weight0 = (1.0 - taps.fv) * w0;
    const float weight1 = taps.fv * w1;
    value = vec4(0.0);
    if (weight0 > 0.0 && weight1 > 0.0) {
        const float t = w0 == w1 ? taps.fv : weight1 / (weight0 + weight1);
        value = lp_lerp(row0, row1, t);
    } else if (weight0 > 0.0) {
        value = row0;
    } else if (weight1 > 0.0) {
        value = row1;
    } else {
        return false;
    }
    return true;
}
