// Ray queries on the frame pass's own BVH2 (passes/frame_bvh.h: nodes depth first, the left
// child next to its parent, the right child's index stored; leaves hold ranges of triangles in
// leaf order). Bindings 1 (nodes) and 2 (triangles); needs frame_common.glsl.
//
// Triangle test: Woop, Benthin, Wald 2013's watertight test, as docs/bvh.md states it, written
// `precise` (no contraction, so a shared edge gives exactly opposite edge functions). Where an
// edge function is exactly 0 the reference recomputes U, V, W in binary64; this port has no
// binary64 (no shaderFloat64 asked for) and recomputes them with the FMA's exact products
// instead: q_x p_y - q_y p_x = (a - b) + (e_a - e_b), a = q_x p_y, e_a = fma(q_x, p_y, -a).
// Traversal: ordered (the nearer child first), a stack of 64 entries; boxes padded by the
// host's margin (2^-19 x the largest scene coordinate, plus that of the ray origin) and culled
// beyond t_best (1 + 2^-12) as in docs/bvh.md, so a hit that rounds just outside its box is
// still tested. Closest hit: the smallest t, then the lowest primitive id (SPEC §3).

struct Node {
    vec3 lo;
    uint a;
    vec3 hi;
    uint count;
};
struct Triangle {
    vec3 p0;
    uint primitive;
    vec3 p1;
    float pad1;
    vec3 p2;
    float pad2;
};
layout(std430, binding = 1) readonly buffer Nodes { Node nodes[]; };
layout(std430, binding = 2) readonly buffer Triangles { Triangle triangles[]; };

#define INFINITY uintBitsToFloat(0x7f800000u)

struct WatertightRay {
    vec3 origin;
    int kx, ky, kz;
    float sx, sy, sz, t_min, t_max;
};

struct Hit {
    float t, u, v;
    int triangle;  // leaf-order index, -1: none
    uint primitive;
};

// The paper's per-ray set-up: kz the axis of the largest |d| (ties to the lower axis)
WatertightRay watertight_ray(vec3 origin, vec3 d, float t_min, float t_max) {
    WatertightRay r;
    r.origin = origin;
    r.t_min = t_min;
    r.t_max = min(t_max, 3.40282347e38);
    int kz = abs(d.y) > abs(d.x) ? 1 : 0;
    kz = abs(d.z) > abs(d[kz]) ? 2 : kz;
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0) {
        const int swap = kx;
        kx = ky;
        ky = swap;
    }
    r.kx = kx;
    r.ky = ky;
    r.kz = kz;
    r.sx = d[kx] / d[kz];
    r.sy = d[ky] / d[kz];
    r.sz = 1.0 / d[kz];
    return r;
}

// q_x p_y - q_y p_x with exact products (the edge function's fallback)
float edge_exact(float px, float py, float qx, float qy) {
    precise float a = qx * py, b = qy * px;
    precise float ea = fma(qx, py, -a), eb = fma(qy, px, -b);
    precise float e = (a - b) + (ea - eb);
    return e;
}

