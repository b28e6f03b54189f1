#version 450
// Meng's internal anti-aliasing in the log-polar buffer (docs/foveation.md, "Internal AA"), as a
// GPU developer writes it from the docs: a traced texel in the buffer's outer half (2 u >= w)
// becomes the 1-2-1 weighted mean of the traced texels of its 3x3 neighbourhood, u clamped at
// the buffer's edges, v wrapping around (v is the angle); every other texel is copied.
// -DINJECT_BUG injects a typical porting bug: v clamped like u instead of wrapped.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Colour { float colour[]; };
layout(std430, binding = 1) readonly buffer Valid { float valid[]; };
layout(std430, binding = 2) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Parameters {
    int width, height, channels;
} p;

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
    const int texel = xy.y * p.width + xy.x;
    if (valid[texel] == 0.0 || 2 * xy.x < p.width) {
        for (int c = 0; c < p.channels; ++c)
            result[texel * p.channels + c] = colour[texel * p.channels + c];
        return;
    }
    vec4 sum = vec4(0.0);
    float weight = 0.0;
    for (int dy = -1; dy <= 1; ++dy) {
#ifdef INJECT_BUG
        const int y = clamp(xy.y + dy, 0, p.height - 1);
#else
        const int y = ((xy.y + dy) % p.height + p.height) % p.height;
#endif
        for (int dx = -1; dx <= 1; ++dx) {
            const int x = clamp(xy.x + dx, 0, p.width - 1);
            const int t = y * p.width + x;
            if (valid[t] == 0.0) continue;
            const float k = float((2 - abs(dx)) * (2 - abs(dy)));
            weight += k;
            for (int c = 0; c < p.channels; ++c) sum[c] += k * colour[t * p.channels + c];
        }
    }
    for (int c = 0; c < p.channels; ++c) result[texel * p.channels + c] = sum[c] / weight;
}
