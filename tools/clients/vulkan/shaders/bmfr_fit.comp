#version 450
// BMFR's fit (Koskela et al. 2019; docs/bmfr.md, "Phase II: the fit"), as a GPU developer writes
// it after the authors' OpenCL fit kernel: one workgroup of 256 invocations per block of the
// frame's shifted 32x32 grid, each invocation owning the block rows tid + 256 k (k = 0..3).
//   1. Gather: features [1, n, w, w^2] and the accumulated colour of the mirrored pixel, stored
//      (binary16 or binary32, include/bmfr_fit_storage.glsl); min and max of features 4..9 by a
//      tree reduction in shared memory; features 4..9 scaled to that range and stored again.
//   2. Householder QR of the 1024 x 13 matrix, columns 0..9 (pivot row c = column): the column's
//      norm below the pivot and the dot products u . a_j (j > column) as tree reductions in
//      shared memory, binary32 (the oracle sums in binary64, row order: where this port rounds
//      differently by design); a_ij -= ((2 u_i) d_j) / |u|^2, stored. The regularisation
//      noise of features 1..9 is added in float as column 0's reflection reads them (so its
//      reflection stores it). R's diagonal stays in float (shared memory). Columns 10..12 (the
//      colours) need no reflection: the back substitution reads rows 0..9 only.
//   3. Back substitution per colour channel, one invocation each, in the authors' order.
// Outputs per block: bmfr_weights (red w0..w9, green, blue) and bmfr_feature_range (6 minima,
// 6 maxima). `precise` where the oracle forbids contraction: the noise, s + x_c^2, s + u_c^2.
// Visual-Polar buffers (docs/visual-polar.md, "BMFR in Visual-Polar space"): columns clamp, rows
// wrap modulo the cell column's phi height H, a row beyond its column's n_c or untraced is a zero
// row (no noise, not in the ranges), and the cells above a column's staircase are not fitted.
// -DINJECT_BUG injects a typical porting bug: the block grid shifted by the previous frame's
// offset (a frame counter that the host advances after the fit instead of before it).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 256) in;
layout(std430, binding = 0) readonly buffer Accumulated { float accumulated[]; };
layout(std430, binding = 1) readonly buffer WorldPosition { float world_position[]; };
layout(std430, binding = 2) readonly buffer Normal { float normal[]; };
layout(std430, binding = 3) buffer Matrix { uint m[]; };
layout(std430, binding = 4) writeonly buffer Weights { float weights[]; };
layout(std430, binding = 5) writeonly buffer FeatureRange { float feature_range[]; };
// Visual-Polar only: the traced texels, and the row count n_c of each column
layout(std430, binding = 6) readonly buffer Valid { float valid[]; };
layout(std430, binding = 7) readonly buffer Rows { int rows[]; };
layout(push_constant) uniform Parameters {
    int width, height, cells_x, cells_y, frame, half_storage, visual_polar;
    float noise_amount, pivot_epsilon;
    int jenkins_hash;
} p;

const int local_size = 256;
const int rows_per_invocation = 4;  // 1024 rows / 256 invocations
const int bmfr_feature_count = 10;  // [1, n_x, n_y, n_z, w_x, w_y, w_z, w_x^2, w_y^2, w_z^2]
const int scaled_first = 4;         // features 4..9 are scaled per block
const int scaled_count = 6;
const int reduce_slots = 12;  // 6 minima + 6 maxima, or up to 12 dot products

int tid;                             // gl_LocalInvocationID.x
uint block;                          // the block's index in the outputs (row-major cells)
uint matrix_base;                    // the block's first word in m[]
bool has_data[rows_per_invocation];  // the invocation's rows that hold a texel (Visual-Polar)
#include "bmfr_fit_features.glsl"
#include "bmfr_fit_storage.glsl"

shared float partial[reduce_slots][local_size];         // the tree reductions
shared float pivot_value;                               // a_cc of the current column
shared float diagonal[bmfr_feature_count];              // R_ii (float, as the authors)
shared float r_rows[bmfr_feature_count][bmfr_columns];  // rows 0..9 of R for the back substitution

// Block row k of this invocation (rows interleaved so that neighbours read neighbouring words)
int own_row(int k) { return tid + k * local_size; }

// Sums partial[0 .. slots - 1][*] into partial[*][0] (pairwise tree, binary32)
void reduce_sum(int slots) {
    for (int stride = local_size / 2; stride > 0; stride >>= 1) {
        if (tid < stride)
            for (int k = 0; k < slots; ++k) partial[k][tid] += partial[k][tid + stride];
        barrier();
    }
}

// Minima of slots 0..5 and maxima of slots 6..11 into partial[*][0]
void reduce_min_max() {
    for (int stride = local_size / 2; stride > 0; stride >>= 1) {
        if (tid < stride)
            for (int k = 0; k < scaled_count; ++k) {
                partial[k][tid] = min(partial[k][tid], partial[k][tid + stride]);
                partial[k + scaled_count][tid] =
                    max(partial[k + scaled_count][tid], partial[k + scaled_count][tid + stride]);
            }
        barrier();
    }
}

