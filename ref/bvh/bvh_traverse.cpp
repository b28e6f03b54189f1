// Ray queries on the BVH (SPEC §3): trace_closest, trace_any and the brute-force reference
// trace_brute_force. Rays traverse the BVH4 of bvh_collapse.cpp depth first in entry order (an
// ordered, robust slab test on four boxes at once) and test a leaf's triangles four at a time
// with the watertight test. docs/bvh.md, "Traversal", explains the choices. Order: the children
// hit are visited by entry distance, the lower slot first on ties; the closest hit is the
// smallest t, then the lowest primitive index (the lanes of a block reduced in leaf order); an
// any-hit query stops at the first block with a hit.
#include "ref/bvh/bvh.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "ref/bvh/bvh_internal.h"
#include "ref/bvh/watertight.h"
#include "ref/bvh/watertight4.h"

// The box and triangle tests use SSE (baseline x86-64) when available (FOVREF_BVH_SSE, set in
// watertight4.h); FOVREF_BVH_SCALAR forces the plain path, which computes the same values lane by
// lane (the tests can be run with either).

namespace fovref {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
using bvh_internal::float_max;
using bvh_internal::ray_is_valid;
using bvh_internal::traversal_stack_size;
using bvh_internal::widen_down;
using bvh_internal::widen_up;

/// The watertight setup; t_max is clamped to the largest float so that t is always finite.
WatertightRay make_triangle_ray(const Ray& ray) {
    return make_watertight_ray(ray.origin, ray.direction, ray.t_min,
                               std::min(ray.t_max, float_max));
}

/// Per-ray constants of the slab test (the scalar path's BoxRay; the SSE path computes the same
/// values in make_box_ray). Every box is padded by `pad` in every direction (see
/// make_slab_ray); a padded plane is reached from a shifted origin, so the test costs no more
/// than an unpadded one.
struct SlabRay {
    glm::vec3 inv_direction{0.0f};
    glm::vec3 origin_near{0.0f};   ///< origin + pad * sign(direction): reaches the near planes
    glm::vec3 origin_far{0.0f};    ///< origin - pad * sign(direction): reaches the far planes
    int near_side[3] = {0, 0, 0};  ///< 1 where the direction is negative: near plane = box max
    float t_lo = 0.0f;             ///< t_min, widened by the margin (boxes only)
};

/// Robust slab test setup. The watertight test decides a hit exactly for its rounded, sheared
/// corners, which lie within 6 eps |corner - origin| (eps = 2^-24) of the true corners along the
/// two sheared axes; the slab distances themselves carry up to 3 eps relative rounding (the
/// concern of Ize 2013, "Robust BVH Ray Traversal"). Padding every box by
/// pad = 2^-19 (max |scene coordinate| + max |origin coordinate|), i.e. 32 eps times a bound on
/// |corner - origin|, covers both with room to spare, so a box is never culled when the triangle
/// test would report a hit inside it (the argument of Woop et al. 2013 for a conservative box
/// test).
[[maybe_unused]] SlabRay make_slab_ray(const Bvh& bvh, const Ray& ray) {
    SlabRay r;
    const glm::vec3 origin_abs = glm::abs(ray.origin);
    const float scene_max = bvh_internal::scene_abs_max(bvh);
    const float origin_max = std::max(std::max(origin_abs.x, origin_abs.y), origin_abs.z);
    const float pad = (scene_max + origin_max) * (1.0f / 524288.0f);
    for (int a = 0; a < 3; ++a) {
        r.inv_direction[a] = 1.0f / ray.direction[a];  // +-inf for a zero component
        const bool negative = std::signbit(r.inv_direction[a]);
        r.near_side[a] = negative ? 1 : 0;
        const float shift = negative ? -pad : pad;
        r.origin_near[a] = ray.origin[a] + shift;
        r.origin_far[a] = ray.origin[a] - shift;
    }
    r.t_lo = widen_down(ray.t_min);
    return r;
}

/// Entry distances of the ray into the padded boxes of a wide node's 4 children within
/// [t_lo, t_hi]; returns the mask of the children hit (bit i: child i) and their entries.
/// A zero direction component gives (plane - shifted origin) * inf = +-inf, or NaN when the
/// shifted origin lies exactly on the plane; max(x, acc) and min(x, acc) keep the accumulator
/// when x is NaN (the SSE MAXPS / MINPS rule, written out in the scalar path), so that axis then
/// decides nothing and the ray counts as inside the slab (as fmaxf / fminf on GPUs). An empty
/// slot's box (+inf, -inf) is missed by every ray: its entry is +inf.
#if FOVREF_BVH_SSE
struct BoxRay {
    __m128 origin_near[3], origin_far[3], inv_direction[3], t_lo;
    int near_plane[3], far_plane[3];  ///< offsets (floats) of an axis' near / far planes in bounds
};

/// make_slab_ray with the three axes in the lanes of one SSE register (the same operations per
/// axis), then broadcast per axis for the 4-wide test.
BoxRay make_box_ray(const Bvh& bvh, const Ray& ray) {
    const glm::vec3 lo = bvh.nodes[0].bounds_min, hi = bvh.nodes[0].bounds_max;
    const glm::vec3 o = ray.origin, d = ray.direction;
    const __m128 sign_bit = _mm_set1_ps(-0.0f);
    const __m128 origin = _mm_setr_ps(o.x, o.y, o.z, 0.0f);
    // max |scene coordinate| and max |origin coordinate| (lane 3 is 0, which changes no max).
    const __m128 scene_abs =
        _mm_max_ps(_mm_andnot_ps(sign_bit, _mm_setr_ps(lo.x, lo.y, lo.z, 0.0f)),
                   _mm_andnot_ps(sign_bit, _mm_setr_ps(hi.x, hi.y, hi.z, 0.0f)));
    const __m128 origin_abs = _mm_andnot_ps(sign_bit, origin);
    // Horizontal max of both at once: lanes (scene, origin) after the two steps.
    __m128 m =
        _mm_max_ps(_mm_movelh_ps(scene_abs, origin_abs), _mm_movehl_ps(origin_abs, scene_abs));
    m = _mm_max_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
    const float scene_max = _mm_cvtss_f32(m);
    const float origin_max = _mm_cvtss_f32(_mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 2, 2, 2)));
    const float pad = (scene_max + origin_max) * (1.0f / 524288.0f);
    const __m128 inv_direction = _mm_div_ps(_mm_set1_ps(1.0f), _mm_setr_ps(d.x, d.y, d.z, 1.0f));
    // shift = negative ? -pad : pad, with negative = the sign bit of 1 / d.
    const __m128 shift = _mm_xor_ps(_mm_set1_ps(pad), _mm_and_ps(inv_direction, sign_bit));
    const __m128 origin_near = _mm_add_ps(origin, shift);
    const __m128 origin_far = _mm_sub_ps(origin, shift);
    const int negative = _mm_movemask_ps(inv_direction);

    BoxRay b;
    b.origin_near[0] = _mm_shuffle_ps(origin_near, origin_near, _MM_SHUFFLE(0, 0, 0, 0));
    b.origin_near[1] = _mm_shuffle_ps(origin_near, origin_near, _MM_SHUFFLE(1, 1, 1, 1));
    b.origin_near[2] = _mm_shuffle_ps(origin_near, origin_near, _MM_SHUFFLE(2, 2, 2, 2));
    b.origin_far[0] = _mm_shuffle_ps(origin_far, origin_far, _MM_SHUFFLE(0, 0, 0, 0));
    b.origin_far[1] = _mm_shuffle_ps(origin_far, origin_far, _MM_SHUFFLE(1, 1, 1, 1));
    b.origin_far[2] = _mm_shuffle_ps(origin_far, origin_far, _MM_SHUFFLE(2, 2, 2, 2));
    b.inv_direction[0] = _mm_shuffle_ps(inv_direction, inv_direction, _MM_SHUFFLE(0, 0, 0, 0));
    b.inv_direction[1] = _mm_shuffle_ps(inv_direction, inv_direction, _MM_SHUFFLE(1, 1, 1, 1));
    b.inv_direction[2] = _mm_shuffle_ps(inv_direction, inv_direction, _MM_SHUFFLE(2, 2, 2, 2));
    for (int a = 0; a < 3; ++a) {
        const int near_side = (negative >> a) & 1;
        b.near_plane[a] = 8 * a + 4 * near_side;  // &bounds[a][near_side][0]
        b.far_plane[a] = 8 * a + 4 * (1 - near_side);
    }
    b.t_lo = _mm_set1_ps(widen_down(ray.t_min));
    return b;
}

