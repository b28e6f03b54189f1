// Tile frustum tracing (Lund 2020 §3.7, §4.5; Hunt et al.'s tile frusta): the screen divided into
// tiles, each tile's frustum, Lund's approximate frustum-box test (a biased AABB against the
// frustum's centre ray, eq. 3.14-3.15 and Listing 3.1), an exact test for comparison, and the
// culled view of the BVH a tile's rays would traverse (docs/frustum.md).
//
// The frustum of tile [x0, x1) x [y0, y1) (pixel edges) of a W x H screen seen by camera C with
// axes R, U, V (right, up, forward) and t = tan(vfov / 2): on the plane at depth 1 along V the
// screen point (x, y) lies at a = ((2 x) / W - 1) t (W / H) along R and b = -((2 y) / H - 1) t
// along U (the primary rays' convention, docs/trace.md). The tile covers a in [a0, a1], b in
// [b0, b1]; its frustum is the pyramid {C + z (V + a R + b U) : z >= 0, a, b in the tile}.
//   centre ray (Lund's O_F, D_F): O_F = C, D_F = V + ((a0 + a1) / 2) R + ((b0 + b1) / 2) U, not
//     normalised (its V component is 1, so the ray is at depth z at t = z);
//   width and height factors: w_F = (a1 - a0) / 2, h_F = (b1 - b0) / 2, the half-extents of the
//     cross-section at depth 1 (choice: Lund says "the width and height of the frustum" without
//     saying full or half; the half-extent is what makes the biased box hold every point of the
//     cross-section around the centre ray); the cross-section at depth d is w_C = d w_F,
//     h_C = d h_F (eq. 3.14).
// Lund's test of box [lo, hi] (lund_box_test): d = the largest (corner - C) . V over the box's 8
//   corners; bias per axis k: |w_C R_k| + |h_C U_k| (eq. 3.15); then Listing 3.1 on the biased
//   box with O = O_F and iD = 1 / D_F: t1, t2 = (lo_x - bias_x - O_x) iD_x, (hi_x + bias_x - O_x)
//   iD_x, and so on; tmin = max(max(min(t1, t2), min(t3, t4)), min(t5, t6)), tmax alike with max
//   and min swapped; kept when tmax >= 0 and tmin <= tmax. binary32, min and max returning the
//   other operand when one is NaN (HLSL's). A point of the box at depth z in (0, d] inside the
//   frustum lies within z w_F <= d w_F of the centre ray along R (and d h_F along U), so the
//   biased box holds the centre ray's point at depth z: the test keeps every box the frustum
//   meets, up to rounding (tests/frustum/tile_frustum_test.cpp measures it).
// The exact test (exact_box_test), binary64: the box meets the pyramid when the apex C lies in
//   the box, or when one of the box's 6 faces keeps a point after clipping (Sutherland-Hodgman)
//   by the pyramid's 4 side half-spaces n_i . (p - C) >= 0 (n_i the side faces' normals turned
//   inwards): the pyramid is unbounded, so what of it lies in the box reaches the box's surface
//   unless the apex is inside. Touching counts as meeting.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "ref/bvh/bvh.h"
#include "ref/scene/camera.h"

