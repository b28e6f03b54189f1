#version 450
// Pass 2 of the end-to-end frame pass (docs/foveation.md, "Pass 2"), one invocation per screen
// pixel (x, y), centre c = (x + 1/2, y + 1/2):
//   c inside the gaze circle (only pixels of the gaze window are tested): the gaze buffer's
//     colour of that pixel;
//   else (u, v) = forward(c) and the bilinear lookup over the traced texels: columns clamp
//     (s = clamp(u, 1/2, w - 1/2) - 1/2), rows wrap (t = v - 1/2); per row both taps traced ->
//     lerp by fu (weight 1), one -> that tap (weight 1 - fu or fu); the rows' weights W0 =
//     (1 - fv) w0, W1 = fv w1 -> lerp by fv (equal row weights) or W1 / (W0 + W1); none: black.
//   lerp(a, b, t) = a + t (b - a), not contracted.
// `decisions` receives the decisions each pixel took, (i0, j0, 0, 0), or -1 from the gaze buffer
// (the diff compares them with resolve_tap).
// -DINJECT_BUG injects the frame pass's porting bug here too: texel centres at integer
// coordinates (no -1/2 before the taps), consistent with frame_trace.comp's.
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "frame_common.glsl"
#include "frame_map.glsl"
layout(std430, binding = 1) readonly buffer LogPolar { float lp[]; };   // RECORD per texel
layout(std430, binding = 2) readonly buffer Gaze { float gaze[]; };     // RECORD per pixel
layout(std430, binding = 3) writeonly buffer Final { float final_color[]; };
layout(std430, binding = 4) writeonly buffer Decisions { vec4 decisions[]; };

float lerp(float a, float b, float t) {
    precise float r = a + t * (b - a);
    return r;
}

bool traced(int i, int j) { return lp[(j * P.screen.z + i) * RECORD + R_VALID] != 0.0; }
float colour(int i, int j, int c) { return lp[(j * P.screen.z + i) * RECORD + R_COLOR + c]; }

// One row of the lookup: the lerp in u over the traced taps; returns the row's weight
float sample_row(int i0, int i1, int j, float fu, out vec3 row) {
    const bool t0 = traced(i0, j), t1 = traced(i1, j);
    row = vec3(0.0);
    if (t0 && t1) {
        for (int c = 0; c < 3; ++c) row[c] = lerp(colour(i0, j, c), colour(i1, j, c), fu);
        return 1.0;
    }
    if (!t0 && !t1) return 0.0;
    for (int c = 0; c < 3; ++c) row[c] = colour(t0 ? i0 : i1, j, c);
    return t0 ? 1.0 - fu : fu;
}

// The bilinear lookup over the traced texels at buffer coordinates uv; `first`: its first tap
vec3 sample_bilinear(vec2 uv, out ivec2 first) {
    const int w = P.screen.z, h = P.screen.w;
#ifdef INJECT_BUG
    const float s = clamp(uv.x, 0.5, float(w) - 0.5), t = uv.y;
#else
    const float s = clamp(uv.x, 0.5, float(w) - 0.5) - 0.5, t = uv.y - 0.5;
#endif
    const float fi = floor(s), fj = floor(t);
    const int i0 = int(fi), i1 = min(i0 + 1, w - 1);
    const float fu = s - fi, fv = t - fj;
    int j0 = int(fj);
    while (j0 < 0) j0 += h;
    while (j0 >= h) j0 -= h;
    const int j1 = j0 + 1 == h ? 0 : j0 + 1;
    first = ivec2(i0, j0);
    vec3 row0, row1;
    const float w0 = sample_row(i0, i1, j0, fu, row0);
    const float w1 = sample_row(i0, i1, j1, fu, row1);
    const float weight0 = (1.0 - fv) * w0, weight1 = fv * w1;
    if (weight0 > 0.0 && weight1 > 0.0) {
        const float t01 = w0 == w1 ? fv : weight1 / (weight0 + weight1);
        return vec3(lerp(row0.x, row1.x, t01), lerp(row0.y, row1.y, t01),
                    lerp(row0.z, row1.z, t01));
    }
    if (weight0 > 0.0) return row0;
    if (weight1 > 0.0) return row1;
    return vec3(0.0);
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= P.screen.x || xy.y >= P.screen.y) return;
    const vec2 centre = vec2(xy) + 0.5;
    const ivec2 g = xy - P.window.xy;
    vec3 result;
    ivec2 first = ivec2(-1);
    if (P.launch.y != 0 && all(greaterThanEqual(g, ivec2(0))) && all(lessThan(g, P.window.zw)) &&
        inside_gaze_circle(centre)) {
        const int k = (g.y * P.window.z + g.x) * RECORD + R_COLOR;
        result = vec3(gaze[k], gaze[k + 1], gaze[k + 2]);
    } else {
        result = sample_bilinear(lp_forward(centre), first);
    }
    decisions[xy.y * P.screen.x + xy.x] = vec4(vec2(first), 0.0, 0.0);
    const int o = (xy.y * P.screen.x + xy.x) * 3;
    final_color[o] = result.x;
    final_color[o + 1] = result.y;
    final_color[o + 2] = result.z;
}
