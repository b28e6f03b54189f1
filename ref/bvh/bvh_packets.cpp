// Shadow-ray packets (trace_any_packets, bvh.h; docs/bvh.md "Shadow-ray packets"): eight
// occlusion queries in the lanes of AVX registers, walking the BVH4 together.
//
//   for each run of consecutive valid rays with one shape (octant and watertight axes), up to 8:
//     the lanes' constants: make_box_ray's and make_watertight_ray4's values, lane by lane
//     the walk from the root, with the lanes that reached each node:
//       wide node: each child's box tested in every lane (child_entries' operations), the
//         children some lane hits visited nearest first for the lowest lane, the others pushed
//       leaf: its triangles in leaf order, each tested in the lanes still without a hit
//         (intersect_watertight4's operations, one triangle against eight rays); a lane that
//         hits leaves the packet
//     a lane's answer: whether it hit a triangle
//
// Every lane performs the one-ray query's operations for its ray (the box tests' slab
// distances, the widened interval, the watertight test with its binary64 recomputation of a zero
// edge function): a lane reaches exactly the leaves trace_any's ray may reach and accepts exactly
// the triangles trace_any accepts, so its answer is trace_any's. Only the order in which the
// packet visits nodes differs, which decides the work, never an answer.
#include "ref/bvh/bvh.h"

#include <bit>
#include <cmath>
#include <utility>

#include "ref/bvh/bvh_internal.h"
#include "ref/bvh/watertight.h"
#include "ref/core/simd.h"

#if defined(__x86_64__) || defined(_M_X64)
#define FOVREF_BVH_PACKETS 1
#include "ref/core/avx_lanes.h"
#endif