namespace fovref {

struct TileFrustum {
    glm::vec3 origin{0.0f};     ///< O_F, the camera position
    glm::vec3 direction{0.0f};  ///< D_F, through the tile's centre, V component 1
    glm::vec3 right{0.0f}, up{0.0f}, view{0.0f};
    float width_factor = 0.0f;   ///< w_F
    float height_factor = 0.0f;  ///< h_F
    /// The tile on the plane at depth 1: a in [a0, a1] along R, b in [b0, b1] along U
    float a0 = 0.0f, a1 = 0.0f, b0 = 0.0f, b1 = 0.0f;
};

/// The frustum of tile [x0, x1) x [y0, y1) of a width x height screen.
TileFrustum tile_frustum(const Camera& camera, int width, int height, int x0, int y0, int x1,
                         int y1);

/// The shadow frustum of a tile towards a point light (docs/frustum.md "Shadow rays"): apex the
/// light L; V = the mean of the unit directions (p - L) / |p - L| over `points` (the tile's
/// shadow-ray origins; summed in binary64 in order, normalised, rounded); R = normalise(V x e)
/// with e the coordinate axis least aligned with V (the lowest index on a tie), U = R x V, each
/// rounded to binary32 (the frustum's vectors); with p - L = x R + y U + z V in that rounded
/// basis (solved in binary64), the bounds a0, a1 (b0, b1) are the least and largest x / z
/// (y / z), widened by 2^-16 of their extent plus 2^-20 and rounded outwards to binary32, so the
/// pyramid holds every point and thus every shadow segment from a point to L. False (no
/// frustum: the tile is traced unculled) without points, or when a point is not in front of L
/// along V by 2^-20 of its distance (a spread of 90 degrees or more).
bool shadow_frustum(glm::vec3 light, const std::vector<glm::vec3>& points, TileFrustum& frustum);
/// Lund's approximate frustum-box test (eq. 3.14-3.15, Listing 3.1).
bool lund_box_test(const TileFrustum& frustum, glm::vec3 lo, glm::vec3 hi);

/// The exact test: whether the box and the frustum's pyramid share a point (binary64).
bool exact_box_test(const TileFrustum& frustum, glm::vec3 lo, glm::vec3 hi);

/// Lund's three optimisations of a culled tree (§4.5.1), each on or off.
struct CullOptions {
    bool exact = false;  ///< the exact test instead of Lund's
    bool trim = true;    ///< inner nodes left without children removed
    bool entry = true;   ///< traversal starts at the deepest node holding every kept leaf
    bool bridge = true;  ///< nodes left with one child replaced by that child
};

/// A tile's culled view of the BVH2 (Bvh::nodes): Lund's TLAS tracer traverses the tree from the
/// root and culls a child whose box fails the test (its subtree is not visited).
struct TileCulling {
    std::vector<std::uint8_t> kept;  ///< per BVH2 node: visited and passed the test
    std::int64_t nodes_tested = 0;   ///< box tests made
    std::int64_t nodes_kept = 0;     ///< in the culled tree, after trimming and bridging
    std::int64_t leaves_kept = 0;
    std::int64_t triangles_kept = 0;
    std::int64_t nodes_trimmed = 0;  ///< inner nodes removed for having no kept child
    std::int64_t nodes_bridged = 0;  ///< inner nodes removed for having one kept child
    std::uint32_t entry = 0;         ///< the node traversal starts at
    std::int64_t entry_depth = 0;    ///< its depth (0: the root)
    /// the culled tree's memory: kept nodes x 32 bytes (BvhNode)
    std::int64_t bytes() const { return nodes_kept * 32; }
};

/// Culls `bvh` for `frustum`. An empty BVH gives no kept node.
TileCulling cull_bvh(const Bvh& bvh, const TileFrustum& frustum, const CullOptions& options = {});

/// The closest hit of `ray` among the triangles of the culled tree's kept leaves, with
/// trace_closest's watertight test and tie-break (lowest t, then lowest primitive id): the same
/// hit as trace_closest wherever the culling kept the triangle it hits. A depth-first BVH2
/// traversal from the entry node over the kept nodes whose box the ray's segment meets (a
/// binary64 slab test on the box widened by 2^-20 relative: it may visit a node it need not,
/// never skip one it must). `stats` (optional) counts the nodes visited and triangles tested.
Hit trace_culled(const Bvh& bvh, const TileCulling& culling, const Ray& ray,
                 TraceStats* stats = nullptr);

/// A tile's culled tree as a GPU traverses it (`fovref rays cull`, docs/frustum.md "Exporting the
/// culled trees"): BvhNode records, [0] the traversal's start (the entry node, or the node that
/// bridging leads to from it). A leaf keeps its BVH2 box and triangles (first, count: the BVH2's
/// leaf order); an inner node has count 0 and its two children at [first] and [first + 1], in
/// the BVH2's child order, each the kept child (with options.bridge, the node that bridging
/// leads to from it) or, where that child was culled, an empty slot: count 0 and first =
/// culled_tree_empty (a traversal skips it; its box is also empty, min +inf, max -inf).
/// Children pairs are appended breadth first. Empty when nothing is kept. Without empty slots
/// the record count is culling.nodes_kept.
std::vector<BvhNode> culled_tree(const Bvh& bvh, const TileCulling& culling,
                                 const CullOptions& options);
/// The `first` of an empty slot of culled_tree (no node: a culled child).
inline constexpr std::uint32_t culled_tree_empty = 0xffffffffu;

/// The culling that keeps the whole tree (every node, entry at the root): trace_culled over it
/// traverses the BVH2 unculled, the baseline of `fovref bench frustum`.
TileCulling keep_everything(const Bvh& bvh);

}  // namespace fovref
