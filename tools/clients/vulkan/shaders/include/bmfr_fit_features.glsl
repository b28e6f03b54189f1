// BMFR's block grid, features and regularisation noise (docs/bmfr.md, "Phase II: the fit"), as
// the authors' OpenCL code computes them per pixel. Needs, before the #include: the push
// constants p.frame and p.noise_amount.

// The authors' 16 block-grid offsets: frame f shifts its grid by offset[f mod 16]
const ivec2 bmfr_block_offsets[16] = ivec2[16](
    ivec2(-14, -14), ivec2(4, -6), ivec2(-8, 14), ivec2(8, 0), ivec2(-10, -8), ivec2(2, 12),
    ivec2(12, -12), ivec2(-10, 0), ivec2(12, 14), ivec2(-8, -16), ivec2(6, 6), ivec2(-2, -2),
    ivec2(6, -14), ivec2(-16, 12), ivec2(14, -4), ivec2(-6, 4));

// A coordinate mirrored into [0, size): -1 -> 0, size -> size - 1, reflected again as often as
// needed (images narrower than a block). GLSL's % is undefined for negative operands: the
// negative side is folded by hand.
int bmfr_mirror(int index, int size) {
    const int period = 2 * size;
    const int m = index >= 0 ? index % period : period - 1 - (-index - 1) % period;
    return m < size ? m : period - 1 - m;
}

// A feature as the fit stores it: NaN -> 0, clamped to binary16's range (+-inf -> +-65504)
float clamp_feature(float v) { return isnan(v) ? 0.0 : clamp(v, -65504.0, 65504.0); }

// Bob Jenkins' six-shift integer hash, the authors' random() (docs/bmfr.md; the default)
uint jenkins_hash(uint a) {
    a = (a + 0x7ed55d16u) + (a << 12u);
    a = (a ^ 0xc761c23cu) ^ (a >> 19u);
    a = (a + 0x165667b1u) + (a << 5u);
    a = (a + 0xd3a2646cu) ^ (a << 9u);
    a = (a + 0xfd7046c5u) + (a << 3u);
    a = (a ^ 0xb55a4f09u) ^ (a >> 16u);
    return a;
}

// Thomas Wang's integer hash (bmfr_noise_hash=wang)
uint wang_hash(uint seed) {
    seed = (seed ^ 61u) ^ (seed >> 16u);
    seed *= 9u;
    seed = seed ^ (seed >> 4u);
    seed *= 0x27d4eb2du;
    seed = seed ^ (seed >> 15u);
    return seed;
}

// The regularisation noise of feature `feature` at block row `row` (the same in every block):
// 0.01 * 2 * (rho - 0.5), rho = hash(row + feature 1024 + frame 13 1024) / 4294967295.0
float regularisation_noise(int row, int feature) {
    const uint seed = uint(row) + uint(feature) * 1024u + uint(p.frame) * 13u * 1024u;
    const uint h = p.jenkins_hash != 0 ? jenkins_hash(seed) : wang_hash(seed);
    const float rho = float(h) / 4294967295.0;
    precise float noise = p.noise_amount * 2.0 * (rho - 0.5);
    return noise;
}

// Features 4..9 scaled to the block's range: (v - lo) / (hi - lo) when the range exceeds 1, else
// v - lo
float scale_feature(float v, float lo, float hi) {
    const float range = hi - lo;
    return range > 1.0 ? (v - lo) / range : v - lo;
}
