#version 450
// One level of the mip resolve's pyramid (docs/foveation.md, "The mip resolve"; Meng §5.1), as
// a GPU developer writes it from the docs: level k + 1 (ceil(w / 2) x ceil(h / 2)) from level k
// (w x h), one invocation per texel (i, j): the mean of the traced texels among columns
// {2i, 2i + 1} (those < w) and rows {2j, (2j + 1) mod h} (v wraps), in the order (2i, 2j),
// (2i + 1, 2j), (2i, 2j + 1), (2i + 1, 2j + 1), as the running mean m += (x - m) / k; traced
// when one of them is. The levels lie one after the other in the same buffers; the host
// dispatches once per level.
// -DINJECT_BUG injects a typical porting bug: the rows clamped, not wrapped, at the seam.
layout(local_size_x = 8, local_size_y = 8) in;
// Each level's first texel, width and height: (offset, w, h, 0)
layout(std430, binding = 0) readonly buffer Levels { ivec4 levels[]; };
layout(std430, binding = 1) buffer Colour { float colour[]; };
layout(std430, binding = 2) buffer Valid { float valid[]; };
layout(push_constant) uniform Parameters {
    int source_level, channels;
} p;

void main() {
    const ivec4 source = levels[p.source_level], target = levels[p.source_level + 1];
    const ivec2 ij = ivec2(gl_GlobalInvocationID.xy);
    if (ij.x >= target.y || ij.y >= target.z) return;
#ifdef INJECT_BUG
    const int rows[2] = int[2](2 * ij.y, min(2 * ij.y + 1, source.z - 1));
#else
    const int rows[2] = int[2](2 * ij.y, (2 * ij.y + 1) % source.z);
#endif
    vec4 mean = vec4(0.0);
    int count = 0;
    for (int r = 0; r < 2; ++r)
        for (int dx = 0; dx < 2; ++dx) {
            const int x = 2 * ij.x + dx;
            const int texel = source.x + rows[r] * source.y + x;
            if (x >= source.y || valid[texel] == 0.0) continue;
            ++count;
            for (int k = 0; k < p.channels; ++k)
                mean[k] += (colour[texel * p.channels + k] - mean[k]) / float(count);
        }
    const int texel = target.x + ij.y * target.y + ij.x;
    valid[texel] = count > 0 ? 1.0 : 0.0;
    for (int k = 0; k < p.channels; ++k) colour[texel * p.channels + k] = mean[k];
}