// The frame's grid offset
ivec2 grid_offset() {
#ifdef INJECT_BUG
    return bmfr_block_offsets[(p.frame + 15) % 16];
#else
    return bmfr_block_offsets[p.frame % 16];
#endif
}

// The phi height H of a Visual-Polar cell column whose first column is origin_x: the largest n_c
// of its (clamped) columns
int cell_rows(int origin_x) {
    int height = 1;
    for (int k = 0; k < 32; ++k) height = max(height, rows[clamp(origin_x + k, 0, p.width - 1)]);
    return height;
}

// The texel behind block row `row` of the shifted grid: mirrored at the image's edges; in a
// Visual-Polar buffer columns clamp and rows wrap modulo H. False for a row without data.
bool source_texel(int row, out ivec2 xy) {
    const ivec2 offset = grid_offset();
    const ivec2 cell = ivec2(gl_WorkGroupID.xy);
    if (p.visual_polar == 0) {
        const ivec2 origin = cell * 32 - 16 + offset;
        xy = ivec2(bmfr_mirror(origin.x + row % 32, p.width),
                   bmfr_mirror(origin.y + row / 32, p.height));
        return true;
    }
    const ivec2 origin = ivec2(cell.x * 32 - 16 + offset.x, cell.y * 32 + offset.y);
    const int height = cell_rows(origin.x);
    const int y = origin.y + row / 32;
    xy = ivec2(clamp(origin.x + row % 32, 0, p.width - 1),
               y >= 0 ? y % height : height - 1 - (-y - 1) % height);
    return xy.y < rows[xy.x] && valid[xy.y * p.width + xy.x] != 0.0;
}

// Gathers the invocation's rows, stored (zero rows without data); returns the minima and maxima
// of their stored features 4..9 in lo, hi
void gather_rows(out float lo[scaled_count], out float hi[scaled_count]) {
    for (int f = 0; f < scaled_count; ++f) {
        lo[f] = 65504.0;
        hi[f] = -65504.0;
    }
    for (int k = 0; k < rows_per_invocation; ++k) {
        const int row = own_row(k);
        ivec2 xy;
        has_data[k] = source_texel(row, xy);
        float a[14];
        for (int j = 0; j < 14; ++j) a[j] = 0.0;
        if (has_data[k]) {
            const int texel = 3 * (xy.y * p.width + xy.x);
            const vec3 n = vec3(normal[texel], normal[texel + 1], normal[texel + 2]);
            const vec3 w =
                vec3(world_position[texel], world_position[texel + 1], world_position[texel + 2]);
            const vec3 w2 = w * w;
            a = float[14](1.0, n.x, n.y, n.z, w.x, w.y, w.z, w2.x, w2.y, w2.z, accumulated[texel],
                          accumulated[texel + 1], accumulated[texel + 2], 0.0);
            for (int j = 0; j < bmfr_columns; ++j) a[j] = clamp_feature(a[j]);
        }
        store_row(row, 0, a);  // rounds to the storage precision
        if (!has_data[k]) continue;
        for (int f = 0; f < scaled_count; ++f) {
            const float stored = storage_round(a[scaled_first + f]);
            lo[f] = min(lo[f], stored);
            hi[f] = max(hi[f], stored);
        }
    }
}

// Gathers the block, reduces the ranges of features 4..9 over it (tree in shared memory), writes
// them, and scales the rows' features 4..9 (stored again)
void gather_block() {
    float lo[scaled_count], hi[scaled_count];
    gather_rows(lo, hi);
    for (int f = 0; f < scaled_count; ++f) {
        partial[f][tid] = lo[f];
        partial[f + scaled_count][tid] = hi[f];
    }
    barrier();
    reduce_min_max();
    // A block without data (Visual-Polar) has the ranges 0
    const bool empty = partial[0][0] > partial[scaled_count][0];
    for (int f = 0; f < scaled_count; ++f) {
        lo[f] = empty ? 0.0 : partial[f][0];
        hi[f] = empty ? 0.0 : partial[f + scaled_count][0];
    }
    if (tid < scaled_count) {
        feature_range[block * 12u + uint(tid)] = lo[tid];
        feature_range[block * 12u + uint(tid + scaled_count)] = hi[tid];
    }
    for (int k = 0; k < rows_per_invocation; ++k) {
        if (!has_data[k]) continue;
        float a[14];
        load_row(own_row(k), scaled_first, a);
        for (int f = 0; f < scaled_count; ++f)
            a[scaled_first + f] = scale_feature(a[scaled_first + f], lo[f], hi[f]);
        store_row(own_row(k), scaled_first, a);
    }
}

