// Bounding volume hierarchy over triangles (SPEC §3): SAH BVH2 with a deterministic build,
// watertight ray-triangle intersection (Woop, Benthin, Wald 2013; ref/bvh/watertight.h), closest
// hit with the SPEC tie-break, any hit for shadow rays. Rays traverse a BVH4 collapsed from the
// BVH2 (four child boxes tested at once) and test a leaf's triangles four at a time from blocks
// of 4 in struct-of-arrays layout. docs/bvh.md documents the build constants, the layouts,
// the robust box test and the measured performance.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "ref/bvh/ray.h"

namespace fovref {

/// Binned SAH build constants (docs/bvh.md). The SAH cost of a split is
/// traversal_cost + intersection_cost * (A_left N_left + A_right N_right) / A_node, of a leaf
/// intersection_cost * N.
struct BvhBuildSettings {
    float traversal_cost = 1.0f;     ///< SAH cost of visiting an inner node
    float intersection_cost = 1.0f;  ///< SAH cost of one ray-triangle test
    int bins = 32;                   ///< binned SAH: bins per axis (2 .. 256)
    int max_leaf_size = 8;           ///< a node with more triangles is always split (1 .. 64)
    bool operator==(const BvhBuildSettings&) const = default;
};

/// Deepest tree the builder makes (the root has depth 0): a node at this depth becomes a leaf
/// whatever its size, so the traversal stack has a fixed size and bad input cannot overflow it.
inline constexpr int bvh_max_depth = 60;

/// A node (32 bytes): an inner node has count == 0 and its children at `first` and `first + 1`;
/// a leaf has count > 0 triangles at Bvh::primitives[first .. first + count).
struct BvhNode {
    glm::vec3 bounds_min{0.0f};
    std::uint32_t first = 0;
    glm::vec3 bounds_max{0.0f};
    std::uint32_t count = 0;
    bool operator==(const BvhNode&) const = default;
};

/// A node of the traversal tree (BVH4, 128 bytes, two cache lines), collapsed from the BVH2: its
/// up to 4 children are BVH2 nodes, their boxes stored per axis and side so that one 4-wide load
/// gives one plane of all four. A child with count > 0 is a leaf (triangles first .. first +
/// count in leaf order), one with count == 0 an inner node (wide_nodes[first]). An unused slot has
/// the empty box (min +inf, max -inf), which every ray misses, and first = count = 0.
struct alignas(64) BvhWideNode {
    float bounds[3][2][4];   ///< [axis][0: min, 1: max][child]
    std::uint32_t first[4];  ///< wide node index (inner child) or first triangle (leaf child)
    std::uint32_t count[4];  ///< triangles of a leaf child; 0 for an inner child or empty slot
    bool operator==(const BvhWideNode&) const = default;
};

/// Four consecutive triangles of leaf order (block b holds triangles 4b .. 4b + 3, i.e. the
/// corners triangle_corners[12b .. 12b + 12)), stored per corner and axis with one triangle per
/// lane, so that one 16-byte load gives one coordinate of all four (144 bytes). A leaf's
/// triangles first .. first + count lie in blocks first / 4 .. (first + count - 1) / 4; lanes of
/// other leaves are masked out. The lanes after the last triangle hold zeros and are never
/// tested.
struct alignas(16) BvhTriangleBlock {
    float corners[3][3][4];  ///< [corner 0, 1, 2][axis x, y, z][lane]
    bool operator==(const BvhTriangleBlock&) const = default;
};

struct BvhBuildStats {
    std::int64_t nodes = 0;
    std::int64_t leaves = 0;
    std::int64_t max_depth = 0;
    std::int64_t triangles = 0;             ///< in the tree
    std::int64_t degenerate_triangles = 0;  ///< zero area or non-finite corners: left out
    double sah_cost = 0.0;  ///< of the whole tree, relative to the root's surface area
};

/// Raw memory for the traversal arrays (bvh_memory.cpp): an allocation of 2 MiB or more is
/// aligned to 2 MiB and, on Linux, marked for transparent huge pages (madvise MADV_HUGEPAGE, as
/// Embree does for its BVH), so that rays scattered over a large tree take far fewer TLB misses.
/// Memory placement only: no result depends on it.
void* bvh_allocate(std::size_t bytes, std::size_t alignment);
void bvh_deallocate(void* p, std::size_t bytes, std::size_t alignment);

template <class T>
struct BvhAllocator {
    using value_type = T;
    BvhAllocator() = default;
    template <class U>
    BvhAllocator(const BvhAllocator<U>&) {}
    T* allocate(std::size_t n) { return static_cast<T*>(bvh_allocate(n * sizeof(T), alignof(T))); }
    void deallocate(T* p, std::size_t n) { bvh_deallocate(p, n * sizeof(T), alignof(T)); }
    template <class U>
    bool operator==(const BvhAllocator<U>&) const {
        return true;
    }
};

/// Plain data: two trees built from the same input compare equal with ==. A scene without a
/// hittable triangle has no nodes.
struct Bvh {
    std::vector<BvhNode> nodes;  ///< nodes[0] is the root; depth-first order
    std::vector<BvhWideNode, BvhAllocator<BvhWideNode>> wide_nodes;  ///< traversal tree; [0]: root
    std::vector<std::uint32_t> primitives;    ///< triangle indices in leaf order
    std::vector<glm::vec3> triangle_corners;  ///< 3 per triangle, in `primitives` order
    /// the same corners, 4 triangles per block
    std::vector<BvhTriangleBlock, BvhAllocator<BvhTriangleBlock>> triangle_blocks;
    BvhBuildStats stats;
    bool operator==(const Bvh& o) const {
        return nodes == o.nodes && wide_nodes == o.wide_nodes && primitives == o.primitives &&
               triangle_corners == o.triangle_corners && triangle_blocks == o.triangle_blocks;
    }
};

/// Builds over `positions` (3 corners per triangle, as in Scene::positions). Deterministic: same
/// input -> same tree; ties between equal costs or centroids are broken by triangle index.
/// Triangles with zero area or non-finite corners are never hit (they are kept out of the tree).
/// Throws fovref::Error when positions.size() is not a multiple of 3 or a setting is out of range.
Bvh build_bvh(const std::vector<glm::vec3>& positions, const BvhBuildSettings& settings = {});

/// Closest hit (SPEC §3 tie-break). `stats` is incremented. A ray with a zero or non-finite
/// direction, a non-finite origin or a NaN t_min / t_max misses (and is counted).
Hit trace_closest(const Bvh& bvh, const Ray& ray, TraceStats& stats);

/// trace_closest of rays[0 .. count) into hits[0 .. count): the same hits and the same `stats`,
/// bit for bit. The traversals of 16 rays are interleaved step by step, so that one ray's next
/// node loads while the others visit theirs. Each ray takes trace_closest's steps in its order;
/// only the order in time differs. Faster for incoherent rays over a tree larger than the
/// last-level cache (1.6x on million's random rays), slower for coherent rays or a small tree,
/// whose nodes are in cache anyway (0.53-0.75x): docs/bvh.md, "Interleaved queries".
void trace_closest_interleaved(const Bvh& bvh, const Ray* rays, std::size_t count, Hit* hits,
                               TraceStats& stats);

/// Any hit in (t_min, t_max], returning on the first one found (shadow rays).
bool trace_any(const Bvh& bvh, const Ray& ray, TraceStats& stats);

/// trace_any of rays[0 .. count) into occluded[0 .. count) (1: a hit in (t_min, t_max], 0: none),
/// the same answer for every ray (bvh_packets.cpp). Where the CPU has AVX (and simd_allowed()),
/// consecutive valid rays are traced eight at a time as one packet, one ray per lane: the packet
/// walks the BVH4 once, each lane testing the boxes with trace_any's operations (so it reaches
/// the leaves trace_any's ray may reach) and the leaves' triangles with the watertight test's
/// operations, and leaving the packet at its first hit. Coherent rays (a row of pixels' shadow
/// rays towards one light) then share each node's load and box test and each triangle's
/// corners. A packet holds rays of one direction octant and one watertight axis permutation: a
/// ray of another starts the next packet. `stats`: rays and hits as trace_any's;
/// nodes_visited counts, for each ray, the nodes it took part in, and triangles_tested its
/// triangles up to its first hit, which follow the packet's order (children by the entry
/// distances of its lowest active lane) and so differ from trace_any's. Without AVX: trace_any
/// ray by ray. docs/bvh.md, "Shadow-ray packets".
void trace_any_packets(const Bvh& bvh, const Ray* rays, std::size_t count, std::uint8_t* occluded,
                       TraceStats& stats);

/// The O(n) reference: every triangle tested with the same watertight test in index order.
/// Gives bit-identical t, primitive and barycentrics to trace_closest.
Hit trace_brute_force(const std::vector<glm::vec3>& positions, const Ray& ray);

}  // namespace fovref
