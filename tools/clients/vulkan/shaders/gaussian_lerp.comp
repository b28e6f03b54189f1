#version 450
// Lund's Gaussian lerp (docs/foveation.md, "The Gaussian lerp"), as a GPU developer writes it
// from the docs: t = clamp((|p - gaze| - D/6) / (R_c - D/6), 0, 1) at the pixel centre p, then
// out = v + t (G3x3(v) - v), G3x3 the 1-2-1 kernel / 16 with clamped edges. Native GLSL
// arithmetic (distance() is the GPU's sqrt): not bit-exact, within the diff's tolerance.
// -DINJECT_BUG injects a typical porting bug: the pixel's corner instead of its centre.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Source { float source[]; };
layout(std430, binding = 1) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Parameters {
    int width, height, channels;
    float gaze_x, gaze_y, ramp_start, ramp_span;
} p;

float load(int x, int y, int c) {
    x = clamp(x, 0, p.width - 1);
    y = clamp(y, 0, p.height - 1);
    return source[(y * p.width + x) * p.channels + c];
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
#ifdef INJECT_BUG
    const vec2 centre = vec2(xy);
#else
    const vec2 centre = vec2(xy) + 0.5;
#endif
    const float t =
        clamp((distance(centre, vec2(p.gaze_x, p.gaze_y)) - p.ramp_start) / p.ramp_span, 0.0, 1.0);
    for (int c = 0; c < p.channels; ++c) {
        float sum = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                sum += float((2 - abs(dx)) * (2 - abs(dy))) * load(xy.x + dx, xy.y + dy, c);
        const float value = load(xy.x, xy.y, c);
        result[(xy.y * p.width + xy.x) * p.channels + c] =
            t == 0.0 ? value : value + t * (sum / 16.0 - value);
    }
}