/// One axis of the slab test on four boxes: entry = max(t_near, entry), exit = min(t_far, exit).
FOVREF_FORCE_INLINE void slab_axis(const float* bounds, const BoxRay& r, int a, __m128& entry,
                                   __m128& exit) {
    const __m128 near_plane = _mm_load_ps(bounds + r.near_plane[a]);
    const __m128 far_plane = _mm_load_ps(bounds + r.far_plane[a]);
    const __m128 t_near = _mm_mul_ps(_mm_sub_ps(near_plane, r.origin_near[a]), r.inv_direction[a]);
    const __m128 t_far = _mm_mul_ps(_mm_sub_ps(far_plane, r.origin_far[a]), r.inv_direction[a]);
    entry = _mm_max_ps(t_near, entry);  // (t_near > entry) ? t_near : entry
    exit = _mm_min_ps(t_far, exit);     // (t_far < exit) ? t_far : exit
}

FOVREF_FORCE_INLINE unsigned child_entries(const BvhWideNode& node, const BoxRay& r, float t_hi,
                                           float entries[4]) {
    const float* bounds = &node.bounds[0][0][0];
    __m128 entry = r.t_lo, exit = _mm_set1_ps(t_hi);
    slab_axis(bounds, r, 0, entry, exit);
    slab_axis(bounds, r, 1, entry, exit);
    slab_axis(bounds, r, 2, entry, exit);
    _mm_store_ps(entries, entry);
    return static_cast<unsigned>(_mm_movemask_ps(_mm_cmple_ps(entry, exit)));
}

