#version 450
// The Visual-Polar resolve, part 1: the phi-only pyramid (docs/visual-polar.md, "Resolve";
// ref/visual_polar/resolve.h). One workgroup per column builds all of that column's levels:
// row j of level k + 1 is the running mean m_k = m_(k-1) + (x_k - m_(k-1)) / k of the traced
// texels among level k's rows 2j and (2j + 1) mod n (n: the column's rows at level k; the last
// row of an odd column wraps onto row 0), traced when one of them is; a column of one row is
// carried down unchanged. Level 0 (the buffer and vp_valid) is uploaded by the host; the other
// levels start at 0, the value of the rows no lookup reads. Between levels the workgroup waits
// for the previous level's writes (memoryBarrierBuffer, barrier).
// -DINJECT_BUG injects a typical porting bug: phi clamped like rho instead of wrapped at 2 pi
// (here an odd column's last row pairs with itself instead of row 0; vp_resolve.comp: the
// lookup's angle and taps).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 64) in;
#include "vp_map.glsl"
layout(std430, binding = 0) coherent buffer Colour { float colour[]; };
layout(std430, binding = 1) coherent buffer Valid { float valid[]; };
layout(std430, binding = 2) readonly buffer ColumnRows { int column_rows[]; };

// Row j of level k + 1 of column i from level k (n rows there, first texel `from`), to `to`.
void downsample(int i, int j, int n, int from, int to) {
    const int target = to + j * p.width + i;
    if (n == 1) {  // carried down unchanged
        const int source = from + i;
        valid[target] = valid[source] != 0.0 ? 1.0 : 0.0;
        if (valid[target] != 0.0)
            for (int c = 0; c < p.channels; ++c)
                colour[target * p.channels + c] = colour[source * p.channels + c];
        return;
    }
#ifdef INJECT_BUG
    const int taps[2] = {2 * j, min(2 * j + 1, n - 1)};
#else
    const int taps[2] = {2 * j, 2 * j + 1 == n ? 0 : 2 * j + 1};
#endif
    precise vec4 mean = vec4(0.0);
    int count = 0;
    for (int t = 0; t < 2; ++t) {
        const int source = from + taps[t] * p.width + i;
        if (valid[source] == 0.0) continue;
        ++count;
        for (int c = 0; c < p.channels; ++c)
            mean[c] += (colour[source * p.channels + c] - mean[c]) / float(count);
    }
    valid[target] = count > 0 ? 1.0 : 0.0;
    for (int c = 0; c < p.channels; ++c) colour[target * p.channels + c] = mean[c];
}

void main() {
    const int i = int(gl_WorkGroupID.x);
    int n = column_rows[i];
    int rows = p.height, from = 0;            // level k: the image's rows, its first texel
    for (int k = 0; k + 1 < p.levels; ++k) {  // uniform: every invocation runs every level
        const int to = from + p.width * rows;
        const int next = (n + 1) / 2;
        for (int j = int(gl_LocalInvocationID.x); j < next; j += int(gl_WorkGroupSize.x))
            downsample(i, j, n, from, to);
        memoryBarrierBuffer();
        barrier();
        n = next;
        rows = (rows + 1) / 2;
        from = to;
    }
}
