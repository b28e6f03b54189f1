#version 450
// Lund's TAA (docs/temporal.md "Per pixel", Lund §3.4, Karis 2014), as a GPU developer writes it
// from the docs, one invocation per screen pixel p = (x, y), centre c = p + 1/2:
//   no history (the first frame): the current pixel, age 1
//   stationary camera (pose bit-equal to the previous one; decided on the host): the history
//     and age at p, never rejected nor clamped
//   otherwise: z = the current view depth at p (<= 0 or not finite: rejected), reprojected to
//     p', z' (include/taa_reproject.glsl; z' <= 0: rejected); the history colour and the
//     previous depth z_h bilinear at p' (taps at pixel centres, taps off the screen dropped and
//     the weights renormalised; no tap: rejected); the previous age that of the pixel under p'
//     depth rejection: kept when |z' - z_h| <= tau z'; otherwise rejected, or beyond the
//       periphery radius from the gaze kept with age 2 (Lund's flicker rule)
//     clamping: the history clamped per channel to the current 3x3 neighbourhood's min/max
//       (screen: a shared-memory tile of the workgroup's pixels plus a ring, clamped at the
//       screen's border) or to the box taa_source made in the buffer's space (clamp-buffer)
//   age_new = min(max(age, 1) + 1, cap) (2 for the periphery rule), w = 1 / age_new,
//   out = history (1 - w) + current w; a rejected pixel: the current pixel, age 1.
// Native GLSL arithmetic (the GPU's division and sqrt): not bit-exact. `precise` (no fused
// multiply-add) where the docs give the binary32 order: the reprojection and the blend; the
// bilinear sums are the compiler's to fuse.
// -DINJECT_BUG injects a typical porting bug: the history's bilinear taps taken around p'
// itself instead of p' - 1/2 (as if pixel centres were at the integers), which samples the
// history half a pixel off.
#extension GL_GOOGLE_include_directive : require
#include "taa_reproject.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 0) readonly buffer Colour { float colour[]; };
layout(std430, binding = 1) readonly buffer Depth { float depth[]; };
layout(std430, binding = 2) readonly buffer HistoryColour { float history_colour[]; };
layout(std430, binding = 3) readonly buffer HistoryAge { float history_age[]; };
layout(std430, binding = 4) readonly buffer HistoryDepth { float history_depth[]; };
layout(std430, binding = 5) readonly buffer Bounds { float bounds[]; };  // W x H x 6
layout(std430, binding = 6) writeonly buffer Result { float result[]; };
layout(std430, binding = 7) writeonly buffer ResultAge { float result_age[]; };
layout(std430, binding = 8) writeonly buffer Decision { uint decision[]; };
layout(push_constant) uniform Parameters {
    int width, height;
    int history;    // 0: none (the first frame), 1: stationary camera, 2: reprojected
    int rejection;  // 0: depth, 1: clamp to the screen's 3x3, 2: clamp to the buffer's box
    float tau, age_cap, periphery_radius, gaze_x, gaze_y;
    float sx_scale, sy_scale;
    float offset_x, offset_y, offset_z, forward_x, forward_y, forward_z;
    float right_x, right_y, right_z, up_x, up_y, up_z, a_x, a_y;
} p;

// The decisions, as the oracle's TaaDecision (the host counts them); NONFINITE is added to a
// rejection caused by a NaN or infinite input.
const uint FIRST = 0u, STATIONARY = 1u, KEPT = 2u, REJECTED = 3u, PERIPHERY = 4u, CLAMPED = 5u;
const uint NONFINITE = 8u;

shared vec3 tile[10][10];  // the current colour of the workgroup's 8x8 pixels and a 1-pixel ring

// The current colour of pixel xy.
vec3 colour_at(ivec2 xy) {
    const int i = (xy.y * p.width + xy.x) * 3;
    return vec3(colour[i], colour[i + 1], colour[i + 2]);
}

// Fills `tile` (clamp-screen only; every invocation of the group takes part).
void load_tile() {
    const ivec2 base = ivec2(gl_WorkGroupID.xy) * 8 - 1;
    for (uint i = gl_LocalInvocationIndex; i < 100u; i += 64u) {
        const ivec2 t = ivec2(i % 10u, i / 10u);
        tile[t.y][t.x] = colour_at(clamp(base + t, ivec2(0), ivec2(p.width - 1, p.height - 1)));
    }
    barrier();
}

// The history colour and previous depth at p', bilinear over the taps on the screen,
// renormalised; false when no tap is on the screen.
bool sample_history(vec2 q, out vec3 history, out float z_h) {
    history = vec3(0.0);
    z_h = 0.0;
    if (!taa_near_screen(q, vec2(p.width, p.height))) return false;
#ifdef INJECT_BUG
    const vec2 origin = q;
#else
    const vec2 origin = q - 0.5;
#endif
    ivec2 taps[4];
    float weights[4];
    taa_taps(origin, taps, weights);
    float sum = 0.0, z = 0.0;
    vec3 acc = vec3(0.0);
    for (int k = 0; k < 4; ++k) {
        const ivec2 t = taps[k];
        if (t.x < 0 || t.y < 0 || t.x >= p.width || t.y >= p.height) continue;
        const int pixel = t.y * p.width + t.x;
        sum += weights[k];
        acc += weights[k] * vec3(history_colour[pixel * 3], history_colour[pixel * 3 + 1],
                                 history_colour[pixel * 3 + 2]);
        z += weights[k] * history_depth[pixel];
    }
    if (!(sum > 0.0)) return false;
    history = acc / sum;
    z_h = z / sum;
    return true;
}

