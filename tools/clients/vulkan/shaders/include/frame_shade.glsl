// The hit's G-buffer record and its shading (docs/trace.md; ref/scene/surface.cpp,
// ref/raster/gbuffer.cpp, ref/trace/direct_light.cpp): the surface at barycentrics (u, v),
// view depth, hit distance, motion against the previous camera, then Lambert with one shadow
// ray per light (any hit). Bindings 3-6; needs frame_common.glsl and frame_bvh.glsl.

// Per primitive (original order), 16 floats: n0, n1, n2, uv0, uv1, uv2, material id
layout(std430, binding = 3) readonly buffer Attributes { float attributes[]; };
// Per material, 12 floats: albedo, emission, texel offset (int bits, -1: none), width, height
layout(std430, binding = 4) readonly buffer Materials { float materials[]; };
layout(std430, binding = 5) readonly buffer Texels { float texels[]; };  // RGB, top row first
// Per light, 16 floats: type (int bits: 0 point, 1 quad, 2 triangle), position, edge_u, edge_v,
// intensity
layout(std430, binding = 6) readonly buffer Lights { float lights[]; };

struct Surface {
    vec3 position, shading_normal, geometric_normal, albedo;
    int material;
};

vec3 load3(int base, int which) {
    if (which == 0) return vec3(attributes[base], attributes[base + 1], attributes[base + 2]);
    if (which == 1) return vec3(materials[base], materials[base + 1], materials[base + 2]);
    return vec3(lights[base], lights[base + 1], lights[base + 2]);
}

// Integral i modulo n, in [0, n) (GLSL's % is undefined for negative operands)
int wrap(float i, int n) {
    int k = int(i - floor(i / float(n)) * float(n));
    return k >= n ? k - n : (k < 0 ? k + n : k);
}

// Bilinear texture lookup, repeat wrap; texel centres at (i + 1/2) / W, v = 0 the bottom row
vec3 texture_bilinear(int offset, int width, int height, vec2 uv) {
    precise float x = uv.x * float(width) - 0.5, y = (1.0 - uv.y) * float(height) - 0.5;
    const float fx = floor(x), fy = floor(y);
    precise float tx = x - fx, ty = y - fy;
    const int x0 = wrap(fx, width), y0 = wrap(fy, height);
    const int x1 = wrap(fx + 1.0, width), y1 = wrap(fy + 1.0, height);
    vec3 result;
    for (int c = 0; c < 3; ++c) {
        const float a = texels[offset + (y0 * width + x0) * 3 + c];
        const float b = texels[offset + (y0 * width + x1) * 3 + c];
        const float d = texels[offset + (y1 * width + x0) * 3 + c];
        const float e = texels[offset + (y1 * width + x1) * 3 + c];
        precise float top = a * (1.0 - tx) + b * tx;
        precise float bottom = d * (1.0 - tx) + e * tx;
        precise float value = top * (1.0 - ty) + bottom * ty;
        result[c] = value;
    }
    return result;
}

// Triangle `primitive` (corners p0, p1, p2) at barycentrics (u, v) of corners 1 and 2
Surface surface_at(uint primitive, vec3 p0, vec3 p1, vec3 p2, float u, float v) {
    const int base = int(primitive) * 16;
    Surface s;
    precise float w = 1.0 - u - v;
    precise vec3 position = p0 * w + p1 * u + p2 * v;
    s.position = position;
    precise vec3 n = load3(base, 0) * w + load3(base + 3, 0) * u + load3(base + 6, 0) * v;
    const float length_n = sqrt(dot3(n, n));
    const vec3 g = cross3(p1 - p0, p2 - p0);
    const float length_g = sqrt(dot3(g, g));
    s.geometric_normal = length_g > 0.0 ? g / length_g : vec3(0.0);
    s.shading_normal = length_n > 0.0 ? n / length_n : s.geometric_normal;
    precise vec2 uv = vec2(attributes[base + 9], attributes[base + 10]) * w +
                      vec2(attributes[base + 11], attributes[base + 12]) * u +
                      vec2(attributes[base + 13], attributes[base + 14]) * v;
    s.material = int(attributes[base + 15]);
    const int m = s.material * 12;
    s.albedo = load3(m, 1);
    const int offset = floatBitsToInt(materials[m + 6]);
    if (offset >= 0) {
        precise vec3 albedo = s.albedo * texture_bilinear(offset, floatBitsToInt(materials[m + 7]),
                                                          floatBitsToInt(materials[m + 8]), uv);
        s.albedo = albedo;
    }
    return s;
}

