// INTERNAL to ref/bvh: shared by bvh_build.cpp and bvh_collapse.cpp only. Not part of the
// library's interface (include ref/bvh/bvh.h instead); nothing outside ref/bvh includes it.
// The box both use for surface areas, and the collapse steps that build_bvh (bvh_build.cpp)
// runs after the BVH2 build (bvh_collapse.cpp).
#pragma once

#include <limits>

#include <glm/glm.hpp>

#include "ref/bvh/bvh.h"

namespace fovref::bvh_internal {

inline constexpr float inf = std::numeric_limits<float>::infinity();

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
