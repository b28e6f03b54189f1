#version 450
// BMFR's weighted sum (Koskela et al. 2019; docs/bmfr.md, "Weighted sum"), as a GPU developer
// writes it after the authors' weighted_sum kernel, one invocation per pixel (x, y):
//   cell = ((x + 16 - o.x) div 32, (y + 16 - o.y) div 32) of the frame's shifted grid,
//     o = offset[frame mod 16] (the authors' table);
//   T = [1, n, w, w^2] from the pixel's shading normal and world position (the squares in float,
//     NaN -> 0, each clamped to +-65504), read in binary32 as the oracle reads them (the fit's
//     binary16 storage applies to the block matrix only, not to the weighted sum's features);
//   features 4..9 scaled with the cell's range: (v - min) / (max - min) when max - min > 1,
//     else v - min;
//   out = max(sum_{i=0..9} w_i T_i, 0) per channel (i ascending; a sum that is not finite: 0).
// Native GLSL arithmetic (the GPU's division): not bit-exact. `precise` (no fused multiply-add):
// the squares, the scaling and the sum, in the docs' binary32 order.
// -DINJECT_BUG injects a typical porting bug: the grid offset of the previous frame (the frame
// counter read after the host advanced it), so pixels near the block seams take a neighbouring
// block's weights.
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer WorldPosition { float world_position[]; };
layout(std430, binding = 1) readonly buffer Normal { float normal[]; };
layout(std430, binding = 2) readonly buffer Weights { float weights[]; };  // 30 per cell
layout(std430, binding = 3) readonly buffer FeatureRange { float feature_range[]; };  // 12 per cell
layout(std430, binding = 4) writeonly buffer Fitted { float fitted[]; };
layout(push_constant) uniform Parameters {
    int width, height, cells_x, cells_y, frame;
} p;

const int block_size = 32;
const int feature_count = 10;
const int scaled_first = 4, scaled_count = 6;
const float half_max = 65504.0;
// The authors' block-grid offsets, one per frame modulo 16
const ivec2 block_offsets[16] = ivec2[16](
    ivec2(-14, -14), ivec2(4, -6), ivec2(-8, 14), ivec2(8, 0), ivec2(-10, -8), ivec2(2, 12),
    ivec2(12, -12), ivec2(-10, 0), ivec2(12, 14), ivec2(-8, -16), ivec2(6, 6), ivec2(-2, -2),
    ivec2(6, -14), ivec2(-16, 12), ivec2(14, -4), ivec2(-6, 4));

float clamp_feature(float v) { return isnan(v) ? 0.0 : clamp(v, -half_max, half_max); }

// The features of pixel `pixel`: 1, n, w, w^2.
void features(int pixel, out float t[feature_count]) {
    const vec3 n = vec3(normal[3 * pixel], normal[3 * pixel + 1], normal[3 * pixel + 2]);
    const vec3 w = vec3(world_position[3 * pixel], world_position[3 * pixel + 1],
                        world_position[3 * pixel + 2]);
    precise vec3 squares = w * w;
    t[0] = 1.0;
    for (int i = 0; i < 3; ++i) {
        t[1 + i] = clamp_feature(n[i]);
        t[4 + i] = clamp_feature(w[i]);
        t[7 + i] = clamp_feature(squares[i]);
    }
}

// A block's scaling of one feature: (v - lo) / (hi - lo) when the range exceeds 1, else v - lo.
precise float scale_feature(float v, float lo, float hi) {
    precise float range = hi - lo;
    precise float shifted = v - lo;
    precise float scaled = range > 1.0 ? shifted / range : shifted;
    return scaled;
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
#ifdef INJECT_BUG
    const ivec2 offset = block_offsets[(p.frame + 15) % 16];
#else
    const ivec2 offset = block_offsets[p.frame % 16];
#endif
    // x + 16 - o.x >= 2 for the offsets in [-16, 14]: the division rounds down
    const ivec2 cell = (xy + block_size / 2 - offset) / block_size;
    const int block = cell.y * p.cells_x + cell.x;
    const int pixel = xy.y * p.width + xy.x;
    float t[feature_count];
    features(pixel, t);
    for (int k = 0; k < scaled_count; ++k)
        t[scaled_first + k] = scale_feature(t[scaled_first + k], feature_range[12 * block + k],
                                            feature_range[12 * block + scaled_count + k]);
    for (int ch = 0; ch < 3; ++ch) {
        precise float sum = 0.0;
        for (int i = 0; i < feature_count; ++i)
            sum = sum + weights[30 * block + ch * feature_count + i] * t[i];
        fitted[3 * pixel + ch] = isnan(sum) || isinf(sum) ? 0.0 : max(sum, 0.0);
    }
}