// The screen point of world point p under the previous camera (false behind it)
bool project_previous(vec3 p, out vec2 screen) {
    const vec3 d = p - P.previous_position.xyz;
    const float depth = dot3(d, P.previous_forward.xyz);
    if (!(depth > 0.0)) return false;
    const float w = float(P.screen.x), h = float(P.screen.y), tan_half = P.previous_position.w;
    const float sx = dot3(d, P.previous_right.xyz) / depth;
    const float sy = -dot3(d, P.previous_up.xyz) / depth;
    screen = vec2((sx / (tan_half * (w / h)) + 1.0) * 0.5 * w, (sy / tan_half + 1.0) * 0.5 * h);
    return true;
}

// PCG hash chain rand(frame, pixel, dimension) in [0, 1) (SPEC §0)
uint pcg_hash(uint x) {
    const uint state = x * 747796405u + 2891336453u;
    const uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}
float rand_unit(uint frame, uint pixel, uint dimension) {
    return float(pcg_hash(pcg_hash(pcg_hash(frame) ^ pixel) ^ dimension) >> 8u) *
           (1.0 / 16777216.0);
}

// Lambert + emission with one shadow ray per light sample (docs/trace.md's basic shading)
vec3 shade_direct(Surface s, uint frame, uint pixel) {
    const vec3 to_eye = P.camera_position.xyz - s.position;
    const bool front = dot3(s.geometric_normal, to_eye) >= 0.0;
    const vec3 n_g = front ? s.geometric_normal : -s.geometric_normal;
    const vec3 n_s = dot3(s.shading_normal, n_g) < 0.0 ? -s.shading_normal : s.shading_normal;
    precise vec3 radiance = front ? load3(s.material * 12 + 3, 1) : vec3(0.0);
    const vec3 brdf = s.albedo * 0.318309886;
    for (int l = 0; l < P.counts.x; ++l) {
        const int base = l * 16, type = floatBitsToInt(lights[base]);
        precise vec3 y = load3(base + 1, 2);
        vec3 light_normal = vec3(0.0);
        float area = 0.0;
        if (type != 0) {  // an area light: a uniform point on it
            const float r1 = rand_unit(frame, pixel, uint(2 * l));
            const float r2 = rand_unit(frame, pixel, uint(2 * l + 1));
            const vec3 edge_u = load3(base + 4, 2), edge_v = load3(base + 7, 2);
            const vec3 c = cross3(edge_u, edge_v);
            const float c_length = sqrt(dot3(c, c));
            if (!(c_length > 0.0)) continue;
            light_normal = c / c_length;
            if (type == 1) {
                y = y + edge_u * r1 + edge_v * r2;
                area = c_length;
            } else {
                const float root = sqrt(r1);
                y = y + edge_u * (root * (1.0 - r2)) + edge_v * (root * r2);
                area = 0.5 * c_length;
            }
        }
        const vec3 to_light = y - s.position;
        const float d2 = dot3(to_light, to_light);
        if (!(d2 > 1e-20)) continue;
        const float d = sqrt(d2);
        const float cos_surface = dot3(n_s, to_light) / d;
        precise float geometry = cos_surface / d2;
        if (type != 0) geometry *= area * (-dot3(light_normal, to_light) / d);
        if (!(cos_surface > 0.0) || !(geometry > 0.0) || dot3(n_g, to_light) <= 0.0) continue;
        precise vec3 origin = s.position + n_g * P.scene.x;
        Hit blocker;
        if (trace_ray(origin, y - origin, 0.0, P.scene.z, true, blocker)) continue;
        radiance += brdf * load3(base + 10, 2) * geometry;
    }
    return radiance;
}
