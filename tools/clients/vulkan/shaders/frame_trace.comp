#version 450
// The end-to-end frame pass's trace-and-shade kernel (passes/frame.cpp), one invocation per
// texel of the log-polar buffer (launch 0; docs/foveation.md, "Ray generation") or per pixel of
// the gaze window (launch 1):
//   log-polar texel (i, j): p = inverse(i + 1/2, j + 1/2); off screen (p outside [0, W) x [0, H)
//     or not finite) or inside the gaze circle: no ray; else traced;
//   gaze pixel (x, y): traced when its centre (x + 1/2, y + 1/2) is inside the gaze circle;
// a traced texel or pixel casts the primary ray through p (SPEC §1), takes the closest hit on
// the BVH (frame_bvh.glsl), writes the G-buffer record (motion: the previous camera's projection
// minus p) and shades it (Lambert + shadow rays; rand's pixel index j w + i in the buffer,
// y W + x for the gaze pixels). Untraced texels and misses keep the background record.
// -DINJECT_BUG injects a typical porting bug: the texel centre without +1/2 (texel (i, j)
// mapped from (i, j), its corner).
#extension GL_GOOGLE_include_directive : require
layout(local_size_x = 8, local_size_y = 8) in;
#include "frame_common.glsl"
#include "frame_map.glsl"
#include "frame_bvh.glsl"
#include "frame_shade.glsl"
layout(std430, binding = 7) writeonly buffer Records { float records[]; };

// The primary ray's direction through screen point p: normalize(F + sx R - sy U)
vec3 primary_direction(vec2 p) {
    const float w = float(P.screen.x), h = float(P.screen.y), tan_half = P.camera_position.w;
    precise float sx = ((2.0 * p.x) / w - 1.0) * tan_half * (w / h);
    precise float sy = ((2.0 * p.y) / h - 1.0) * tan_half;
    precise vec3 d = P.camera_forward.xyz + sx * P.camera_right.xyz - sy * P.camera_up.xyz;
    return d / sqrt(dot3(d, d));
}

// The background record: ids -1, everything else 0
void clear_record(int r) {
    for (int k = 0; k < RECORD; ++k) records[r + k] = 0.0;
    records[r + R_MATERIAL] = -1.0;
    records[r + R_PRIMITIVE] = -1.0;
}

void write3(int at, vec3 value) {
    records[at] = value.x;
    records[at + 1] = value.y;
    records[at + 2] = value.z;
}

// Traces the primary ray through p and fills the record from its closest hit
void trace_and_shade(int r, vec2 p, uint pixel) {
    const vec3 origin = P.camera_position.xyz;
    Hit hit;
    if (!trace_ray(origin, primary_direction(p), 0.0, INFINITY, false, hit)) return;
    const Triangle tri = triangles[hit.triangle];
    const Surface s = surface_at(hit.primitive, tri.p0, tri.p1, tri.p2, hit.u, hit.v);
    const vec3 to_point = s.position - origin;
    records[r + R_VIEW_DEPTH] = dot3(to_point, P.camera_forward.xyz);
    records[r + R_HIT_DISTANCE] = sqrt(dot3(to_point, to_point));
    write3(r + R_POSITION, s.position);
    write3(r + R_SHADING_NORMAL, s.shading_normal);
    write3(r + R_GEOMETRIC_NORMAL, s.geometric_normal);
    write3(r + R_ALBEDO, s.albedo);
    records[r + R_MATERIAL] = float(s.material);
    records[r + R_PRIMITIVE] = float(hit.primitive);
    vec2 previous;
    if (project_previous(s.position, previous)) {
        records[r + R_MOTION] = previous.x - p.x;
        records[r + R_MOTION + 1] = previous.y - p.y;
    }
    write3(r + R_COLOR, shade_direct(s, uint(P.counts.y), pixel));
}

void main() {
    const ivec2 xy = ivec2(gl_GlobalInvocationID.xy);
    const bool gaze_launch = P.launch.x == 1;
    const ivec2 size = gaze_launch ? P.window.zw : P.screen.zw;
    if (xy.x >= size.x || xy.y >= size.y) return;
    const int r = (xy.y * size.x + xy.x) * RECORD;
    clear_record(r);
    vec2 p;
    uint pixel;
    float status = TRACED;
    if (gaze_launch) {
        const ivec2 screen_pixel = xy + P.window.xy;
        p = vec2(screen_pixel) + 0.5;
        pixel = uint(screen_pixel.y * P.screen.x + screen_pixel.x);
        if (!inside_gaze_circle(p)) status = OUTSIDE_CIRCLE;
    } else {
#ifdef INJECT_BUG
        const vec2 centre = vec2(xy);
#else
        const vec2 centre = vec2(xy) + 0.5;
#endif
        p = lp_inverse(centre);
        pixel = uint(xy.y * size.x + xy.x);
        records[r + R_SCREEN_POINT] = p.x;
        records[r + R_SCREEN_POINT + 1] = p.y;
        if (!(p.x >= 0.0 && p.x < float(P.screen.x) && p.y >= 0.0 && p.y < float(P.screen.y)))
            status = OFF_SCREEN;
        else if (inside_gaze_circle(p))
            status = INSIDE_GAZE;
    }
    records[r + R_STATUS] = status;
    if (status != TRACED) return;
    records[r + R_VALID] = 1.0;
    trace_and_shade(r, p, pixel);
}