// Columns column .. 12 of the invocation's row k as the reflection of column `column` reads
// them: column 0's reflection reads features 1..9 of a row with data with the regularisation
// noise added in float (not stored before the reflection stores it)
void read_row(int k, int column, inout float a[14]) {
    load_row(own_row(k), column, a);
    if (column == 0 && has_data[k])
        for (int f = 1; f < bmfr_feature_count; ++f) {
            precise float noisy = a[f] + regularisation_noise(own_row(k), f);
            a[f] = noisy;
        }
}

// One Householder reflection of columns column + 1 .. 12 about the pivot row c = column; leaves
// R_cc in diagonal[column]
void reflect_column(int column) {
    // The norm of the column below the pivot row (tree reduction), and the pivot
    barrier();  // partial[] and pivot_value are free again
    float norm = 0.0;
    for (int k = 0; k < rows_per_invocation; ++k) {
        const int row = own_row(k);
        const float x = load_entry(row, column);  // column 0 is the constant: no noise
        if (row > column) norm += x * x;
        if (row == column) pivot_value = x;
    }
    partial[0][tid] = norm;
    barrier();
    reduce_sum(1);
    const float s = partial[0][0], xc = pivot_value;
    precise float r = sqrt(s + xc * xc);
    const float uc = xc - r;
    precise float u_length_squared = s + uc * uc;
    if (!(u_length_squared > 0.0)) {  // nothing to reflect (uniform in the workgroup)
        if (tid == 0) diagonal[column] = xc;
        return;
    }
    // The dot products d_j = u . a_j over the rows >= c (one reduction slot per column j), from
    // the invocation's rows as the reflection reads them (kept for the update)
    const int count = bmfr_columns - 1 - column;
    float a[rows_per_invocation][14];
    float d[reduce_slots];
    for (int j = 0; j < count; ++j) d[j] = 0.0;
    for (int k = 0; k < rows_per_invocation; ++k) {
        const int row = own_row(k);
        if (row < column) continue;
        read_row(k, column, a[k]);
        const float u = row == column ? uc : a[k][column];
        for (int j = 0; j < count; ++j) d[j] += u * a[k][column + 1 + j];
    }
    barrier();  // every invocation has read partial[0][0]
    for (int j = 0; j < count; ++j) partial[j][tid] = d[j];
    barrier();
    reduce_sum(count);
    for (int j = 0; j < count; ++j) d[j] = partial[j][0];
    // a_ij -= ((2 u_i) d_j) / |u|^2 for the rows >= c, stored (the authors' order)
    for (int k = 0; k < rows_per_invocation; ++k) {
        const int row = own_row(k);
        if (row < column) continue;
        const float u2 = 2.0 * (row == column ? uc : a[k][column]);
        for (int j = 0; j < count; ++j)
            a[k][column + 1 + j] = a[k][column + 1 + j] - (u2 * d[j]) / u_length_squared;
        store_row(row, column + 1, a[k]);
    }
    if (tid == 0) diagonal[column] = r;
}

// Back substitution of colour channel `channel` from R's rows 0..9, in the authors' order: the
// row divided by its pivot first, w_i = b_i / R_ii - sum_{k > i} (R_ik w_k) / R_ii (k
// ascending); a pivot below pivot_epsilon gives 0, and so does a weight that overflows
void back_substitute(int channel) {
    float w[bmfr_feature_count];
    for (int i = bmfr_feature_count - 1; i >= 0; --i) {
        const float pivot = diagonal[i];
        w[i] = 0.0;
        if (!(abs(pivot) >= p.pivot_epsilon)) continue;
        float v = r_rows[i][bmfr_feature_count + channel] / pivot;
        for (int k = i + 1; k < bmfr_feature_count; ++k) v = v - (r_rows[i][k] * w[k]) / pivot;
        w[i] = isinf(v) || isnan(v) ? 0.0 : v;
    }
    for (int i = 0; i < bmfr_feature_count; ++i)
        weights[block * 30u + uint(channel * bmfr_feature_count + i)] = w[i];
}

void main() {
    tid = int(gl_LocalInvocationID.x);
    block = gl_WorkGroupID.y * uint(p.cells_x) + gl_WorkGroupID.x;
    // Visual-Polar: the cells above the column's staircase are not fitted (outputs stay 0)
    const int origin_x = int(gl_WorkGroupID.x) * 32 - 16 + grid_offset().x;
    if (p.visual_polar != 0 && int(gl_WorkGroupID.y) * 32 >= cell_rows(origin_x)) return;
    matrix_base = block * uint(bmfr_pixels * (p.half_storage != 0 ? 7 : bmfr_columns));
    gather_block();
    for (int column = 0; column < bmfr_feature_count; ++column) reflect_column(column);
    // Rows 0..9 of R (owned by invocations 0..9) into shared memory
    if (tid < bmfr_feature_count) {
        float a[14];
        load_row(tid, 0, a);
        for (int j = 0; j < bmfr_columns; ++j) r_rows[tid][j] = a[j];
    }
    barrier();
    if (tid < 3) back_substitute(tid);
}