namespace fovref {

#if FOVREF_BVH_PACKETS
namespace {

using bvh_internal::float_max;
using bvh_internal::inf;
using bvh_internal::ray_is_valid;
using bvh_internal::scene_abs_max;
using bvh_internal::traversal_stack_size;

constexpr int packet_lanes = 8;

/// What the rays of a packet share: per axis whether the direction is negative (so the box's
/// max is the near plane: make_box_ray's choice, by the sign of 1 / d, which is d's sign), and
/// make_watertight_ray's axes (kz of the largest |d|, ties to the lower axis; kx, ky the next
/// two, swapped when d[kz] < 0). Packed into an int: bits 0-2 the signs, 3-4 kz, 5 the swap.
int ray_shape(const Ray& ray) {
    const float d[3] = {ray.direction.x, ray.direction.y, ray.direction.z};
    int kz = std::fabs(d[1]) > std::fabs(d[0]) ? 1 : 0;
    kz = std::fabs(d[2]) > std::fabs(d[kz]) ? 2 : kz;
    return (std::signbit(d[0]) ? 1 : 0) | (std::signbit(d[1]) ? 2 : 0) |
           (std::signbit(d[2]) ? 4 : 0) | (kz << 3) | (d[kz] < 0.0f ? 32 : 0);
}

/// A packet's constants, lane k from ray k.
struct Packet {
    // The box test (make_box_ray): shifted origins, 1 / d, the widened interval.
    __m256 origin_near[3], origin_far[3], inv_direction[3];
    __m256 t_lo, t_hi;
    int near_plane[3], far_plane[3];  ///< offsets of an axis' planes in BvhWideNode::bounds
    // The watertight test (make_watertight_ray4): origin and shear on the permuted axes.
    __m256 origin_kx, origin_ky, origin_kz, shear_x, shear_y, shear_z, t_min, t_max;
    int kx = 0, ky = 1, kz = 2;
};

static_assert(sizeof(Ray) == 8 * sizeof(float), "a Ray is its 8 floats, loaded as one register");

/// The constants of rays[index[0 .. n)] (n >= 1, one shape; lanes past n repeat lane 0 and are
/// never active). `scene_max`: max |coordinate| of the root's box, as make_box_ray takes it.
__attribute__((target("avx"))) void make_packet(const Ray* rays, const std::size_t* index, int n,
                                                int shape, float scene_max, Packet& p) {
    // The eight rays' 8 floats each (origin, direction, t_min, t_max), transposed into one
    // register per field: value moves only.
    __m256 f[8];
    for (int k = 0; k < packet_lanes; ++k)
        f[k] = _mm256_loadu_ps(reinterpret_cast<const float*>(&rays[index[k < n ? k : 0]]));
    avx::transpose8_lanes(f);
    const __m256 t_min = f[6];
    // t_max' = std::min(t_max, float_max) (as make_traversal_ray); t_lo = widen_down(t_min) =
    // std::max(t - |t| margin, -float_max); t_hi = widen_up(t_max') = std::min(t + |t| margin,
    // float_max): std::min(a, b) is _mm256_min_ps(b, a) and std::max(a, b) _mm256_max_ps(b, a),
    // ties and NaN included.
    const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));
    const __m256 margin = _mm256_set1_ps(bvh_internal::cull_margin);
    const __m256 t_max = _mm256_min_ps(_mm256_set1_ps(float_max), f[7]);
    p.t_lo =
        _mm256_max_ps(_mm256_set1_ps(-float_max),
                      _mm256_sub_ps(t_min, _mm256_mul_ps(_mm256_and_ps(t_min, abs_mask), margin)));
    p.t_hi =
        _mm256_min_ps(_mm256_set1_ps(float_max),
                      _mm256_add_ps(t_max, _mm256_mul_ps(_mm256_and_ps(t_max, abs_mask), margin)));
    p.t_min = t_min;
    p.t_max = t_max;
    const __m256 sign_bit = _mm256_set1_ps(-0.0f);
    __m256 origin[3], direction[3], origin_max = _mm256_setzero_ps();
    for (int a = 0; a < 3; ++a) {
        origin[a] = f[a];
        direction[a] = f[3 + a];
        // max of |o.x|, |o.y|, |o.z| (and 0): non-negative and never NaN, so any order gives
        // make_box_ray's horizontal max.
        origin_max = _mm256_max_ps(origin_max, _mm256_andnot_ps(sign_bit, origin[a]));
    }
    const __m256 pad = _mm256_mul_ps(_mm256_add_ps(_mm256_set1_ps(scene_max), origin_max),
                                     _mm256_set1_ps(1.0f / 524288.0f));
    for (int a = 0; a < 3; ++a) {
        const int negative = (shape >> a) & 1;
        p.inv_direction[a] = _mm256_div_ps(_mm256_set1_ps(1.0f), direction[a]);
        const __m256 shift = negative ? _mm256_xor_ps(pad, sign_bit) : pad;  // -pad or pad
        p.origin_near[a] = _mm256_add_ps(origin[a], shift);
        p.origin_far[a] = _mm256_sub_ps(origin[a], shift);
        p.near_plane[a] = 8 * a + 4 * negative;
        p.far_plane[a] = 8 * a + 4 * (1 - negative);
    }
    const int next[3] = {1, 2, 0};
    p.kz = (shape >> 3) & 3;
    p.kx = next[p.kz];
    p.ky = next[p.kx];
    if ((shape & 32) != 0) std::swap(p.kx, p.ky);
    // (d[kx], d[ky], 1) / d[kz], each lane's division as make_watertight_ray4_axes's
    p.shear_x = _mm256_div_ps(direction[p.kx], direction[p.kz]);
    p.shear_y = _mm256_div_ps(direction[p.ky], direction[p.kz]);
    p.shear_z = _mm256_div_ps(_mm256_set1_ps(1.0f), direction[p.kz]);
    p.origin_kx = origin[p.kx];
    p.origin_ky = origin[p.ky];
    p.origin_kz = origin[p.kz];
}