/// The per-ray state of a query: box test and triangle test constants.
struct TraversalRay {
    BoxRay box;
    WatertightRay4 triangle;
    float t_max = 0.0f;  ///< the triangle test's t_max (clamped to the largest float)
};

TraversalRay make_traversal_ray(const Bvh& bvh, const Ray& ray) {
    const float t_max = std::min(ray.t_max, float_max);  // as make_triangle_ray
    return {make_box_ray(bvh, ray),
            make_watertight_ray4(ray.origin, ray.direction, ray.t_min, t_max), t_max};
}

/// The triangles of one block in `lanes`: intersect_watertight4 (watertight4.h).
FOVREF_FORCE_INLINE unsigned intersect_block(const TraversalRay& ray, const BvhTriangleBlock& block,
                                             unsigned lanes, Hits4& hits) {
    return intersect_watertight4(ray.triangle, &block.corners[0][0][0], lanes, hits);
}
#else
using BoxRay = SlabRay;

BoxRay make_box_ray(const Bvh& bvh, const Ray& ray) { return make_slab_ray(bvh, ray); }

FOVREF_FORCE_INLINE unsigned child_entries(const BvhWideNode& node, const BoxRay& r, float t_hi,
                                           float entries[4]) {
    unsigned mask = 0;
    for (int i = 0; i < 4; ++i) {
        float entry = r.t_lo, exit = t_hi;
        for (int a = 0; a < 3; ++a) {
            const float near_plane = node.bounds[a][r.near_side[a]][i];
            const float far_plane = node.bounds[a][1 - r.near_side[a]][i];
            const float t_near = (near_plane - r.origin_near[a]) * r.inv_direction[a];
            const float t_far = (far_plane - r.origin_far[a]) * r.inv_direction[a];
            entry = t_near > entry ? t_near : entry;
            exit = t_far < exit ? t_far : exit;
        }
        entries[i] = entry;
        if (entry <= exit) mask |= 1u << i;
    }
    return mask;
}

struct TraversalRay {
    BoxRay box;
    WatertightRay triangle;
    float t_max = 0.0f;
};

TraversalRay make_traversal_ray(const Bvh& bvh, const Ray& ray) {
    const WatertightRay triangle = make_triangle_ray(ray);
    return {make_box_ray(bvh, ray), triangle, triangle.t_max};
}

/// The plain path: intersect_watertight on each lane in `lanes`, corners read from the block.
FOVREF_FORCE_INLINE unsigned intersect_block(const TraversalRay& ray, const BvhTriangleBlock& block,
                                             unsigned lanes, Hits4& hits) {
    unsigned mask = 0;
    for (int i = 0; i < 4; ++i) {
        if (((lanes >> i) & 1u) == 0) continue;
        const auto& c = block.corners;
        const glm::vec3 a(c[0][0][i], c[0][1][i], c[0][2][i]);
        const glm::vec3 b(c[1][0][i], c[1][1][i], c[1][2][i]);
        const glm::vec3 p(c[2][0][i], c[2][1][i], c[2][2][i]);
        if (intersect_watertight(ray.triangle, a, b, p, hits.t[i], hits.u[i], hits.v[i]))
            mask |= 1u << i;
    }
    return mask;
}
#endif

