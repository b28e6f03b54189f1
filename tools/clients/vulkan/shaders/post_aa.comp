#version 450
// Meng's post anti-aliasing (docs/foveation.md, "Meng's post anti-aliasing"; Meng eq. 2.14), as
// a GPU developer writes it from the docs: at pixel centre c, t = min(|c - g| / R, 1) (R the
// map's R); the kernel size eta = 3 + 2 ceil((t - 0.10) / 0.05) (3 .. 39; t <= 0.05 gives
// eta <= 1: the pixel is copied), sigma = eta / 6 and
//   out = sum_dy g(dy) sum_dx g(dx) I(clamp(x + dx), clamp(y + dy)),
// each row sum left to right, rows top to bottom, g(d) = e^(-d^2 / (2 sigma^2)) / sum_d (native
// exp, the sum from the most negative d up).
// GPU layout: a 16 x 16 workgroup per tile. For each eta that one of its pixels needs, the
// workgroup computes that eta's weights, then the row sums its pixels of that eta read (their
// bounding box's columns, its rows and the eta - 1 rows around them) into shared memory, once
// each (the reference's row cache: the same operations on the same values), then each pixel of
// that eta sums its column's eta rows.
// -DINJECT_BUG injects a typical porting bug: the kernel's step count truncated by int() instead
// of rounded up, so every pixel beyond t = 0.10 gets a kernel 2 texels narrower.
#extension GL_GOOGLE_include_directive : require
#include "lp_map.glsl"

const int TILE = 16, MAX_HALF = 19, MAX_ETA = 2 * MAX_HALF + 1;

layout(local_size_x = TILE, local_size_y = TILE) in;
layout(std430, binding = 0) readonly buffer MapBlock { LpMap map; };  // the gaze and R
layout(std430, binding = 1) readonly buffer Source { float source[]; };
layout(std430, binding = 2) writeonly buffer Result { float result[]; };
layout(push_constant) uniform Parameters {
    int width, height, channels;
} p;

shared vec4 row_sums[(TILE + 2 * MAX_HALF) * TILE];  // row r of the tile's apron, column x
shared float weights[MAX_ETA];
shared float weight_sum;
// Per half = (eta - 1) / 2: the bounds of the tile's pixels of that eta (local x0, y0, x1, y1;
// x0 > x1 when none)
shared int bounds[MAX_HALF + 1][4];

// The kernel size at distance ratio t (0: no filter)
int kernel_size(float t) {
    t = min(t, 1.0);
    if (!(t > 0.05)) return 0;
#ifdef INJECT_BUG
    const int steps = int((t - 0.1) / 0.05);
#else
    const int steps = int(ceil((t - 0.1) / 0.05));
#endif
    return min(3 + 2 * steps, MAX_ETA);
}

vec4 load(int x, int y) {
    vec4 c = vec4(0.0);
    for (int k = 0; k < p.channels; ++k) c[k] = source[(y * p.width + x) * p.channels + k];
    return c;
}

void store(ivec2 xy, vec4 value) {
    const int pixel = xy.y * p.width + xy.x;
    for (int k = 0; k < p.channels; ++k) result[pixel * p.channels + k] = value[k];
}

// The normalised weights of size 2 half + 1 into `weights` (every invocation calls it)
void make_weights(int half_size, uint index) {
    const int size = 2 * half_size + 1;
    if (index < size) {
        const float sigma = float(size) / 6.0;
        const int d = int(index) - half_size;
        weights[index] = exp(-float(d * d) / (2.0 * sigma * sigma));
    }
    barrier();
    if (index == 0) {
        float sum = 0.0;
        for (int k = 0; k < size; ++k) sum += weights[k];
        weight_sum = sum;
    }
    barrier();
    if (index < size) weights[index] /= weight_sum;
    barrier();
}

// The row sums of size 2 half + 1 that the tile's pixels of that size read: columns x0 .. x1,
// rows y0 - half .. y1 + half of the tile (clamped to the screen), row r at row_sums[r TILE + x]
void make_row_sums(ivec2 origin, int half_size, ivec4 box, uint index) {
    const int columns = box.z - box.x + 1, rows = box.w - box.y + 1 + 2 * half_size;
    for (int k = int(index); k < rows * columns; k += TILE * TILE) {
        const int column = box.x + k % columns, r = k / columns;
        const int x = origin.x + column;
        const int yy = clamp(origin.y + box.y - half_size + r, 0, p.height - 1);
        precise vec4 sum = vec4(0.0);
        for (int dx = -half_size; dx <= half_size; ++dx)
            sum += weights[dx + half_size] * load(clamp(x + dx, 0, p.width - 1), yy);
        row_sums[r * TILE + column] = sum;
    }
    barrier();
}

void main() {
    const ivec2 origin = ivec2(gl_WorkGroupID.xy) * TILE;
    const ivec2 local = ivec2(gl_LocalInvocationID.xy);
    const ivec2 xy = origin + local;
    const uint index = gl_LocalInvocationIndex;
    if (index <= MAX_HALF) {
        bounds[index][0] = bounds[index][1] = TILE;
        bounds[index][2] = bounds[index][3] = -1;
    }
    barrier();
    int eta = 0;
    if (xy.x < p.width && xy.y < p.height) {
        eta = kernel_size(lp_gaze_distance(map, vec2(xy) + 0.5) / map.radius_max);
        if (eta == 0) {
            store(xy, load(xy.x, xy.y));
        } else {
            atomicMin(bounds[eta / 2][0], local.x);
            atomicMin(bounds[eta / 2][1], local.y);
            atomicMax(bounds[eta / 2][2], local.x);
            atomicMax(bounds[eta / 2][3], local.y);
        }
    }
    barrier();
    for (int half_size = 1; half_size <= MAX_HALF; ++half_size) {
        const ivec4 box = ivec4(bounds[half_size][0], bounds[half_size][1],
                                bounds[half_size][2], bounds[half_size][3]);
        if (box.x > box.z) continue;  // no pixel of this size: the same for the whole workgroup
        make_weights(half_size, index);
        make_row_sums(origin, half_size, box, index);
        if (eta == 2 * half_size + 1) {
            precise vec4 sum = vec4(0.0);
            for (int dy = -half_size; dy <= half_size; ++dy)
                sum += weights[dy + half_size] *
                       row_sums[(local.y - box.y + dy + half_size) * TILE + local.x];
            store(xy, sum);
        }
        barrier();
    }
}