/// child_entries for child `i`, lane by lane: the slab_axis operations in their order
/// (entry = max(t_near, entry), exit = min(t_far, exit); x, y, z). Returns the lanes whose box
/// is hit (entry <= exit) and their entries.
FOVREF_AVX_INLINE unsigned packet_box(const BvhWideNode& node, int i, const Packet& p,
                                      __m256& entry) {
    const float* bounds = &node.bounds[0][0][0] + i;
    entry = p.t_lo;
    __m256 exit = p.t_hi;
    for (int a = 0; a < 3; ++a) {
        const __m256 near_plane = _mm256_broadcast_ss(bounds + p.near_plane[a]);
        const __m256 far_plane = _mm256_broadcast_ss(bounds + p.far_plane[a]);
        const __m256 t_near =
            _mm256_mul_ps(_mm256_sub_ps(near_plane, p.origin_near[a]), p.inv_direction[a]);
        const __m256 t_far =
            _mm256_mul_ps(_mm256_sub_ps(far_plane, p.origin_far[a]), p.inv_direction[a]);
        entry = _mm256_max_ps(t_near, entry);
        exit = _mm256_min_ps(t_far, exit);
    }
    return static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(entry, exit, _CMP_LE_OQ)));
}

/// The lanes of `zeros` with U, V or W exactly 0: all three recomputed in binary64, lane by
/// lane (watertight4_edge_fallback's rule).
__attribute__((target("avx"))) void packet_edge_fallback(__m256 Ax, __m256 Ay, __m256 Bx, __m256 By,
                                                         __m256 Cx, __m256 Cy, unsigned zeros,
                                                         __m256& U, __m256& V, __m256& W) {
    alignas(32) float ax[8], ay[8], bx[8], by[8], cx[8], cy[8], u[8], v[8], w[8];
    _mm256_store_ps(ax, Ax);
    _mm256_store_ps(ay, Ay);
    _mm256_store_ps(bx, Bx);
    _mm256_store_ps(by, By);
    _mm256_store_ps(cx, Cx);
    _mm256_store_ps(cy, Cy);
    _mm256_store_ps(u, U);
    _mm256_store_ps(v, V);
    _mm256_store_ps(w, W);
    watertight_edge_fallback_lanes(packet_lanes, zeros, ax, ay, bx, by, cx, cy, u, v, w);
    U = _mm256_load_ps(u);
    V = _mm256_load_ps(v);
    W = _mm256_load_ps(w);
}

