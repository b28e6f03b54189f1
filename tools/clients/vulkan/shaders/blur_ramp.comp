#version 450
// The P5 blur ramp, one separable pass (docs/visual-polar.md, "Blur ramp";
// ref/filters/blur_ramp.h): along x, or along y with `vertical`. At the output pixel's centre c,
// e = |c - g| / s model degrees; sigma = 0 up to the fovea edge e_f, sigma_deg (e - e_f) /
// (full_deg - e_f) up to full_deg, sigma_deg beyond; sigma_px = sigma s; radius R =
// min(ceil(3 sigma_px), 64) (0: the pixel is copied). Weights w_d = a^(d^2), a = exp(-1 /
// ((2 sigma_px) sigma_px)) (the GPU's exp), by the recurrence w_d = w_(d-1) g_d, g_1 = a,
// g_(d+1) = g_d a^2; normalised by their sum over d = -R .. R (in that order); out = sum over
// d = -R .. R of w_d c_d, taps clamped to the border. Sums and products in the reference's
// order, not contracted (`precise`).
// One workgroup is a run of 64 pixels along the pass; it stages its run and 64 pixels either
// side (the largest radius), clamped to the border, in shared memory.
// -DINJECT_BUG injects a typical porting bug: the weights not renormalised over the taps kept,
// but divided by the continuous Gaussian's integral sqrt(2 pi) sigma_px (wrong where sigma_px is
// small: where the ramp starts).
layout(local_size_x = 64) in;
layout(std430, binding = 0) readonly buffer Source { float source[]; };
layout(std430, binding = 1) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Parameters {
    int width, height, channels;
    int vertical;  // 0: along x, 1: along y
    float gaze_x, gaze_y;
    float scale;      // s, pixels per model degree
    float fovea_deg;  // e_f = P(u0)
    float sigma_deg, full_deg;
} p;

const int max_radius = 64;
const int run = 64;  // pixels per workgroup along the pass (gl_WorkGroupSize.x)
shared float tile[(run + 2 * max_radius) * 4];

// sigma_px at screen point c.
float sigma_px(vec2 c) {
    const float dx = c.x - p.gaze_x, dy = c.y - p.gaze_y;
    precise float e = sqrt(dx * dx + dy * dy) / p.scale;
    float sigma = 0.0;
    if (e <= p.fovea_deg)
        sigma = 0.0;
    else if (e >= p.full_deg)
        sigma = p.sigma_deg;
    else
        sigma = p.sigma_deg * (e - p.fovea_deg) / (p.full_deg - p.fovea_deg);
    return sigma * p.scale;
}

void main() {
    // The workgroup's run: pixels first .. first + 63 of line `line` along the pass
    const int extent = p.vertical != 0 ? p.height : p.width;
    const int first = int(gl_WorkGroupID.x) * run, line = int(gl_WorkGroupID.y);
    const int position = first + int(gl_LocalInvocationID.x);
    const ivec2 stride = p.vertical != 0 ? ivec2(0, 1) : ivec2(1, 0);
    const ivec2 origin = p.vertical != 0 ? ivec2(line, 0) : ivec2(0, line);

    // Stage the run and max_radius pixels either side, clamped to the border
    for (int k = int(gl_LocalInvocationID.x); k < run + 2 * max_radius; k += run) {
        const ivec2 xy = origin + stride * clamp(first - max_radius + k, 0, extent - 1);
        for (int c = 0; c < p.channels; ++c)
            tile[k * p.channels + c] = source[(xy.y * p.width + xy.x) * p.channels + c];
    }
    barrier();
    if (position >= extent) return;

    const ivec2 xy = origin + stride * position;
    const int centre = position - first + max_radius;  // this pixel's place in the tile
    const int out_index = (xy.y * p.width + xy.x) * p.channels;
    const float sigma = sigma_px(vec2(xy) + 0.5);
    int radius = 0;
    if (sigma > 0.0) {
        const float r = ceil(3.0 * sigma);
        radius = r >= float(max_radius) ? max_radius : int(r);
    }
    if (radius == 0) {  // copied
        for (int c = 0; c < p.channels; ++c) result[out_index + c] = tile[centre * p.channels + c];
        return;
    }

    // Gaussian weights w_|d| by the recurrence (one exp per pixel), normalised over -R .. R
    float weights[max_radius + 1];
    precise float a = exp(-1.0 / (2.0 * sigma * sigma));
    precise float a2 = a * a;
    weights[0] = 1.0;
    precise float g = a;
    for (int d = 1; d <= radius; ++d) {
        weights[d] = weights[d - 1] * g;
        g = g * a2;
    }
    precise float weight_sum = 0.0;
    for (int d = -radius; d <= radius; ++d) weight_sum += weights[abs(d)];
#ifdef INJECT_BUG
    const float inverse = 1.0 / (sqrt(2.0 * 3.14159265358979) * sigma);
#else
    const float inverse = 1.0 / weight_sum;
#endif
    for (int d = 0; d <= radius; ++d) weights[d] = weights[d] * inverse;

    // The weighted sum over the taps -R .. R
    precise vec4 mean = vec4(0.0);
    for (int d = -radius; d <= radius; ++d) {
        const float weight = weights[abs(d)];
        for (int c = 0; c < p.channels; ++c)
            mean[c] += weight * tile[(centre + d) * p.channels + c];
    }
    for (int c = 0; c < p.channels; ++c) result[out_index + c] = mean[c];
}
