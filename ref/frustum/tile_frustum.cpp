#include "ref/frustum/tile_frustum.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "ref/bvh/watertight.h"

namespace fovref {

namespace {

// HLSL's min and max: when one operand is NaN, the other
float hlsl_min(float a, float b) { return std::fmin(a, b); }
float hlsl_max(float a, float b) { return std::fmax(a, b); }

bool closer(float t, std::int32_t primitive, const Hit& best) {
    return best.primitive < 0 || t < best.t || (t == best.t && primitive < best.primitive);
}

}  // namespace

TileFrustum tile_frustum(const Camera& camera, int width, int height, int x0, int y0, int x1,
                         int y1) {
    const float tan_half = tan_half_vfov(camera);
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    // the primary rays' screen-plane coordinates (primary_ray_direction)
    const auto a = [&](int x) {
        return ((2.0f * static_cast<float>(x)) / w - 1.0f) * tan_half * (w / h);
    };
    const auto sy = [&](int y) { return ((2.0f * static_cast<float>(y)) / h - 1.0f) * tan_half; };
    TileFrustum f;
    f.origin = camera.position;
    f.right = camera.right;
    f.up = camera.up;
    f.view = camera.forward;
    f.a0 = a(x0);
    f.a1 = a(x1);
    f.b0 = -sy(y1);
    f.b1 = -sy(y0);
    f.width_factor = (f.a1 - f.a0) * 0.5f;
    f.height_factor = (f.b1 - f.b0) * 0.5f;
    f.direction = f.view + ((f.a0 + f.a1) * 0.5f) * f.right + ((f.b0 + f.b1) * 0.5f) * f.up;
    return f;
}

bool shadow_frustum(glm::vec3 light, const std::vector<glm::vec3>& points, TileFrustum& f) {
    if (points.empty()) return false;
    const glm::dvec3 l(light);
    glm::dvec3 sum(0.0);
    for (const glm::vec3& p : points) {
        const glm::dvec3 d = glm::dvec3(p) - l;
        const double length = std::sqrt(glm::dot(d, d));
        if (!(length > 0.0) || !std::isfinite(length)) return false;
        sum += d / length;
    }
    const double sum_length = std::sqrt(glm::dot(sum, sum));
    if (!(sum_length > 0.0)) return false;
    const glm::dvec3 v = sum / sum_length;
    // the axis least aligned with V, then R and U (orthonormal, rounded once each)
    int axis = 0;
    for (int k = 1; k < 3; ++k)
        if (std::fabs(v[k]) < std::fabs(v[axis])) axis = k;
    glm::dvec3 e(0.0);
    e[axis] = 1.0;
    // the basis as stored (binary32): the bounds are measured in it, so that the pyramid the
    // tests see (these vectors) holds the points, not a pyramid of the unrounded basis
    const glm::vec3 vf(v), rf(glm::normalize(glm::cross(v, e)));
    const glm::vec3 uf(glm::cross(glm::dvec3(rf), v));
    const glm::dmat3 basis{glm::dvec3(rf), glm::dvec3(uf), glm::dvec3(vf)};  // columns R, U, V
    const glm::dmat3 to_basis = glm::inverse(basis);
    double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
    for (const glm::vec3& p : points) {
        const glm::dvec3 d = glm::dvec3(p) - l;
        // d = x R + y U + z V: z the depth, (a, b) = (x, y) / z on the plane at depth 1
        const glm::dvec3 c = to_basis * d;
        if (!(c.z > 0x1p-20 * std::sqrt(glm::dot(d, d)))) return false;
        const double a = c.x / c.z, b = c.y / c.z;
        a0 = std::min(a0, a), a1 = std::max(a1, a), b0 = std::min(b0, b), b1 = std::max(b1, b);
    }
    const double margin_a = (a1 - a0) * 0x1p-16 + 0x1p-20, margin_b = (b1 - b0) * 0x1p-16 + 0x1p-20;
    const auto down = [](double x) {
        const auto f32 = static_cast<float>(x);
        return static_cast<double>(f32) <= x ? f32 : std::nextafter(f32, -INFINITY);
    };
    const auto up = [](double x) {
        const auto f32 = static_cast<float>(x);
        return static_cast<double>(f32) >= x ? f32 : std::nextafter(f32, INFINITY);
    };
    f = TileFrustum{};
    f.origin = light;
    f.view = vf;
    f.right = rf;
    f.up = uf;
    f.a0 = down(a0 - margin_a);
    f.a1 = up(a1 + margin_a);
    f.b0 = down(b0 - margin_b);
    f.b1 = up(b1 + margin_b);
    f.width_factor = (f.a1 - f.a0) * 0.5f;
    f.height_factor = (f.b1 - f.b0) * 0.5f;
    f.direction = f.view + ((f.a0 + f.a1) * 0.5f) * f.right + ((f.b0 + f.b1) * 0.5f) * f.up;
    return true;
}

bool lund_box_test(const TileFrustum& f, glm::vec3 lo, glm::vec3 hi) {
    // d: the box's farthest point from the camera along V
    float d = -std::numeric_limits<float>::infinity();
    for (int k = 0; k < 8; ++k) {
        const glm::vec3 corner{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        d = std::max(d, glm::dot(corner - f.origin, f.view));
    }
    // eq. 3.14 and 3.15
    const float w_c = d * f.width_factor, h_c = d * f.height_factor;
    const glm::vec3 bias{std::fabs(w_c * f.right.x) + std::fabs(h_c * f.up.x),
                         std::fabs(w_c * f.right.y) + std::fabs(h_c * f.up.y),
                         std::fabs(w_c * f.right.z) + std::fabs(h_c * f.up.z)};
    // Listing 3.1
    const glm::vec3 o = f.origin;
    const glm::vec3 id{1.0f / f.direction.x, 1.0f / f.direction.y, 1.0f / f.direction.z};
    const float t1 = (lo.x - bias.x - o.x) * id.x, t2 = (hi.x + bias.x - o.x) * id.x;
    const float t3 = (lo.y - bias.y - o.y) * id.y, t4 = (hi.y + bias.y - o.y) * id.y;
    const float t5 = (lo.z - bias.z - o.z) * id.z, t6 = (hi.z + bias.z - o.z) * id.z;
    const float tmin = hlsl_max(hlsl_max(hlsl_min(t1, t2), hlsl_min(t3, t4)), hlsl_min(t5, t6));
    const float tmax = hlsl_min(hlsl_min(hlsl_max(t1, t2), hlsl_max(t3, t4)), hlsl_max(t5, t6));
    return tmax >= 0.0f && tmin <= tmax;
}

bool exact_box_test(const TileFrustum& f, glm::vec3 lo_f, glm::vec3 hi_f) {
    const glm::dvec3 lo(lo_f), hi(hi_f), o(f.origin);
    // the apex inside the box: they meet
    if (o.x >= lo.x && o.x <= hi.x && o.y >= lo.y && o.y <= hi.y && o.z >= lo.z && o.z <= hi.z)
        return true;
    // the pyramid = the 4 half-spaces n_i . (p - C) >= 0 of its side faces, oriented inwards
    const glm::dvec3 r(f.right), u(f.up), v(f.view);
    const double as[4] = {f.a0, f.a1, f.a1, f.a0}, bs[4] = {f.b0, f.b0, f.b1, f.b1};
    glm::dvec3 edges[4], normals[4];
    for (int i = 0; i < 4; ++i) edges[i] = v + as[i] * r + bs[i] * u;
    const glm::dvec3 centre = (edges[0] + edges[2]) * 0.5;
    for (int i = 0; i < 4; ++i) {
        normals[i] = glm::cross(edges[i], edges[(i + 1) % 4]);
        if (glm::dot(normals[i], centre) < 0.0) normals[i] = -normals[i];
    }
    // Otherwise they meet exactly when some face of the box keeps a point after clipping by the 4
    // half-spaces (the pyramid is unbounded, so what of it lies in the box crosses the box's
    // surface unless the apex is inside)
    const auto corner = [&](int k) {
        return glm::dvec3{(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    };
    static const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                    {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    for (const auto& face : faces) {
        std::vector<glm::dvec3> polygon = {corner(face[0]), corner(face[1]), corner(face[2]),
                                           corner(face[3])};
        for (const glm::dvec3& n : normals) {
            std::vector<glm::dvec3> clipped;
            for (std::size_t k = 0; k < polygon.size(); ++k) {
                const glm::dvec3 a = polygon[k], b = polygon[(k + 1) % polygon.size()];
                const double da = glm::dot(n, a - o), db = glm::dot(n, b - o);
                if (da >= 0.0) clipped.push_back(a);
                if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))
                    clipped.push_back(a + (b - a) * (da / (da - db)));
            }
            polygon = std::move(clipped);
            if (polygon.empty()) break;
        }
        if (!polygon.empty()) return true;
    }
    return false;
}

namespace {

struct Culler {
    const Bvh& bvh;
    const TileFrustum& frustum;
    const CullOptions& options;
    TileCulling& out;

    bool test(const BvhNode& node) {
        ++out.nodes_tested;
        return options.exact ? exact_box_test(frustum, node.bounds_min, node.bounds_max)
                             : lund_box_test(frustum, node.bounds_min, node.bounds_max);
    }
    // Visits node `index`, whose box passed the test; returns whether it stays in the tree
    bool keep(std::uint32_t index) {
        const BvhNode& node = bvh.nodes[index];
        if (node.count > 0) {
            out.kept[index] = 1;
            return true;
        }
        bool any = false;
        for (const std::uint32_t child : {node.first, node.first + 1})
            if (test(bvh.nodes[child]) && keep(child)) any = true;
        if (!any && options.trim) {
            ++out.nodes_trimmed;
            return false;
        }
        out.kept[index] = 1;
        return true;
    }
    int kept_children(std::uint32_t index) const {
        const BvhNode& node = bvh.nodes[index];
        if (node.count > 0) return 0;
        return out.kept[node.first] + out.kept[node.first + 1];
    }
    // Counts the tree below `index` (kept), bridging nodes with one kept child
    void count(std::uint32_t index) {
        const BvhNode& node = bvh.nodes[index];
        if (node.count > 0) {
            ++out.nodes_kept;
            ++out.leaves_kept;
            out.triangles_kept += node.count;
            return;
        }
        if (options.bridge && kept_children(index) == 1)
            ++out.nodes_bridged;
        else
            ++out.nodes_kept;
        for (const std::uint32_t child : {node.first, node.first + 1})
            if (out.kept[child]) count(child);
    }
};

}  // namespace

TileCulling cull_bvh(const Bvh& bvh, const TileFrustum& frustum, const CullOptions& options) {
    TileCulling out;
    out.kept.assign(bvh.nodes.size(), 0);
    if (bvh.nodes.empty()) return out;
    Culler c{bvh, frustum, options, out};
    if (!(c.test(bvh.nodes[0]) && c.keep(0))) return out;
    // Entry point: down from the root while a node has exactly one kept child
    std::uint32_t entry = 0;
    while (options.entry && c.kept_children(entry) == 1) {
        const BvhNode& node = bvh.nodes[entry];
        entry = out.kept[node.first] ? node.first : node.first + 1;
        ++out.entry_depth;
    }
    out.entry = entry;
    c.count(entry);
    return out;
}

namespace {

// Whether the ray's segment [t_min, t_max] meets box [lo, hi] widened by a relative 2^-20 (a
// slab test in binary64 that errs on the side of visiting: it only prunes the traversal)
bool segment_meets_box(const Ray& ray, glm::vec3 lo_f, glm::vec3 hi_f) {
    const glm::dvec3 o(ray.origin), d(ray.direction);
    double t0 = std::max(0.0, static_cast<double>(ray.t_min)), t1 = ray.t_max;
    for (int k = 0; k < 3; ++k) {
        const double pad = (std::fabs(lo_f[k]) + std::fabs(hi_f[k]) + 1.0) * 0x1p-20;
        const double lo = lo_f[k] - pad, hi = hi_f[k] + pad;
        if (d[k] == 0.0) {
            if (o[k] < lo || o[k] > hi) return false;
            continue;
        }
        double a = (lo - o[k]) / d[k], b = (hi - o[k]) / d[k];
        if (a > b) std::swap(a, b);
        t0 = std::max(t0, a);
        t1 = std::min(t1, b);
        if (t0 > t1) return false;
    }
    return true;
}

}  // namespace

std::vector<BvhNode> culled_tree(const Bvh& bvh, const TileCulling& culling,
                                 const CullOptions& options) {
    std::vector<BvhNode> tree;
    if (bvh.nodes.empty() || culling.kept.size() != bvh.nodes.size() ||
        !culling.kept[culling.entry])
        return tree;
    const auto kept_children = [&](std::uint32_t n) {
        const BvhNode& node = bvh.nodes[n];
        return node.count > 0 ? 0 : culling.kept[node.first] + culling.kept[node.first + 1];
    };
    // the node bridging leads to from n: down while a node has exactly one kept child
    const auto resolve = [&](std::uint32_t n) {
        while (options.bridge && kept_children(n) == 1) {
            const BvhNode& node = bvh.nodes[n];
            n = culling.kept[node.first] ? node.first : node.first + 1;
        }
        return n;
    };
    BvhNode empty;
    empty.bounds_min = glm::vec3(std::numeric_limits<float>::infinity());
    empty.bounds_max = glm::vec3(-std::numeric_limits<float>::infinity());
    empty.first = culled_tree_empty;
    empty.count = 0;
    // (record index, BVH2 node) of the inner nodes whose children are still to be placed
    std::vector<std::pair<std::size_t, std::uint32_t>> queue;
    const auto place = [&](std::uint32_t n) {
        tree.push_back(bvh.nodes[n]);
        if (bvh.nodes[n].count == 0) queue.emplace_back(tree.size() - 1, n);
    };
    place(resolve(culling.entry));
    for (std::size_t q = 0; q < queue.size(); ++q) {
        const auto [record, n] = queue[q];
        const BvhNode& node = bvh.nodes[n];
        tree[record].first = static_cast<std::uint32_t>(tree.size());
        tree[record].count = 0;
        for (const std::uint32_t child : {node.first, node.first + 1}) {
            if (culling.kept[child])
                place(resolve(child));
            else
                tree.push_back(empty);
        }
    }
    return tree;
}

TileCulling keep_everything(const Bvh& bvh) {
    TileCulling all;
    all.kept.assign(bvh.nodes.size(), 1);
    for (const BvhNode& node : bvh.nodes) {
        ++all.nodes_kept;
        if (node.count == 0) continue;
        ++all.leaves_kept;
        all.triangles_kept += node.count;
    }
    return all;
}

Hit trace_culled(const Bvh& bvh, const TileCulling& culling, const Ray& ray, TraceStats* stats) {
    Hit best;
    const glm::vec3 o = ray.origin, d = ray.direction;
    const bool valid = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z) &&
                       std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z) &&
                       (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f) && !std::isnan(ray.t_min) &&
                       !std::isnan(ray.t_max);
    if (!valid || bvh.nodes.empty() || !culling.kept[culling.entry]) return best;
    const WatertightRay r = make_watertight_ray(
        o, d, ray.t_min, std::min(ray.t_max, std::numeric_limits<float>::max()));
    // Every kept node from the entry point down (the closest hit with its tie-break does not
    // depend on the order)
    std::vector<std::uint32_t> stack = {culling.entry};
    while (!stack.empty()) {
        const std::uint32_t n = stack.back();
        stack.pop_back();
        const BvhNode& node = bvh.nodes[n];
        if (!segment_meets_box(ray, node.bounds_min, node.bounds_max)) continue;
        if (stats) ++stats->nodes_visited;
        if (node.count == 0) {
            for (const std::uint32_t child : {node.first, node.first + 1})
                if (culling.kept[child]) stack.push_back(child);
            continue;
        }
        for (std::uint32_t k = node.first; k < node.first + node.count; ++k) {
            float t, u, v;
            const glm::vec3* p = &bvh.triangle_corners[3 * static_cast<std::size_t>(k)];
            if (stats) ++stats->triangles_tested;
            if (!intersect_watertight(r, p[0], p[1], p[2], t, u, v)) continue;
            const auto primitive = static_cast<std::int32_t>(bvh.primitives[k]);
            if (closer(t, primitive, best)) best = Hit{t, primitive, u, v};
        }
    }
    if (stats) {
        ++stats->rays;
        stats->hits += best.hit() ? 1 : 0;
    }
    return best;
}

}  // namespace fovref