/// The lanes of block `block` that belong to the leaf's triangles [first, end).
FOVREF_FORCE_INLINE unsigned leaf_lanes(std::uint32_t block, std::uint32_t first,
                                        std::uint32_t end) {
    const std::uint32_t base = 4 * block;
    unsigned lanes = 0xfu;
    if (first > base) lanes &= 0xfu << (first - base);
    if (end - base < 4) lanes &= (1u << (end - base)) - 1u;
    return lanes;
}

/// A child to visit: a wide node (count == 0) or a leaf's triangle range.
struct ChildRef {
    std::uint32_t first;
    std::uint32_t count;
};

struct StackEntry {
    ChildRef child;
    float entry;  ///< the box's entry distance when pushed: skipped if beyond the best hit
};

FOVREF_FORCE_INLINE ChildRef child(const BvhWideNode& node, int i) {
    return {node.first[i], node.count[i]};
}

/// Two children hit (slots i0 < i1): the nearer is returned, the other pushed; on equal entries
/// the lower slot is nearer (as in the general insertion sort).
FOVREF_FORCE_INLINE ChildRef nearer_of_two(const BvhWideNode& node, const float entries[4], int i0,
                                           int i1, StackEntry* stack, int& stack_size) {
    if (entries[i1] < entries[i0]) {
        stack[stack_size++] = {child(node, i0), entries[i0]};
        return child(node, i1);
    }
    stack[stack_size++] = {child(node, i1), entries[i1]};
    return child(node, i0);
}

/// One step of the ordered depth-first traversal of the BVH4: visits `current` and chooses the
/// next, from the boxes still to visit on `stack` (with their entry distances) and the cull
/// distance t_hi; returns false when the traversal is over. At a wide node the 4 children's boxes
/// are tested at once; the children hit are sorted by entry distance (the lower slot first on
/// ties), the nearest is visited next and the others are pushed, farthest first, with their
/// entry distances. One and two children hit (the common cases) take short paths that give the
/// same order as the general insertion sort, so the counters (nodes visited, triangles tested)
/// do not depend on which path ran. `visit_leaf(first, count)` tests a leaf's triangles and
/// returns the new cull distance t_hi (or a negative infinity to stop, used by any-hit queries).
/// The next node has been prefetched, so a caller that interleaves the steps of several rays
/// (trace_closest_interleaved) hides its load behind the other rays' steps. The state is passed
/// as separate references so that a single ray's loop (traverse) keeps it in registers.
template <class LeafVisitor>
FOVREF_FORCE_INLINE bool traverse_step(const BvhWideNode* nodes, const BvhTriangleBlock* blocks,
                                       const BoxRay& r, StackEntry* stack, int& stack_size,
                                       ChildRef& current, float& t_hi, LeafVisitor&& visit_leaf) {
    if (current.count > 0) {
        t_hi = visit_leaf(current.first, current.count);
        if (t_hi == -inf) return false;
    } else {
        const BvhWideNode& node = nodes[current.first];
        alignas(16) float entries[4];
        const unsigned mask = child_entries(node, r, t_hi, entries);
        // Prefetch the children hit: on incoherent rays, where the predictor misses the branch
        // below, a child's load then starts as soon as the mask is known, and a pushed child is
        // in cache when it is popped (measured: +10-20 % on incoherent rays, -4 % on coherent
        // ones, where the loads were already under way).
        for (unsigned m = mask; m != 0; m &= m - 1) {
            const int i = std::countr_zero(m);
            bvh_internal::prefetch_child(nodes, blocks, node.first[i], node.count[i]);
        }
        // The children hit, by mask. One or two children (the common cases) branch to code with
        // constant slots, so the next node's address waits for a predicted branch, not for the
        // box test (a coherent ray stream predicts well).
        switch (mask) {
            case 0x0: break;  // none: pop
            case 0x1: current = child(node, 0); return true;
            case 0x2: current = child(node, 1); return true;
            case 0x4: current = child(node, 2); return true;
            case 0x8: current = child(node, 3); return true;
            case 0x3: current = nearer_of_two(node, entries, 0, 1, stack, stack_size); return true;
            case 0x5: current = nearer_of_two(node, entries, 0, 2, stack, stack_size); return true;
            case 0x9: current = nearer_of_two(node, entries, 0, 3, stack, stack_size); return true;
            case 0x6: current = nearer_of_two(node, entries, 1, 2, stack, stack_size); return true;
            case 0xa: current = nearer_of_two(node, entries, 1, 3, stack, stack_size); return true;
            case 0xc: current = nearer_of_two(node, entries, 2, 3, stack, stack_size); return true;
            default: {
                // Three or four: take them in slot order, inserting each into place by entry
                // (strict '<': equal entries keep slot order).
                StackEntry hit[4];
                int hits = 0;
                for (unsigned m = mask; m != 0; m &= m - 1) {
                    const int i = std::countr_zero(m);
                    StackEntry e{child(node, i), entries[i]};
                    int j = hits++;
                    for (; j > 0 && e.entry < hit[j - 1].entry; --j) hit[j] = hit[j - 1];
                    hit[j] = e;
                }
                for (int j = hits - 1; j > 0; --j) stack[stack_size++] = hit[j];
                current = hit[0].child;
                return true;
            }
        }
    }
    // Pop the next box that may still hold a hit.
    while (stack_size > 0) {
        const StackEntry e = stack[--stack_size];
        if (e.entry <= t_hi) {
            current = e.child;
            return true;
        }
    }
    return false;
}

