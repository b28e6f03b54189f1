// INTERNAL to ref/bvh: shared by its .cpp files only. Not part of the library's interface
// (include ref/bvh/bvh.h instead); nothing outside ref/bvh includes it. The box the build and
// the collapse use for surface areas, the collapse steps that build_bvh (bvh_build.cpp) runs
// after the BVH2 build (bvh_collapse.cpp), and what the one-ray queries (bvh_traverse.cpp) and
// the packets (bvh_packets.cpp) share: which rays are traced, and the cull interval's margin.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

#include "ref/bvh/bvh.h"

namespace fovref::bvh_internal {

inline constexpr float inf = std::numeric_limits<float>::infinity();
inline constexpr float float_max = std::numeric_limits<float>::max();

/// Relative margin on the ray interval used to cull boxes (never to accept hits). The triangle
/// test's t is rounded and, for grazing triangles, can lie slightly outside the box interval
/// that contains the exact hit; boxes are culled only when their entry lies beyond
/// t_best * (1 + margin), so such a triangle is still tested and the result stays independent
/// of the traversal order (docs/bvh.md).
inline constexpr float cull_margin = 1.0f / 4096.0f;

/// The interval's ends widened by the margin, for the box tests only.
inline float widen_up(float t) { return std::min(t + std::fabs(t) * cull_margin, float_max); }
inline float widen_down(float t) { return std::max(t - std::fabs(t) * cull_margin, -float_max); }

/// Whether a ray is traced: finite origin and direction, a non-zero direction, no NaN in its
/// interval. Any other ray misses without a traversal (and is counted).
inline bool ray_is_valid(const Ray& ray) {
    const glm::vec3 o = ray.origin, d = ray.direction;
    const bool finite = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z) &&
                        std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
    return finite && (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f) && !std::isnan(ray.t_min) &&
           !std::isnan(ray.t_max);
}

/// max |coordinate| of the root's box (the box padding's scene term, make_box_ray and
/// make_slab_ray): non-negative values, so any order of the maxima gives the same float.
inline float scene_abs_max(const Bvh& bvh) {
    const BvhNode& root = bvh.nodes[0];
    float m = 0.0f;
    for (int a = 0; a < 3; ++a)
        m = std::max(m, std::max(std::fabs(root.bounds_min[a]), std::fabs(root.bounds_max[a])));
    return m;
}

/// Asks for a child's memory ahead of its use: both cache lines of the wide node `first` (count
/// 0), or the three lines of a leaf's first triangle block (the leaf's triangles [first, first +
/// count)). A hint only: results never depend on it.
inline __attribute__((always_inline)) void prefetch_child(const BvhWideNode* nodes,
                                                          const BvhTriangleBlock* blocks,
                                                          std::uint32_t first,
                                                          std::uint32_t count) {
    const char* p = count > 0 ? reinterpret_cast<const char*>(blocks + first / 4)
                              : reinterpret_cast<const char*>(nodes + first);
    __builtin_prefetch(p, 0, 3);
    __builtin_prefetch(p + 64, 0, 3);
    // a block: 144 bytes at 16-byte alignment (offset 0, 16, 32 or 48 in its first line), so
    // always three lines
    if (count > 0) __builtin_prefetch(p + 128, 0, 3);
}

/// Each wide node pushes at most 3 children and is at most bvh_max_depth + 1 levels deep.
inline constexpr int traversal_stack_size = 3 * (bvh_max_depth + 1) + 1;

struct Box {
    glm::vec3 lo{inf};
    glm::vec3 hi{-inf};
    void grow(const Box& b) {
        lo = glm::min(lo, b.lo);
        hi = glm::max(hi, b.hi);
    }
    void grow(glm::vec3 p) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    /// Half the surface area (the SAH only uses ratios). 0 for an empty box.
    float half_area() const {
        if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return 0.0f;
        const glm::vec3 d = hi - lo;
        return d.x * d.y + d.y * d.z + d.z * d.x;
    }
};

inline Box node_box(const BvhNode& n) {
    Box b;
    b.lo = n.bounds_min;
    b.hi = n.bounds_max;
    return b;
}

/// Fills bvh.triangle_blocks from bvh.triangle_corners (bvh_collapse.cpp). `bvh` has nodes.
void make_triangle_blocks(Bvh& bvh);

/// Fills bvh.wide_nodes, the BVH4 collapsed from bvh.nodes (bvh_collapse.cpp). `bvh` has nodes.
void collapse_to_bvh4(Bvh& bvh);

}  // namespace fovref::bvh_internal
