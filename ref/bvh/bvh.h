// Bounding volume hierarchy over triangles (SPEC §3): SAH BVH2 with a deterministic build,
// watertight ray-triangle intersection (Woop, Benthin, Wald 2013), closest hit with the SPEC
// tie-break, any hit for shadow rays. docs/bvh.md documents the build constants.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "ref/bvh/ray.h"

namespace fovref {

struct BvhBuildSettings {
    float traversal_cost = 1.0f;    ///< SAH cost of visiting an inner node
    float intersection_cost = 1.0f; ///< SAH cost of one ray-triangle test
    int bins = 32;                  ///< binned SAH: bins per axis
    int max_leaf_size = 8;          ///< a node with more triangles is always split
    bool operator==(const BvhBuildSettings&) const = default;
};

/// A node: an inner node has count == 0 and its children at `first` and `first + 1`; a leaf has
/// count > 0 triangles at Bvh::primitives[first .. first + count).
struct BvhNode {
    glm::vec3 bounds_min{0.0f};
    std::uint32_t first = 0;
    glm::vec3 bounds_max{0.0f};
    std::uint32_t count = 0;
    bool operator==(const BvhNode&) const = default;
};

struct BvhBuildStats {
    std::int64_t nodes = 0;
    std::int64_t leaves = 0;
    std::int64_t max_depth = 0;
    double sah_cost = 0.0;  ///< of the whole tree, relative to the root's surface area
};

/// Plain data: two trees built from the same input compare equal with ==.
struct Bvh {
    std::vector<BvhNode> nodes;              ///< nodes[0] is the root
    std::vector<std::uint32_t> primitives;   ///< triangle indices in leaf order
    std::vector<glm::vec3> triangle_corners; ///< 3 per triangle, in `primitives` order
    BvhBuildStats stats;
    bool operator==(const Bvh& o) const {
        return nodes == o.nodes && primitives == o.primitives && triangle_corners == o.triangle_corners;
    }
};

/// Builds over `positions` (3 corners per triangle, as in Scene::positions). Deterministic: same
/// input -> same tree; ties between equal costs or centroids are broken by triangle index.
/// Triangles with zero area or non-finite corners are never hit (they are kept out of the tree).
Bvh build_bvh(const std::vector<glm::vec3>& positions, const BvhBuildSettings& settings = {});

/// Closest hit (SPEC §3 tie-break). `stats` is incremented.
Hit trace_closest(const Bvh& bvh, const Ray& ray, TraceStats& stats);

/// Any hit in (t_min, t_max], returning on the first one found (shadow rays).
bool trace_any(const Bvh& bvh, const Ray& ray, TraceStats& stats);

/// The O(n) reference: every triangle tested with the same watertight test in index order.
/// Gives bit-identical t, primitive and barycentrics to trace_closest.
Hit trace_brute_force(const std::vector<glm::vec3>& positions, const Ray& ray);

}  // namespace fovref
