#include "ref/frustum/probe.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/scene/camera.h"

namespace fovref {

namespace {

// The nodes from the root to the leaf that holds `primitive` (empty when none does)
std::vector<std::uint32_t> path_to(const Bvh& bvh, std::int32_t primitive) {
    std::vector<std::uint32_t> path;
    const auto find = [&](auto&& self, std::uint32_t n) -> bool {
        path.push_back(n);
        const BvhNode& node = bvh.nodes[n];
        if (node.count > 0) {
            for (std::uint32_t k = node.first; k < node.first + node.count; ++k)
                if (static_cast<std::int32_t>(bvh.primitives[k]) == primitive) return true;
        } else if (self(self, node.first) || self(self, node.first + 1)) {
            return true;
        }
        path.pop_back();
        return false;
    };
    if (!bvh.nodes.empty() && primitive >= 0) find(find, 0);
    return path;
}

}  // namespace

void explain_frustum_pixel(const ProbeContext& c, const FrustumSettings& s, ProbeReport& report) {
    const int width = c.settings->width, height = c.settings->height, size = s.tile_size;
    const int tx = c.x / size, ty = c.y / size;
    const int x0 = tx * size, y0 = ty * size;
    const int x1 = std::min(x0 + size, width), y1 = std::min(y0 + size, height);
    const Bvh bvh = build_bvh(c.scene->positions);
    const TileFrustum f = tile_frustum(c.camera, width, height, x0, y0, x1, y1);
    const TileCulling culled = cull_bvh(bvh, f, s.options);
    ProbeSection t{"frustum_cull",
                   std::string("the pixel's tile and its culled BVH (") +
                       (s.options.exact ? "exact test" : "Lund's test") + ", docs/frustum.md)",
                   {}};
    t.add("tile", "(" + std::to_string(tx) + ", " + std::to_string(ty) + "): pixels " +
                      std::to_string(x0) + ".." + std::to_string(x1 - 1) + " x " +
                      std::to_string(y0) + ".." + std::to_string(y1 - 1));
    t.add("frustum ray",
          "O_F " + probe_vec3(f.origin) + ", D_F " + probe_vec3(f.direction) + " (V component 1)");
    t.add("factors", "w_F " + probe_float(f.width_factor) + ", h_F " +
                         probe_float(f.height_factor) + " (half-extents at depth 1)");
    t.add("culled tree",
          std::to_string(culled.nodes_kept) + " nodes (" + std::to_string(culled.nodes_trimmed) +
              " trimmed, " + std::to_string(culled.nodes_bridged) + " bridged), " +
              std::to_string(culled.triangles_kept) + " triangles, entry node " +
              std::to_string(culled.entry) + " at depth " + std::to_string(culled.entry_depth) +
              ", " + std::to_string(culled.nodes_tested) + " box tests");
    Ray ray;
    ray.origin = c.camera.position;
    ray.direction =
        primary_ray_direction(c.camera, tan_half_vfov(c.camera), width, height,
                              static_cast<float>(c.x) + 0.5f, static_cast<float>(c.y) + 0.5f);
    TraceStats stats;
    const Hit whole = trace_closest(bvh, ray, stats);
    const Hit through = trace_culled(bvh, culled, ray);
    t.add("hit", whole.hit() ? "primitive " + std::to_string(whole.primitive) + " at t " +
                                   probe_float(whole.t) + " (whole BVH); " +
                                   (through == whole ? "the same through the culled tree"
                                                     : "LOST by the culling: primitive " +
                                                           std::to_string(through.primitive))
                             : "none (background)");
    // The path to the hit's leaf, each node's test
    for (const std::uint32_t n : path_to(bvh, whole.primitive)) {
        const BvhNode& node = bvh.nodes[n];
        float d = -INFINITY;
        for (int k = 0; k < 8; ++k) {
            const glm::vec3 corner{(k & 1) ? node.bounds_max.x : node.bounds_min.x,
                                   (k & 2) ? node.bounds_max.y : node.bounds_min.y,
                                   (k & 4) ? node.bounds_max.z : node.bounds_min.z};
            d = std::max(d, glm::dot(corner - f.origin, f.view));
        }
        t.add("node " + std::to_string(n),
              std::string(node.count > 0 ? "leaf" : "inner") + ", box " +
                  probe_vec3(node.bounds_min) + ".." + probe_vec3(node.bounds_max) + ", d " +
                  probe_float(d) + ": Lund " +
                  (lund_box_test(f, node.bounds_min, node.bounds_max) ? "keeps" : "culls") +
                  ", exact " +
                  (exact_box_test(f, node.bounds_min, node.bounds_max) ? "keeps" : "culls") +
                  (culled.kept[n] ? "; in the culled tree" : "; not in the culled tree"));
    }
    report.sections.push_back(t);
}

}  // namespace fovref
