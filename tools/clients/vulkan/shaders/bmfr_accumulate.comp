#version 450
// BMFR's phase I, the accumulation of the noisy illumination (Koskela et al. 2019; docs/bmfr.md,
// "Phase I"), as a GPU developer writes it after the authors' accumulate_noisy_data kernel, one
// invocation per pixel (x, y) with world position P and shading normal n (NaN or infinite: 0):
//   reprojection: c = M' (P, 1) with the previous frame's view-projection M' (rows 0, 1 and 3,
//     made on the host); c.w <= 0: behind the previous camera, q = (-2, -2), no history;
//     otherwise q = ((c.x / c.w + 1) 0.5 W - 1/2, (1 - c.y / c.w) 0.5 H - 1/2), the previous
//     frame's pixel index (integers at pixel centres);
//   taps: include/bmfr_pixel_taps.glsl; tap k accepted (bit k of bmfr_accept) when inside the
//     image, |P_k - P|^2 < L_p and |n_k - n|^2 < L_n (strict), P_k, n_k the previous G-buffer;
//   blend: the accepted taps' colours and sample counts, weights renormalised (tap order);
//     alpha = max(1 / (s_h + 1), 0.2), out = alpha c + (1 - alpha) h,
//     spp = min(roundEven(s_h) + 1, 255); no accepted tap with weight: out = c, spp = 1, mask 0.
// Without a previous frame: out = c, spp = 1, q = (x, y). bmfr_accept_margin: over the taps
// inside, the smallest |L^2 - d^2| / L^2 of each test, and q's distance from the nearest integer
// (1e30 where nothing was decided).
// Native GLSL arithmetic (the GPU's division): not bit-exact. `precise` (no fused multiply-add)
// where the docs give the binary32 order: the matrix rows, the pixel index, the distances, the
// blend.
// -DINJECT_BUG injects a typical porting bug: the reprojected pixel without the -1/2 of the
// pixel centre (q = (ndc + 1) W / 2, the pixel's corner), so every history is sampled half a
// pixel off.
#extension GL_GOOGLE_include_directive : require
#include "bmfr_pixel_taps.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Illumination { float illumination[]; };
layout(std430, binding = 1) readonly buffer WorldPosition { float world_position[]; };
layout(std430, binding = 2) readonly buffer Normal { float normal[]; };
layout(std430, binding = 3) readonly buffer PreviousWorld { float previous_world[]; };
layout(std430, binding = 4) readonly buffer PreviousNormal { float previous_normal[]; };
layout(std430, binding = 5) readonly buffer PreviousAccumulated { float previous_accumulated[]; };
layout(std430, binding = 6) readonly buffer PreviousSpp { float previous_spp[]; };
layout(std430, binding = 7) writeonly buffer Accumulated { float accumulated[]; };
layout(std430, binding = 8) writeonly buffer Spp { float spp[]; };
layout(std430, binding = 9) writeonly buffer Accept { float accept[]; };
layout(std430, binding = 10) writeonly buffer PreviousPixel { float previous_pixel[]; };
layout(std430, binding = 11) writeonly buffer AcceptMargin { float accept_margin[]; };
layout(push_constant) uniform Parameters {
    int width, height, has_history;
    float position_limit_squared, normal_limit_squared, alpha_min, offset_x, offset_y;
    vec4 row_x, row_y, row_w;  // rows 0, 1 and 3 of the previous view-projection
} p;

const float no_margin = 1e30;

vec3 finite_or_zero(vec3 v) {
    return vec3(isnan(v.x) || isinf(v.x) ? 0.0 : v.x, isnan(v.y) || isinf(v.y) ? 0.0 : v.y,
                isnan(v.z) || isinf(v.z) ? 0.0 : v.z);
}

vec3 load_world(int i) {
    return vec3(world_position[3 * i], world_position[3 * i + 1], world_position[3 * i + 2]);
}
vec3 load_normal(int i) { return vec3(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]); }
vec3 load_previous_world(int i) {
    return vec3(previous_world[3 * i], previous_world[3 * i + 1], previous_world[3 * i + 2]);
}
vec3 load_previous_normal(int i) {
    return vec3(previous_normal[3 * i], previous_normal[3 * i + 1], previous_normal[3 * i + 2]);
}

// |a - b|^2, summed x, y, z in that order.
precise float distance_squared(vec3 a, vec3 b) {
    precise vec3 d = a - b;
    precise float sum = d.x * d.x + d.y * d.y + d.z * d.z;
    return sum;
}

// (row . (v, 1)), summed x, y, z, w in that order.
precise float row_dot(vec4 row, vec3 v) {
    precise float sum = row.x * v.x + row.y * v.y + row.z * v.z + row.w;
    return sum;
}

