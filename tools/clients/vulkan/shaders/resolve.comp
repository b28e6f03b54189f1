#version 450
// Pass 2 of the log-polar modes (docs/foveation.md, "Pass 2" and "The mip resolve"; Lund §3.3
// inverse transform, Meng §2.2 and §5.1), as a GPU developer writes it from the docs: one
// invocation per screen pixel (x, y), centre c = (x + 1/2, y + 1/2):
//   |c - g| < r_G inside the gaze buffer's window: that buffer's pixel (x - x0, y - y0)
//   otherwise (u, v) = forward(c) (shaders/include/lp_map.glsl) and
//     bilinear: the lookup over the traced texels of level 0 (lp_bilinear.glsl)
//     mip:      lambda = log2(max(s_u, s_v)) at r = max(|c - g|, 2^-10), clamped to
//               [0, levels - 1]; levels l0 = floor(lambda) and l0 + 1 looked up at
//               (u, v) / 2^l and lerped by f = lambda - l0 (a level without a traced tap gives
//               way to the other; neither: black)
// The pyramid (shaders/resolve_mips.comp) lies level after level in one buffer. `lookups`
// receives each pixel's (u, v, lambda, source) (source: 0 gaze buffer, 1 log-polar buffer,
// 2 black), `decisions` the decisions the pixel took, (i0, j0, l0, 0): the first tap of level l0
// and l0 (-1 from the gaze buffer), which the diff compares with resolve_tap and
// resolve_mip_level.
// -DINJECT_BUG injects a typical porting bug: v (the angle) not wrapped at the buffer's seam,
// the rows clamped like the columns.
#extension GL_GOOGLE_include_directive : require
#include "lp_map.glsl"
#include "lp_bilinear.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer MapBlock { LpMap map; };
// Each level's first texel in the pyramid, its width and height: (offset, w, h, 0)
layout(std430, binding = 1) readonly buffer Levels { ivec4 levels[]; };
layout(std430, binding = 2) readonly buffer Colour { float colour[]; };
layout(std430, binding = 3) readonly buffer Valid { float valid[]; };
layout(std430, binding = 4) readonly buffer GazeColour { float gaze_colour[]; };
layout(std430, binding = 5) writeonly buffer Result { float result[]; };
layout(std430, binding = 6) writeonly buffer Lookups { vec4 lookups[]; };
layout(std430, binding = 7) writeonly buffer Decisions { vec4 decisions[]; };
layout(push_constant) uniform Parameters {
    int screen_width, screen_height, channels, level_count, mip;
    int gaze_x0, gaze_y0, gaze_width, gaze_height;  // gaze_width = 0: no gaze buffer
} p;

// The taps of (u, v) in a w x h level
LpTaps taps_of(vec2 uv, int width, int height) {
    LpTaps taps = lp_bilinear_taps(uv, width, height);
#ifdef INJECT_BUG
    taps.j0 = clamp(int(floor(uv.y - 0.5)), 0, height - 1);
    taps.j1 = min(taps.j0 + 1, height - 1);
#endif
    return taps;
}

vec4 load(int texel) {
    vec4 c = vec4(0.0);
    for (int k = 0; k < p.channels; ++k) c[k] = colour[texel * p.channels + k];
    return c;
}

// The bilinear lookup of level `level` at its coordinates uv; false: no traced tap. `first`:
// the first tap (i0, j0)
bool sample_level(int level, vec2 uv, out vec4 value, out ivec2 first) {
    const ivec4 l = levels[level];
    const LpTaps taps = taps_of(uv, l.y, l.z);
    first = ivec2(taps.i0, taps.j0);
    const ivec2 tap[4] = ivec2[4](ivec2(taps.i0, taps.j0), ivec2(taps.i1, taps.j0),
                                  ivec2(taps.i0, taps.j1), ivec2(taps.i1, taps.j1));
    bvec4 traced;
    vec4 c[4];
    for (int k = 0; k < 4; ++k) {
        const int texel = l.x + tap[k].y * l.y + tap[k].x;
        traced[k] = valid[texel] != 0.0;
        c[k] = load(texel);
    }
    return lp_bilinear_blend(taps, traced, c, value);
}

// The mip resolve of centre c at buffer coordinates uv; returns lambda. `first`: level l0's first
// tap, `level`: l0
float sample_mip(vec2 c, vec2 uv, out vec4 value, out bool any, out ivec2 first, out int level) {
    const float r = max(lp_gaze_distance(map, c), 1.0 / 1024.0);
    const vec2 s = lp_texels_per_pixel(map, r);
    const float lambda = clamp(log2(max(s.x, s.y)), 0.0, float(p.level_count - 1));
    const int l0 = int(floor(lambda));
    const int l1 = min(l0 + 1, p.level_count - 1);
    const float f = lambda - float(l0);
    vec4 a, b = vec4(0.0);
    ivec2 unused;
    level = l0;
    const bool have_a = sample_level(l0, ldexp(uv, ivec2(-l0)), a, first);
    const bool have_b =
        l1 != l0 && f > 0.0 && sample_level(l1, ldexp(uv, ivec2(-l1)), b, unused);
    precise vec4 blend = a + f * (b - a);
    value = have_a && have_b ? blend : (have_a ? a : b);
    any = have_a || have_b;
    return lambda;
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.screen_width || xy.y >= p.screen_height) return;
    const int pixel = xy.y * p.screen_width + xy.x;
    const vec2 c = vec2(xy) + 0.5;
    const ivec2 g = xy - ivec2(p.gaze_x0, p.gaze_y0);
    if (p.gaze_width > 0 && g.x >= 0 && g.y >= 0 && g.x < p.gaze_width && g.y < p.gaze_height &&
        lp_gaze_distance(map, c) < map.gaze_radius) {
        const int source = g.y * p.gaze_width + g.x;
        for (int k = 0; k < p.channels; ++k)
            result[pixel * p.channels + k] = gaze_colour[source * p.channels + k];
        lookups[pixel] = vec4(0.0);
        decisions[pixel] = vec4(-1.0, -1.0, -1.0, 0.0);
        return;
    }
    const vec2 uv = lp_forward(map, c);
    vec4 value;
    bool any;
    float lambda = 0.0;
    ivec2 first;
    int level = 0;
    if (p.mip != 0)
        lambda = sample_mip(c, uv, value, any, first, level);
    else
        any = sample_level(0, uv, value, first);
    for (int k = 0; k < p.channels; ++k) result[pixel * p.channels + k] = value[k];
    lookups[pixel] = vec4(uv, lambda, any ? 1.0 : 2.0);
    decisions[pixel] = vec4(vec2(first), float(level), 0.0);
}