/// The whole traversal of one ray from the root with cull distance t_hi; the nodes and leaves
/// visited are added to `stats`.
template <class LeafVisitor>
FOVREF_FORCE_INLINE void traverse(const Bvh& bvh, const BoxRay& r, float t_hi, TraceStats& stats,
                                  LeafVisitor&& visit_leaf) {
    const BvhWideNode* nodes = bvh.wide_nodes.data();
    const BvhTriangleBlock* blocks = bvh.triangle_blocks.data();
    StackEntry stack[traversal_stack_size];
    int stack_size = 0;
    ChildRef current{0, 0};
    std::int64_t visited = 0;  // counted locally, added to `stats` once at the end
    do {
        ++visited;
    } while (traverse_step(nodes, blocks, r, stack, stack_size, current, t_hi, visit_leaf));
    stats.nodes_visited += visited;
}

/// The closest-hit order of SPEC §3: smaller t first, then the lower primitive index.
inline bool closer(float t, std::int32_t primitive, const Hit& best) {
    return best.primitive < 0 || t < best.t || (t == best.t && primitive < best.primitive);
}

/// A closest-hit query on a BVH with nodes: the ray's constants, the best hit so far, the
/// triangles tested, and the leaf visitor of traverse_step.
struct ClosestQuery {
    TraversalRay r;
    Hit best;
    float t_hi_none = 0.0f;   ///< the cull distance while nothing is hit
    std::int64_t tested = 0;  ///< triangles tested
    const BvhTriangleBlock* blocks = nullptr;
    const std::uint32_t* primitives = nullptr;

    /// Starts the query of a valid ray (ray_is_valid).
    void start(const Bvh& bvh, const Ray& ray) {
        r = make_traversal_ray(bvh, ray);
        best = Hit{};
        t_hi_none = widen_up(r.t_max);
        tested = 0;
        blocks = bvh.triangle_blocks.data();
        primitives = bvh.primitives.data();
    }

    /// A leaf's triangles, a block of 4 at a time; the hits reduced in the SPEC §3 order.
    /// Returns the new cull distance.
    FOVREF_FORCE_INLINE float operator()(std::uint32_t first, std::uint32_t count) {
        tested += count;
        const std::uint32_t end = first + count;
        for (std::uint32_t block = first / 4; 4 * block < end; ++block) {
            Hits4 hits;
            unsigned mask = intersect_block(r, blocks[block], leaf_lanes(block, first, end), hits);
            for (; mask != 0; mask &= mask - 1) {
                const int lane = std::countr_zero(mask);
                const auto primitive = static_cast<std::int32_t>(primitives[4 * block + lane]);
                if (closer(hits.t[lane], primitive, best))
                    best = Hit{hits.t[lane], primitive, hits.u[lane], hits.v[lane]};
            }
        }
        return best.hit() ? widen_up(best.t) : t_hi_none;
    }

    /// Adds the finished query's counts to `stats`.
    void finish(TraceStats& stats) const {
        stats.triangles_tested += tested;
        if (best.hit()) ++stats.hits;
    }
};

/// Rays whose traversals trace_closest_interleaved interleaves: enough that a node's load has
/// the other rays' steps to arrive in (16 was fastest on million's incoherent rays of
/// `fovref bench rays`, against 4, 8, 10 and 12; docs/bvh.md, "Interleaved queries").
constexpr int interleaved_lanes = 16;

}  // namespace

