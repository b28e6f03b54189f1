#version 450
// BMFR's phase III, the accumulation of the fit (Koskela et al. 2019; docs/bmfr.md, "Phase
// III"), as a GPU developer writes it after the authors' accumulate_filtered_data kernel, one
// invocation per pixel (x, y): phase I's accept bits (bmfr_accept, 0..15, anything else none)
// and its reprojected pixel q (bmfr_previous_pixel) pick the taps (include/bmfr_pixel_taps.glsl)
// of the history, the previous phase III output; the accepted taps inside the image are blended
// with their weights renormalised (tap order); alpha = max(1 / spp, 0.1) with phase I's spp,
// out = alpha fit + (1 - alpha) history. No history, no accepted tap or no weight: out = fit.
// Native GLSL arithmetic (the GPU's division): not bit-exact. `precise` (no fused multiply-add):
// the tap weights, the history's sum and the blend, in the docs' binary32 order.
// -DINJECT_BUG injects a typical porting bug: phase I's blend factor reused,
// alpha = max(1 / (spp + 1), 0.1), as if spp were still the history's count (phase III's spp is
// phase I's output, which already counts this frame).
#extension GL_GOOGLE_include_directive : require
#include "bmfr_pixel_taps.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Fitted { float fitted[]; };
layout(std430, binding = 1) readonly buffer Spp { float spp[]; };
layout(std430, binding = 2) readonly buffer Accept { float accept[]; };
layout(std430, binding = 3) readonly buffer PreviousPixel { float previous_pixel[]; };
layout(std430, binding = 4) readonly buffer History { float history[]; };
layout(std430, binding = 5) writeonly buffer Filtered { float filtered[]; };
layout(push_constant) uniform Parameters {
    int width, height, has_history;
    float alpha_min;
} p;

// The history over the taps whose bit is set in `mask` (inside the image), weights
// renormalised; false when they have no weight.
bool blend_accepted(BmfrTaps taps, uint mask, out vec3 h) {
    precise vec3 sum = vec3(0.0);
    precise float total = 0.0;
    for (int k = 0; k < 4; ++k) {
        if ((mask & (1u << k)) == 0u || !bmfr_inside(taps.xy[k], p.width, p.height)) continue;
        const int i = taps.xy[k].y * p.width + taps.xy[k].x;
        sum = sum + taps.w[k] * vec3(history[3 * i], history[3 * i + 1], history[3 * i + 2]);
        total = total + taps.w[k];
    }
    h = sum / total;
    return total > 0.0;
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
    const int pixel = xy.y * p.width + xy.x;
    const vec3 c = vec3(fitted[3 * pixel], fitted[3 * pixel + 1], fitted[3 * pixel + 2]);
    const float bits = accept[pixel];
    const uint mask = bits >= 0.0 && bits < 16.0 ? uint(bits) : 0u;
    precise vec3 result = c;
    vec3 h;
    if (p.has_history != 0 && mask != 0u &&
        blend_accepted(bmfr_taps(vec2(previous_pixel[2 * pixel], previous_pixel[2 * pixel + 1])),
                       mask, h)) {
#ifdef INJECT_BUG
        precise float alpha = max(1.0 / (spp[pixel] + 1.0), p.alpha_min);
#else
        precise float alpha = max(1.0 / spp[pixel], p.alpha_min);
#endif
        result = alpha * c + (1.0 - alpha) * h;
    }
    for (int ch = 0; ch < 3; ++ch) filtered[3 * pixel + ch] = result[ch];
}
