#version 450
// Pass 2 of Gupta's stereo (docs/foveation.md, "Stereo"; Gupta 2019 §2-3), as a GPU developer
// writes it from the docs: one invocation per screen pixel (x, y) of the W x H screen; eye
// e = floor(x / (W/2)); the eye-local centre c = (x - e W/2 + 1/2, y + 1/2); with the barrel
// distortion its source
//   q = (c - eye centre) / (W/4),  s = eye centre + (W/4) q (1 + k1 |q|^2 + k2 |q|^4)
// (|q|^2 = q.x q.x + q.y q.y, |q|^4 = |q|^2 |q|^2; black when s leaves the eye's image); then
// the bilinear lookup (lp_bilinear.glsl) at forward(s) (lp_map.glsl: both eyes share one map
// on the W/2 x H sub-screen) in eye e's half of the 2w x h buffer, wrapping and clamping within
// that half. `lookups` receives each pixel's (u, v, 0, source) for the port's flip report
// (source: 1 buffer, 2 black: no traced tap, 3 black: outside the lens).
// -DINJECT_BUG injects a typical porting bug: the barrel distortion applied the wrong way (the
// source divided by the factor, as the inverse distortion, instead of multiplied).
#extension GL_GOOGLE_include_directive : require
#include "lp_map.glsl"
#include "lp_bilinear.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer MapBlock { LpMap map; };
layout(std430, binding = 1) readonly buffer Colour { float colour[]; };  // 2w x h
layout(std430, binding = 2) readonly buffer Valid { float valid[]; };
layout(std430, binding = 3) writeonly buffer Result { float result[]; };
layout(std430, binding = 4) writeonly buffer Lookups { vec4 lookups[]; };
// (i0, j0): the lookup's first tap in the side-by-side buffer's columns; -1 outside the lens
layout(std430, binding = 5) writeonly buffer Decisions { vec4 decisions[]; };
layout(push_constant) uniform Parameters {
    int screen_width, screen_height, channels, barrel;
    float k1, k2;
} p;

// Gupta's barrel distortion: the source of eye-local point c
vec2 barrel_source(vec2 c) {
    const float half_width = float(map.screen_width) * 0.5;
    const vec2 centre = vec2(half_width, float(map.screen_height) * 0.5);
    const vec2 q = (c - centre) / half_width;
    precise float q2 = q.x * q.x + q.y * q.y;
    precise float scale = 1.0 + p.k1 * q2 + p.k2 * (q2 * q2);
#ifdef INJECT_BUG
    precise vec2 s = centre + half_width * (q / scale);
#else
    precise vec2 s = centre + half_width * (q * scale);
#endif
    return s;
}

vec4 load(int texel) {
    vec4 c = vec4(0.0);
    for (int k = 0; k < p.channels; ++k) c[k] = colour[texel * p.channels + k];
    return c;
}

// The bilinear lookup of eye `eye`'s half at uv; false: no traced tap
bool sample_eye(int eye, vec2 uv, out vec4 value, out ivec2 first) {
    const int w = map.width, h = map.height;
    const LpTaps taps = lp_bilinear_taps(uv, w, h);
    first = ivec2(eye * w + taps.i0, taps.j0);
    const ivec2 tap[4] = ivec2[4](ivec2(taps.i0, taps.j0), ivec2(taps.i1, taps.j0),
                                  ivec2(taps.i0, taps.j1), ivec2(taps.i1, taps.j1));
    bvec4 traced;
    vec4 c[4];
    for (int k = 0; k < 4; ++k) {
        const int texel = tap[k].y * 2 * w + eye * w + tap[k].x;
        traced[k] = valid[texel] != 0.0;
        c[k] = load(texel);
    }
    return lp_bilinear_blend(taps, traced, c, value);
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.screen_width || xy.y >= p.screen_height) return;
    const int pixel = xy.y * p.screen_width + xy.x;
    const int eye = xy.x / map.screen_width;
    vec2 c = vec2(xy.x - eye * map.screen_width, xy.y) + 0.5;
    vec4 value = vec4(0.0);
    float source = 3.0;
    vec2 uv = vec2(0.0);
    ivec2 first = ivec2(-1);
    if (p.barrel != 0) c = barrel_source(c);
    if (p.barrel == 0 || lp_on_screen(map, c)) {
        uv = lp_forward(map, c);
        source = sample_eye(eye, uv, value, first) ? 1.0 : 2.0;
    }
    decisions[pixel] = vec4(vec2(first), 0.0, 0.0);
    for (int k = 0; k < p.channels; ++k) result[pixel * p.channels + k] = value[k];
    lookups[pixel] = vec4(uv, 0.0, source);
}
