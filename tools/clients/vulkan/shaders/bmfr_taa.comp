#version 450
// BMFR's TAA in display space (the authors' taa kernel; docs/bmfr.md, "TAA"), as a GPU developer
// writes it, one invocation per pixel (x, y), 16 x 16 per workgroup:
//   the 3x3 neighbourhood in unnormalised YCoCg (Y = R + 2G + B, Co = 2R - 2B, Cg = -R + 2G - B),
//     from a shared-memory tile of the workgroup's pixels and a 1-pixel ring, each converted
//     once; neighbours outside the image are skipped; lo = (box min + cross min) 0.5, hi alike,
//     the cross being the centre and its 4 neighbours;
//   the history (the previous bmfr_taa) bilinear at phase I's reprojected pixel q
//     (include/bmfr_pixel_taps.glsl), taps outside the image dropped, weights renormalised;
//   clamped to [lo, hi] in YCoCg, back to RGB (R = ((Y + Co) - Cg) / 4, G = (Y + Cg) / 4,
//     B = ((Y - Co) - Cg) / 4), out = 0.2 new + 0.8 history.
// The new colour alone on the first frame, when floor(q) lies outside [-1, W - 1] x [-1, H - 1]
// (behind the previous camera included: q = (-2, -2)) or when the taps inside have no weight.
// Native GLSL arithmetic (the GPU's division): not bit-exact. `precise` (no fused multiply-add):
// the YCoCg transforms, the extents' means, the history's sum and the blend.
// -DINJECT_BUG injects a typical porting bug: the inverse of the normalised YCoCg
// (R = Y + Co - Cg, no /4) paired with the unnormalised forward transform, so the clamped
// history comes back 4 times too bright.
#extension GL_GOOGLE_include_directive : require
#include "bmfr_pixel_taps.glsl"

layout(local_size_x = 16, local_size_y = 16) in;
layout(std430, binding = 0) readonly buffer Display { float display[]; };
layout(std430, binding = 1) readonly buffer PreviousPixel { float previous_pixel[]; };
layout(std430, binding = 2) readonly buffer History { float history[]; };
layout(std430, binding = 3) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Parameters {
    int width, height, has_history;
    float taa_alpha;
} p;

const int tile_size = 18;                // 16 pixels and a ring of 1
shared vec3 tile[tile_size][tile_size];  // YCoCg of the display
shared bool tile_inside[tile_size][tile_size];

vec3 load_display(ivec2 xy) {
    const int i = 3 * (xy.y * p.width + xy.x);
    return vec3(display[i], display[i + 1], display[i + 2]);
}

precise vec3 rgb_to_ycocg(vec3 c) {
    precise vec3 v = vec3(c.x + 2.0 * c.y + c.z, 2.0 * c.x - 2.0 * c.z, -c.x + 2.0 * c.y - c.z);
    return v;
}

precise vec3 ycocg_to_rgb(vec3 v) {
#ifdef INJECT_BUG
    precise vec3 c = vec3((v.x + v.y) - v.z, v.x + v.z, (v.x - v.y) - v.z);
#else
    precise vec3 c =
        vec3(((v.x + v.y) - v.z) * 0.25, (v.x + v.z) * 0.25, ((v.x - v.y) - v.z) * 0.25);
#endif
    return c;
}

// Fills the tile: the YCoCg of the workgroup's pixels and their ring (every invocation takes
// part, before the barrier).
void load_tile() {
    const ivec2 origin = ivec2(gl_WorkGroupID.xy) * 16 - 1;
    for (int t = int(gl_LocalInvocationIndex); t < tile_size * tile_size; t += 256) {
        const ivec2 local = ivec2(t % tile_size, t / tile_size);
        const ivec2 xy = origin + local;
        const bool inside = bmfr_inside(xy, p.width, p.height);
        tile_inside[local.y][local.x] = inside;
        tile[local.y][local.x] = inside ? rgb_to_ycocg(load_display(xy)) : vec3(0.0);
    }
    barrier();
}

// The history bilinear at q over the taps inside the image, weights renormalised; false when
// they have no weight.
bool sample_history(vec2 q, out vec3 h) {
    const BmfrTaps taps = bmfr_taps(q);
    precise vec3 sum = vec3(0.0);
    precise float total = 0.0;
    for (int k = 0; k < 4; ++k) {
        if (!bmfr_inside(taps.xy[k], p.width, p.height)) continue;
        const int i = 3 * (taps.xy[k].y * p.width + taps.xy[k].x);
        sum = sum + taps.w[k] * vec3(history[i], history[i + 1], history[i + 2]);
        total = total + taps.w[k];
    }
    h = sum / total;
    return total > 0.0;
}

// The pixel's blend with the history at q; false when no tap counts.
bool taa_blend(ivec2 local, vec3 current, vec2 q, out vec3 blended) {
    const float infinity = uintBitsToFloat(0x7f800000u);
    vec3 box_min = vec3(infinity), box_max = vec3(-infinity);
    vec3 cross_min = box_min, cross_max = box_max;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            if (!tile_inside[local.y + dy][local.x + dx]) continue;
            const vec3 v = tile[local.y + dy][local.x + dx];
            box_min = min(box_min, v);
            box_max = max(box_max, v);
            if (dx == 0 || dy == 0) {
                cross_min = min(cross_min, v);
                cross_max = max(cross_max, v);
            }
        }
    precise vec3 lo = (box_min + cross_min) * 0.5;
    precise vec3 hi = (box_max + cross_max) * 0.5;
    vec3 h;
    if (!sample_history(q, h)) return false;
    const vec3 clamped = ycocg_to_rgb(min(max(rgb_to_ycocg(h), lo), hi));
    precise vec3 mixed = current * p.taa_alpha + clamped * (1.0 - p.taa_alpha);
    blended = mixed;
    return true;
}

void main() {
    load_tile();
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
    const int pixel = xy.y * p.width + xy.x;
    vec3 out_colour = load_display(xy);
    const vec2 q = vec2(previous_pixel[2 * pixel], previous_pixel[2 * pixel + 1]);
    // Some tap of the reprojected point must be on the image: floor(q) in [-1, W - 1]
    const bool on_image =
        q.x >= -1.0 && q.y >= -1.0 && q.x < float(p.width) && q.y < float(p.height);
    vec3 blended;
    if (p.has_history != 0 && on_image &&
        taa_blend(ivec2(gl_LocalInvocationID.xy) + 1, out_colour, q, blended))
        out_colour = blended;
    for (int ch = 0; ch < 3; ++ch) result[3 * pixel + ch] = out_colour[ch];
}
