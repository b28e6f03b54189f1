// TAA's per-pixel geometry (docs/temporal.md, "Per pixel", steps 2 and 3), shared by the TAA
// shaders: where a pixel's surface point was in the previous frame, and the four bilinear taps
// of the history around that point. Plain functions of their arguments (no buffers), so they
// read like the docs' formulas.

// The frame's reprojection, factored on the host once per frame (as the oracle's
// TaaReprojection): the current camera's offset and axes in the previous camera's axes
// (x = .R', y = -.U', z = .F'), the current tan (W / H) and tan, the previous projection's scale.
struct TaaReprojection {
    vec2 screen;                      // W, H
    vec2 s_scale;                     // tan (W / H), tan
    vec3 offset, forward, right, up;  // o, f, r, u
    vec2 a;                           // (W / 2 / (tan' W / H), H / 2 / tan')
};

// Pixel centre c at view depth z (> 0): its point in the previous camera's view, q = o + z d
// with d = f + sx r - sy u (d . F = 1, so q is at view depth z in the current view). Writes
// p' = (q.x (a.x / z') + W / 2, q.y (a.y / z') + H / 2) and z' = q.z; false when z' <= 0
// (behind the previous camera).
bool taa_reproject(TaaReprojection k, vec2 centre, float z, out vec2 previous_point,
                   out float previous_depth) {
    // precise: the docs give each product in binary32 in this order (no fused multiply-add)
    precise float sx = ((2.0 * centre.x) / k.screen.x - 1.0) * k.s_scale.x;
    precise float sy = ((2.0 * centre.y) / k.screen.y - 1.0) * k.s_scale.y;
    precise vec3 d = k.forward + sx * k.right - sy * k.up;
    precise vec3 q = k.offset + z * d;
    previous_depth = q.z;
    previous_point = vec2(0.0);
    if (!(q.z > 0.0)) return false;
    precise vec2 point =
        vec2(q.x * (k.a.x / q.z) + 0.5 * k.screen.x, q.y * (k.a.y / q.z) + 0.5 * k.screen.y);
    previous_point = point;
    return true;
}

// The bilinear taps around `origin` (the sample point less 1/2, i.e. in the frame where pixel
// centres are integers): x0 = floor(origin.x), fx = origin.x - x0, likewise y; taps (x0, y0),
// (x0 + 1, y0), (x0, y0 + 1), (x0 + 1, y0 + 1) with the weights (1 - fx)(1 - fy), fx (1 - fy),
// (1 - fx) fy, fx fy, in that order. The caller drops the taps off the screen.
void taa_taps(vec2 origin, out ivec2 taps[4], out float weights[4]) {
    const ivec2 o = ivec2(floor(origin));
    const vec2 f = origin - vec2(o);
    taps[0] = o;
    taps[1] = o + ivec2(1, 0);
    taps[2] = o + ivec2(0, 1);
    taps[3] = o + ivec2(1, 1);
    weights[0] = (1.0 - f.x) * (1.0 - f.y);
    weights[1] = f.x * (1.0 - f.y);
    weights[2] = (1.0 - f.x) * f.y;
    weights[3] = f.x * f.y;
}

// Whether a sample point can have a tap on a W x H screen: within one pixel of it (the oracle's
// test, which also keeps far-off points from overflowing an int).
bool taa_near_screen(vec2 q, vec2 screen) {
    return q.x > -1.0 && q.y > -1.0 && q.x < screen.x + 1.0 && q.y < screen.y + 1.0;
}