/// intersect_watertight4's operations for one triangle (lane `t` of `block`) against the rays
/// of `lanes`: returns the lanes hit with t in (t_min, t_max].
FOVREF_AVX_INLINE unsigned packet_triangle(const Packet& p, const BvhTriangleBlock& block, int t,
                                           unsigned lanes) {
    const auto& c = block.corners;
    // Corners relative to the ray origin, on the permuted axes.
    const __m256 A_kx = _mm256_sub_ps(_mm256_set1_ps(c[0][p.kx][t]), p.origin_kx);
    const __m256 A_ky = _mm256_sub_ps(_mm256_set1_ps(c[0][p.ky][t]), p.origin_ky);
    const __m256 A_kz = _mm256_sub_ps(_mm256_set1_ps(c[0][p.kz][t]), p.origin_kz);
    const __m256 B_kx = _mm256_sub_ps(_mm256_set1_ps(c[1][p.kx][t]), p.origin_kx);
    const __m256 B_ky = _mm256_sub_ps(_mm256_set1_ps(c[1][p.ky][t]), p.origin_ky);
    const __m256 B_kz = _mm256_sub_ps(_mm256_set1_ps(c[1][p.kz][t]), p.origin_kz);
    const __m256 C_kx = _mm256_sub_ps(_mm256_set1_ps(c[2][p.kx][t]), p.origin_kx);
    const __m256 C_ky = _mm256_sub_ps(_mm256_set1_ps(c[2][p.ky][t]), p.origin_ky);
    const __m256 C_kz = _mm256_sub_ps(_mm256_set1_ps(c[2][p.kz][t]), p.origin_kz);
    // Shear and scale (x and y).
    const __m256 Ax = _mm256_sub_ps(A_kx, _mm256_mul_ps(p.shear_x, A_kz));
    const __m256 Ay = _mm256_sub_ps(A_ky, _mm256_mul_ps(p.shear_y, A_kz));
    const __m256 Bx = _mm256_sub_ps(B_kx, _mm256_mul_ps(p.shear_x, B_kz));
    const __m256 By = _mm256_sub_ps(B_ky, _mm256_mul_ps(p.shear_y, B_kz));
    const __m256 Cx = _mm256_sub_ps(C_kx, _mm256_mul_ps(p.shear_x, C_kz));
    const __m256 Cy = _mm256_sub_ps(C_ky, _mm256_mul_ps(p.shear_y, C_kz));
    // Scaled barycentrics; a lane with one of them exactly 0 recomputes all three.
    __m256 U = _mm256_sub_ps(_mm256_mul_ps(Cx, By), _mm256_mul_ps(Cy, Bx));
    __m256 V = _mm256_sub_ps(_mm256_mul_ps(Ax, Cy), _mm256_mul_ps(Ay, Cx));
    __m256 W = _mm256_sub_ps(_mm256_mul_ps(Bx, Ay), _mm256_mul_ps(By, Ax));
    const __m256 zero = _mm256_setzero_ps();
    const unsigned zeros = static_cast<unsigned>(_mm256_movemask_ps(
        avx::either(avx::either(avx::equal(U, zero), avx::equal(V, zero)), avx::equal(W, zero))));
    if ((zeros & lanes) != 0) packet_edge_fallback(Ax, Ay, Bx, By, Cx, Cy, zeros, U, V, W);
    // Edge tests (some negative and some positive: outside), and det != 0 (true for NaN).
    const __m256 negative =
        avx::either(avx::either(avx::less(U, zero), avx::less(V, zero)), avx::less(W, zero));
    const __m256 positive = avx::either(avx::either(avx::greater(U, zero), avx::greater(V, zero)),
                                        avx::greater(W, zero));
    const __m256 det = _mm256_add_ps(_mm256_add_ps(U, V), W);
    const __m256 inside =
        _mm256_andnot_ps(avx::both(negative, positive), avx::not_equal(det, zero));
    // Scaled distance with det's sign moved into it, against the scaled interval.
    const __m256 Az = _mm256_mul_ps(p.shear_z, A_kz);
    const __m256 Bz = _mm256_mul_ps(p.shear_z, B_kz);
    const __m256 Cz = _mm256_mul_ps(p.shear_z, C_kz);
    const __m256 T = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(U, Az), _mm256_mul_ps(V, Bz)),
                                   _mm256_mul_ps(W, Cz));
    const __m256 sign_bit = _mm256_set1_ps(-0.0f);
    const __m256 T_signed = _mm256_xor_ps(T, avx::both(avx::less(det, zero), sign_bit));
    const __m256 det_abs = _mm256_andnot_ps(sign_bit, det);
    const __m256 in_range = avx::both(avx::greater(T_signed, _mm256_mul_ps(p.t_min, det_abs)),
                                      avx::at_most(T_signed, _mm256_mul_ps(p.t_max, det_abs)));
    unsigned mask = static_cast<unsigned>(_mm256_movemask_ps(avx::both(inside, in_range))) & lanes;
    if (mask == 0) return 0;
    // The exact test of t = T (1 / det) against (t_min, t_max].
    const __m256 t_hit = _mm256_mul_ps(T, _mm256_div_ps(_mm256_set1_ps(1.0f), det));
    return mask & static_cast<unsigned>(_mm256_movemask_ps(
                      avx::both(avx::greater(t_hit, p.t_min), avx::at_most(t_hit, p.t_max))));
}

/// A child still to visit and the lanes whose boxes led to it.
/// (No member initialisers: the walk's stack of them is not zero-filled on every packet.)
struct PacketEntry {
    std::uint32_t first, count;  ///< as BvhWideNode's first[i], count[i]
    unsigned lanes;
};

