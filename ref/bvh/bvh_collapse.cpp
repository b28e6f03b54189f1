// The traversal layout built from the BVH2 of bvh_build.cpp (SPEC §3): the BVH4 that rays
// traverse (Bvh::wide_nodes) and the triangle blocks its leaves point into
// (Bvh::triangle_blocks: 4 triangles of leaf order per block, struct-of-arrays). docs/bvh.md,
// "Traversal tree (BVH4)" and "Triangle blocks (SoA leaves)" under "Build", gives the layouts.
// Order: wide nodes are stored depth first; a wide node's slots keep the BVH2's left-to-right
// order, and the inner child opened next is the one with the largest surface area, the first on
// ties. The boxes and the leaves are the BVH2's, bit for bit.
#include "ref/bvh/bvh_internal.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace fovref::bvh_internal {

namespace {

/// Appends the BVH4 node collapsed from BVH2 node `index` (and, depth first, those of its
/// inner children) to bvh.wide_nodes; returns its position. The children start as the BVH2
/// node's two; while there are fewer than 4, the inner child with the largest surface area
/// (the first on ties) is replaced in place by its two children, so the slots keep the BVH2's
/// left-to-right order. A root that is a leaf becomes the single child of the wide root.
std::uint32_t collapse_node(Bvh& bvh, std::uint32_t index) {
    const std::vector<BvhNode>& nodes = bvh.nodes;
    std::uint32_t slots[4];
    int used = 0;
    if (nodes[index].count > 0) {
        slots[used++] = index;
    } else {
        slots[used++] = nodes[index].first;
        slots[used++] = nodes[index].first + 1;
    }
    while (used < 4) {
        int widest = -1;
        float widest_area = -1.0f;
        for (int i = 0; i < used; ++i) {
            const BvhNode& child = nodes[slots[i]];
            const float area = node_box(child).half_area();
            if (child.count == 0 && area > widest_area) {
                widest = i;
                widest_area = area;
            }
        }
        if (widest < 0) break;
        const std::uint32_t first = nodes[slots[widest]].first;
        for (int i = used; i > widest + 1; --i) slots[i] = slots[i - 1];
        slots[widest] = first;
        slots[widest + 1] = first + 1;
        ++used;
    }

    const auto wide = static_cast<std::uint32_t>(bvh.wide_nodes.size());
    BvhWideNode empty{};
    for (int a = 0; a < 3; ++a)
        for (int i = 0; i < 4; ++i) {
            empty.bounds[a][0][i] = inf;
            empty.bounds[a][1][i] = -inf;
        }
    bvh.wide_nodes.push_back(empty);
    for (int i = 0; i < used; ++i) {
        const BvhNode& child = nodes[slots[i]];
        for (int a = 0; a < 3; ++a) {
            bvh.wide_nodes[wide].bounds[a][0][i] = child.bounds_min[a];
            bvh.wide_nodes[wide].bounds[a][1][i] = child.bounds_max[a];
        }
        // The recursion is at most as deep as the BVH2 (bvh_max_depth).
        const std::uint32_t first = child.count > 0 ? child.first : collapse_node(bvh, slots[i]);
        bvh.wide_nodes[wide].first[i] = first;
        bvh.wide_nodes[wide].count[i] = child.count;
    }
    return wide;
}

}  // namespace

void make_triangle_blocks(Bvh& bvh) {
    const std::size_t triangles = bvh.primitives.size();
    // The same corners in blocks of 4 triangles, one per lane (zeros after the last one).
    bvh.triangle_blocks.assign((triangles + 3) / 4, BvhTriangleBlock{});
    for (std::size_t i = 0; i < triangles; ++i)
        for (int k = 0; k < 3; ++k)
            for (int a = 0; a < 3; ++a)
                bvh.triangle_blocks[i / 4].corners[k][a][i % 4] =
                    bvh.triangle_corners[3 * i + k][a];
}

void collapse_to_bvh4(Bvh& bvh) {
    bvh.wide_nodes.reserve(bvh.nodes.size() / 2 + 1);
    collapse_node(bvh, 0);
}

}  // namespace fovref::bvh_internal