Hit trace_closest(const Bvh& bvh, const Ray& ray, TraceStats& stats) {
    ++stats.rays;
    if (bvh.nodes.empty() || !ray_is_valid(ray)) return Hit{};
    ClosestQuery query;
    query.start(bvh, ray);
    traverse(bvh, query.r.box, query.t_hi_none, stats, query);
    query.finish(stats);
    return query.best;
}

void trace_closest_interleaved(const Bvh& bvh, const Ray* rays, std::size_t count, Hit* hits,
                               TraceStats& stats) {
    if (bvh.nodes.empty()) {
        for (std::size_t i = 0; i < count; ++i) hits[i] = trace_closest(bvh, rays[i], stats);
        return;
    }
    // Each lane traces one ray at a time; the lanes take one traversal step each in turn.
    struct Lane {
        ClosestQuery query;
        StackEntry stack[traversal_stack_size];
        int stack_size = 0;
        ChildRef current{0, 0};
        float t_hi = 0.0f;
        std::int64_t visited = 0;
        std::size_t ray = 0;
        bool busy = false;
    };
    Lane lanes[interleaved_lanes];
    std::size_t next = 0;
    // Gives `lane` the next valid ray (an invalid one misses without a traversal, as in
    // trace_closest); false when no ray is left.
    const auto start = [&](Lane& lane) {
        for (; next < count; ++next) {
            ++stats.rays;
            if (!ray_is_valid(rays[next])) {
                hits[next] = Hit{};
                continue;
            }
            lane.ray = next++;
            lane.query.start(bvh, rays[lane.ray]);
            lane.stack_size = 0;
            lane.current = ChildRef{0, 0};  // the root
            lane.t_hi = lane.query.t_hi_none;
            lane.visited = 0;
            return true;
        }
        return false;
    };
    int busy = 0;
    for (Lane& lane : lanes) {
        lane.busy = start(lane);
        busy += lane.busy ? 1 : 0;
    }
    const BvhWideNode* nodes = bvh.wide_nodes.data();
    const BvhTriangleBlock* blocks = bvh.triangle_blocks.data();
    while (busy > 0) {
        for (Lane& lane : lanes) {
            if (!lane.busy) continue;
            ++lane.visited;
            if (traverse_step(nodes, blocks, lane.query.r.box, lane.stack, lane.stack_size,
                              lane.current, lane.t_hi, lane.query))
                continue;
            stats.nodes_visited += lane.visited;
            lane.query.finish(stats);
            hits[lane.ray] = lane.query.best;
            lane.busy = start(lane);
            busy -= lane.busy ? 0 : 1;
        }
    }
}

bool trace_any(const Bvh& bvh, const Ray& ray, TraceStats& stats) {
    ++stats.rays;
    if (bvh.nodes.empty() || !ray_is_valid(ray)) return false;
    const TraversalRay r = make_traversal_ray(bvh, ray);
    const BvhTriangleBlock* blocks = bvh.triangle_blocks.data();
    const float t_hi = widen_up(r.t_max);
    bool found = false;
    std::int64_t tested = 0;
    traverse(bvh, r.box, t_hi, stats, [&](std::uint32_t first, std::uint32_t count) {
        // Triangles are counted as if tested one by one in leaf order up to the first hit.
        const std::uint32_t end = first + count;
        for (std::uint32_t block = first / 4; 4 * block < end; ++block) {
            Hits4 hits;
            const unsigned mask =
                intersect_block(r, blocks[block], leaf_lanes(block, first, end), hits);
            if (mask != 0) {
                tested +=
                    4 * block + static_cast<std::uint32_t>(std::countr_zero(mask)) + 1 - first;
                found = true;
                return -inf;
            }
        }
        tested += count;
        return t_hi;
    });
    stats.triangles_tested += tested;
    if (found) ++stats.hits;
    return found;
}

Hit trace_brute_force(const std::vector<glm::vec3>& positions, const Ray& ray) {
    Hit best;
    if (!ray_is_valid(ray)) return best;
    const WatertightRay r = make_triangle_ray(ray);
    const std::size_t triangles = positions.size() / 3;
    for (std::size_t i = 0; i < triangles; ++i) {
        const glm::vec3 a = positions[3 * i], b = positions[3 * i + 1], c = positions[3 * i + 2];
        if (!triangle_is_hittable(a, b, c)) continue;
        float t, u, v;
        if (!intersect_watertight(r, a, b, c, t, u, v)) continue;
        const auto primitive = static_cast<std::int32_t>(i);
        if (closer(t, primitive, best)) best = Hit{t, primitive, u, v};
    }
    return best;
}

}  // namespace fovref