/// The children of a wide node that `lanes` hit, nearest first for the lowest of `lanes` (the
/// children it misses after those it hits; ties in slot order): the nearest becomes `current`,
/// the others are pushed farthest first. False when no lane hits a child.
FOVREF_AVX_INLINE bool packet_children(const BvhWideNode* nodes, const BvhTriangleBlock* blocks,
                                       const BvhWideNode& node, const Packet& p, unsigned lanes,
                                       PacketEntry* stack, int& stack_size, PacketEntry& current) {
    PacketEntry hit[4];
    float keys[4];
    const int lead = std::countr_zero(lanes);
    int hits = 0;
    for (int i = 0; i < 4; ++i) {
        __m256 entry;
        const unsigned mask = packet_box(node, i, p, entry) & lanes;
        if (mask == 0) continue;
        // its first cache lines asked for now: a pushed child is then in cache when popped
        bvh_internal::prefetch_child(nodes, blocks, node.first[i], node.count[i]);
        alignas(32) float entries[packet_lanes];
        _mm256_store_ps(entries, entry);
        const float key = ((mask >> lead) & 1u) != 0 ? entries[lead] : inf;
        int j = hits++;
        for (; j > 0 && key < keys[j - 1]; --j) {
            hit[j] = hit[j - 1];
            keys[j] = keys[j - 1];
        }
        hit[j] = {node.first[i], node.count[i], mask};
        keys[j] = key;
    }
    if (hits == 0) return false;
    for (int j = hits - 1; j > 0; --j) stack[stack_size++] = hit[j];
    current = hit[0];
    return true;
}

/// The walk of one packet of n rays from the root: the lanes without a hit at the end
/// (bit k: ray k), and the work into `stats`.
__attribute__((target("avx"))) unsigned walk_packet(const Bvh& bvh, const Packet& p, int n,
                                                    TraceStats& stats) {
    const BvhWideNode* nodes = bvh.wide_nodes.data();
    const BvhTriangleBlock* blocks = bvh.triangle_blocks.data();
    unsigned active = (1u << n) - 1u;
    PacketEntry stack[traversal_stack_size];
    int stack_size = 0;
    PacketEntry current{0, 0, active};  // the root
    std::int64_t visited = 0, tested = 0;
    for (;;) {
        visited += std::popcount(current.lanes);
        bool next = false;
        if (current.count > 0) {
            // The leaf's triangles in leaf order, each in the lanes still without a hit.
            unsigned lanes = current.lanes;
            const std::uint32_t end = current.first + current.count;
            for (std::uint32_t j = current.first; j < end && lanes != 0; ++j) {
                tested += std::popcount(lanes);
                const unsigned hit =
                    packet_triangle(p, blocks[j / 4], static_cast<int>(j % 4), lanes);
                lanes &= ~hit;
                active &= ~hit;
            }
        } else {
            next = packet_children(nodes, blocks, nodes[current.first], p, current.lanes, stack,
                                   stack_size, current);
        }
        // Pop the next child that some lane still without a hit reached.
        while (!next && stack_size > 0 && active != 0) {
            current = stack[--stack_size];
            current.lanes &= active;
            next = current.lanes != 0;
        }
        if (!next) break;
    }
    stats.nodes_visited += visited;
    stats.triangles_tested += tested;
    return active;
}

}  // namespace
#endif

void trace_any_packets(const Bvh& bvh, const Ray* rays, std::size_t count, std::uint8_t* occluded,
                       TraceStats& stats) {
#if FOVREF_BVH_PACKETS
    if (!bvh.nodes.empty() && simd_allowed() && cpu_has_avx()) {
        const float scene_max = scene_abs_max(bvh);
        std::size_t index[packet_lanes];
        int n = 0, shape = 0;
        Packet p;
        const auto flush = [&] {
            make_packet(rays, index, n, shape, scene_max, p);
            const unsigned missed = walk_packet(bvh, p, n, stats);
            for (int k = 0; k < n; ++k) {
                const bool hit = ((missed >> k) & 1u) == 0;
                occluded[index[k]] = hit ? 1 : 0;
                stats.hits += hit ? 1 : 0;
            }
            n = 0;
        };
        for (std::size_t i = 0; i < count; ++i) {
            ++stats.rays;
            occluded[i] = 0;
            if (!ray_is_valid(rays[i])) continue;  // misses, as in trace_any
            const int s = ray_shape(rays[i]);
            if (n > 0 && s != shape) flush();
            shape = s;
            index[n++] = i;
            if (n == packet_lanes) flush();
        }
        if (n > 0) flush();
        return;
    }
#endif
    for (std::size_t i = 0; i < count; ++i) occluded[i] = trace_any(bvh, rays[i], stats) ? 1 : 0;
}

}  // namespace fovref