// The frame's reprojection constants from the push constants.
TaaReprojection reprojection() {
    return TaaReprojection(
        vec2(p.width, p.height), vec2(p.sx_scale, p.sy_scale),
        vec3(p.offset_x, p.offset_y, p.offset_z), vec3(p.forward_x, p.forward_y, p.forward_z),
        vec3(p.right_x, p.right_y, p.right_z), vec3(p.up_x, p.up_y, p.up_z), vec2(p.a_x, p.a_y));
}

// The min and max of the current 3x3 neighbourhood (from the tile) or of the buffer's box.
void clamp_box(ivec2 xy, out vec3 lo, out vec3 hi) {
    if (p.rejection == 2) {
        const int i = (xy.y * p.width + xy.x) * 6;
        lo = vec3(bounds[i], bounds[i + 1], bounds[i + 2]);
        hi = vec3(bounds[i + 3], bounds[i + 4], bounds[i + 5]);
        return;
    }
    const ivec2 t = ivec2(gl_LocalInvocationID.xy) + 1;
    lo = tile[t.y][t.x];
    hi = lo;
    for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
            lo = min(lo, tile[t.y + dy][t.x + dx]);
            hi = max(hi, tile[t.y + dy][t.x + dx]);
        }
}

// Writes the pixel's output colour, age and decision.
void store(int pixel, vec3 value, float age, uint what) {
    result[pixel * 3] = value.x;
    result[pixel * 3 + 1] = value.y;
    result[pixel * 3 + 2] = value.z;
    result_age[pixel] = age;
    decision[pixel] = what;
}

// Neither NaN nor infinite.
bool finite(float v) { return !isnan(v) && !isinf(v); }

// The history of pixel xy (stationary or reprojected) with its previous age, previous depth and
// the depth test's verdict; false (with `what` REJECTED, maybe | NONFINITE) when there is none.
bool previous_history(ivec2 xy, out vec3 history, out float age_previous, out float z_h,
                      out bool consistent, out uint what) {
    const int pixel = xy.y * p.width + xy.x;
    consistent = true;
    age_previous = 0.0;
    z_h = 0.0;
    history = vec3(0.0);
    if (p.history == 1) {
        history = vec3(history_colour[pixel * 3], history_colour[pixel * 3 + 1],
                       history_colour[pixel * 3 + 2]);
        age_previous = history_age[pixel];
        what = STATIONARY;
        return true;
    }
    const float z = depth[pixel];
    what = finite(z) ? REJECTED : REJECTED | NONFINITE;
    vec2 previous_point;
    float previous_depth;
    if (!(z > 0.0 && finite(z)) ||
        !taa_reproject(reprojection(), vec2(xy) + 0.5, z, previous_point, previous_depth) ||
        !sample_history(previous_point, history, z_h))
        return false;
    const ivec2 under =
        clamp(ivec2(floor(previous_point)), ivec2(0), ivec2(p.width - 1, p.height - 1));
    age_previous = history_age[under.y * p.width + under.x];
    consistent = abs(previous_depth - z_h) <= p.tau * previous_depth;
    what = KEPT;
    return true;
}

void main() {
    if (p.rejection == 1 && p.history == 2) load_tile();
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    if (xy.x >= p.width || xy.y >= p.height) return;
    const int pixel = xy.y * p.width + xy.x;
    const vec3 current = colour_at(xy);
    if (p.history == 0) {
        store(pixel, current, 1.0, FIRST);
        return;
    }
    vec3 history;
    float age_previous, z_h;
    bool consistent;
    uint what;
    if (!previous_history(xy, history, age_previous, z_h, consistent, what)) {
        store(pixel, current, 1.0, what);
        return;
    }
    if (!finite(history.x) || !finite(history.y) || !finite(history.z) || !finite(age_previous) ||
        !finite(z_h)) {
        store(pixel, current, 1.0, REJECTED | NONFINITE);
        return;
    }
    float age_new = min(max(age_previous, 1.0) + 1.0, p.age_cap);
    if (p.rejection != 0 && what != STATIONARY) {
        vec3 lo, hi;
        clamp_box(xy, lo, hi);
        const vec3 clamped = min(max(history, lo), hi);
        what = clamped == history ? KEPT : CLAMPED;
        history = clamped;
    } else if (!consistent) {
        // Lund's flicker rule: far from the gaze an inconsistent history is kept with age 2.
        if (!(distance(vec2(xy) + 0.5, vec2(p.gaze_x, p.gaze_y)) > p.periphery_radius)) {
            store(pixel, current, 1.0, REJECTED);
            return;
        }
        what = PERIPHERY;
        age_new = 2.0;
    }
    // precise: the docs' binary32 order, history (1 - w) + current w, not fused
    const float w = 1.0 / age_new;
    precise vec3 blended = history * (1.0 - w) + current * w;
    store(pixel, blended, age_new, what);
}
