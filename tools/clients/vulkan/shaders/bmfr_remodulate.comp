#version 450
// BMFR's remodulation and tone mapping (docs/bmfr.md, "Remodulation and tone mapping"), as a GPU
// developer writes it, one invocation per pixel, per channel:
//   linear = max(0, x) max(albedo, 0.01) (+ e, the directly seen emission, with
//   bmfr_emission=separate; a non-finite albedo is 0, a non-finite e is left out),
//   display = clamp(max(0, linear)^g, 0, 1) (g: bmfr_gamma, the authors' 0.454545 by default),
//   linear >= 1 giving 1 directly.
// Native GLSL pow (the GPU's exp2(y log2 x)), not the oracle's dm::pow_fast: not bit-exact.
// `precise` (no fused multiply-add): the product and the emission's sum.
// -DINJECT_BUG injects a typical porting bug: the albedo's floor (the epsilon that demodulation
// divided by) left out, x albedo, so a black or sky pixel loses the illumination the fit gave it.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Filtered { float filtered[]; };
layout(std430, binding = 1) readonly buffer Albedo { float albedo[]; };
layout(std430, binding = 2) readonly buffer Emission { float emission[]; };
layout(std430, binding = 3) writeonly buffer Display { float display[]; };
layout(push_constant) uniform Parameters {
    int width, height, separate_emission;
    float albedo_floor, inverse_gamma;
} p;

bool finite(float v) { return !(isnan(v) || isinf(v)); }

// The display value of element i (a pixel's channel).
float remodulate(int i) {
    const float a = finite(albedo[i]) ? albedo[i] : 0.0;
#ifdef INJECT_BUG
    precise float linear = max(0.0, filtered[i]) * a;
#else
    precise float linear = max(0.0, filtered[i]) * max(a, p.albedo_floor);
#endif
    if (p.separate_emission != 0 && finite(emission[i])) linear = linear + emission[i];
    linear = max(0.0, linear);
    return linear >= 1.0 ? 1.0 : clamp(pow(linear, p.inverse_gamma), 0.0, 1.0);
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
    const int pixel = xy.y * p.width + xy.x;
    for (int ch = 0; ch < 3; ++ch) display[3 * pixel + ch] = remodulate(3 * pixel + ch);
}