// The watertight test of triangle k: t in (t_min, t_max], barycentrics of corners 1 and 2
bool intersect_triangle(WatertightRay ray, int k, out float t, out float u, out float v) {
    precise vec3 A = triangles[k].p0 - ray.origin;
    precise vec3 B = triangles[k].p1 - ray.origin;
    precise vec3 C = triangles[k].p2 - ray.origin;
    precise float Ax = A[ray.kx] - ray.sx * A[ray.kz], Ay = A[ray.ky] - ray.sy * A[ray.kz];
    precise float Bx = B[ray.kx] - ray.sx * B[ray.kz], By = B[ray.ky] - ray.sy * B[ray.kz];
    precise float Cx = C[ray.kx] - ray.sx * C[ray.kz], Cy = C[ray.ky] - ray.sy * C[ray.kz];
    precise float U = Cx * By - Cy * Bx, V = Ax * Cy - Ay * Cx, W = Bx * Ay - By * Ax;
    if (U == 0.0 || V == 0.0 || W == 0.0) {
        U = edge_exact(Bx, By, Cx, Cy);
        V = edge_exact(Cx, Cy, Ax, Ay);
        W = edge_exact(Ax, Ay, Bx, By);
    }
    if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
    precise float det = U + V + W;
    if (det == 0.0) return false;
    precise float T =
        U * (ray.sz * A[ray.kz]) + V * (ray.sz * B[ray.kz]) + W * (ray.sz * C[ray.kz]);
    const float T_signed = det < 0.0 ? -T : T;
    const float det_abs = abs(det);
    if (!(T_signed > ray.t_min * det_abs && T_signed <= ray.t_max * det_abs)) return false;
    const float rcp_det = 1.0 / det;
    t = T * rcp_det;
    if (!(t > ray.t_min && t <= ray.t_max)) return false;
    u = V * rcp_det;
    v = W * rcp_det;
    return true;
}

// The entry distance of node n's padded box, or +inf when the ray misses it within [lo, hi]
float box_entry(int n, vec3 origin, vec3 inverse_d, float pad, float t_lo, float t_hi) {
    const vec3 a = (nodes[n].lo - pad - origin) * inverse_d;
    const vec3 b = (nodes[n].hi + pad - origin) * inverse_d;
    const vec3 near = min(a, b), far = max(a, b);
    const float entry = max(max(near.x, near.y), max(near.z, t_lo));
    const float exit = min(min(far.x, far.y), min(far.z, t_hi));
    return entry <= exit ? entry : INFINITY;
}

// The closest hit (any_hit: the first hit found) of the ray origin + t d, t in (t_min, t_max]
bool trace_ray(vec3 origin, vec3 d, float t_min, float t_max, bool any_hit, out Hit hit) {
    hit.t = INFINITY;
    hit.triangle = -1;
    hit.primitive = 0xffffffffu;
    const WatertightRay ray = watertight_ray(origin, d, t_min, t_max);
    const vec3 inverse_d = 1.0 / d;
    const float pad =  // 2^-19 (max |scene coordinate| + max |origin coordinate|)
        P.scene.y + 1.9073486e-6 * max(max(abs(origin.x), abs(origin.y)), abs(origin.z));
    const float margin = 1.0 + 1.0 / 4096.0;
    const float t_lo = t_min * (1.0 - 1.0 / 4096.0);
    int stack[64];
    int top = 0;
    int n = 0;
    if (box_entry(0, origin, inverse_d, pad, t_lo, ray.t_max * margin) == INFINITY) return false;
    while (true) {
        if (nodes[n].count > 0) {  // leaf: test its triangles
            const int first = int(nodes[n].a), last = first + int(nodes[n].count);
            for (int k = first; k < last; ++k) {
                float t, u, v;
                if (!intersect_triangle(ray, k, t, u, v)) continue;
                const uint primitive = triangles[k].primitive;
                if (t < hit.t || (t == hit.t && primitive < hit.primitive)) {
                    hit = Hit(t, u, v, k, primitive);
                    if (any_hit) return true;
                }
            }
        } else {  // inner: the nearer child next, the other pushed
            const float t_hi = min(hit.t, ray.t_max) * margin;
            const int left = n + 1, right = int(nodes[n].a);
            const float a = box_entry(left, origin, inverse_d, pad, t_lo, t_hi);
            const float b = box_entry(right, origin, inverse_d, pad, t_lo, t_hi);
            const bool hit_a = a != INFINITY, hit_b = b != INFINITY;
            if (hit_a && hit_b) {
                n = a <= b ? left : right;
                stack[top++] = a <= b ? right : left;
                continue;
            }
            if (hit_a || hit_b) {
                n = hit_a ? left : right;
                continue;
            }
        }
        if (top == 0) break;
        n = stack[--top];
    }
    return hit.triangle >= 0;
}