// The previous frame's pixel index of world point `world`; false when behind the previous camera
// or not finite.
bool reproject(vec3 world, out vec2 q) {
    precise float cx = row_dot(p.row_x, world);
    precise float cy = row_dot(p.row_y, world);
    precise float cw = row_dot(p.row_w, world);
    q = vec2(-2.0);
    if (!(cw > 0.0)) return false;
    const float w = float(p.width), h = float(p.height);
#ifdef INJECT_BUG
    precise float qx = (cx / cw + 1.0) * 0.5 * w;
    precise float qy = (1.0 - cy / cw) * 0.5 * h;
#else
    precise float qx = (cx / cw + 1.0) * 0.5 * w - p.offset_x;
    precise float qy = (1.0 - cy / cw) * 0.5 * h - p.offset_y;
#endif
    q = vec2(qx, qy);
    return !(isnan(qx) || isinf(qx) || isnan(qy) || isinf(qy));
}

// The accept bits of the taps for a pixel at `world` with normal `n`, and the margins of both
// tests (channels 0 and 1 of bmfr_accept_margin).
uint accepted_taps(BmfrTaps taps, vec3 world, vec3 n, inout vec3 margin) {
    uint mask = 0u;
    for (int k = 0; k < 4; ++k) {
        if (!bmfr_inside(taps.xy[k], p.width, p.height)) continue;
        const int i = taps.xy[k].y * p.width + taps.xy[k].x;
        const float dp = distance_squared(load_previous_world(i), world);
        margin.x = min(margin.x, abs(p.position_limit_squared - dp) / p.position_limit_squared);
        if (!(dp < p.position_limit_squared)) continue;
        const float dn = distance_squared(load_previous_normal(i), n);
        margin.y = min(margin.y, abs(p.normal_limit_squared - dn) / p.normal_limit_squared);
        if (!(dn < p.normal_limit_squared)) continue;
        mask |= 1u << k;
    }
    return mask;
}

// The accepted taps' colour h and sample count s_h, weights renormalised (summed in tap order);
// false when they have no weight.
bool blend_history(BmfrTaps taps, uint mask, out vec3 h, out float h_spp) {
    precise vec3 colour = vec3(0.0);
    precise float count = 0.0, total = 0.0;
    for (int k = 0; k < 4; ++k) {
        if ((mask & (1u << k)) == 0u) continue;
        const int i = taps.xy[k].y * p.width + taps.xy[k].x;
        const vec3 c_k = vec3(previous_accumulated[3 * i], previous_accumulated[3 * i + 1],
                              previous_accumulated[3 * i + 2]);
        colour = colour + taps.w[k] * c_k;
        count = count + taps.w[k] * previous_spp[i];
        total = total + taps.w[k];
    }
    h = colour / total;
    h_spp = count / total;
    return total > 0.0;
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
    const int pixel = xy.y * p.width + xy.x;
    const vec3 c =
        vec3(illumination[3 * pixel], illumination[3 * pixel + 1], illumination[3 * pixel + 2]);
    vec2 q = vec2(xy);
    uint mask = 0u;
    vec3 margin = vec3(no_margin);
    vec3 h = vec3(0.0);
    float h_spp = 0.0;
    bool has_history = false;
    if (p.has_history != 0) {
        const vec3 world = finite_or_zero(load_world(pixel));
        const vec3 n = finite_or_zero(load_normal(pixel));
        if (reproject(world, q)) {
            const BmfrTaps taps = bmfr_taps(q);
            mask = accepted_taps(taps, world, n, margin);
            const vec2 below = q - floor(q), above = ceil(q) - q;
            margin.z = min(min(below.x, above.x), min(below.y, above.y));
            has_history = blend_history(taps, mask, h, h_spp);
            if (!has_history) mask = 0u;
        } else {
            q = vec2(-2.0);
        }
    }
    precise vec3 result = c;
    float count = 1.0;
    if (has_history) {
        precise float alpha = max(1.0 / (h_spp + 1.0), p.alpha_min);
        result = alpha * c + (1.0 - alpha) * h;
        count = min(roundEven(h_spp) + 1.0, 255.0);
    }
    for (int ch = 0; ch < 3; ++ch) {
        accumulated[3 * pixel + ch] = result[ch];
        accept_margin[3 * pixel + ch] = margin[ch];
    }
    spp[pixel] = count;
    accept[pixel] = float(mask);
    previous_pixel[2 * pixel] = q.x;
    previous_pixel[2 * pixel + 1] = q.y;
}
