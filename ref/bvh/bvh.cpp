// BVH2 build (binned SAH, deterministic) and traversal (ordered, robust slab test, watertight
// triangles). docs/bvh.md explains the constants and the choices.
#include "ref/bvh/bvh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "ref/bvh/watertight.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float float_max = std::numeric_limits<float>::max();

// ---- build ------------------------------------------------------------------------------------

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

struct Bin {
    Box box;
    std::uint32_t count = 0;
};

/// Bin of a centroid coordinate: floor((c - c_min) * scale), clamped to [0, bins - 1]. The same
/// function places primitives while binning and while partitioning, so both agree exactly.
inline int bin_index(float c, float c_min, float scale, int bins) {
    const int b = static_cast<int>((c - c_min) * scale);
    return std::clamp(b, 0, bins - 1);
}

struct BuildTask {
    std::uint32_t node;
    std::uint32_t begin, end;  // range in `refs`
    int depth;
};

class Builder {
public:
    Builder(const std::vector<glm::vec3>& positions, const BvhBuildSettings& settings)
        : settings_(settings) {
        const std::size_t triangles = positions.size() / 3;
        boxes_.resize(triangles);
        centroids_.resize(triangles);
        // Gather the hittable triangles in index order.
        for (std::size_t i = 0; i < triangles; ++i) {
            const glm::vec3 a = positions[3 * i], b = positions[3 * i + 1],
                            c = positions[3 * i + 2];
            if (!triangle_is_hittable(a, b, c)) {
                ++bvh_.stats.degenerate_triangles;
                continue;
            }
            Box box;
            box.grow(a);
            box.grow(b);
            box.grow(c);
            boxes_[i] = box;
            centroids_[i] = (box.lo + box.hi) * 0.5f;
            refs_.push_back(static_cast<std::uint32_t>(i));
        }
        scratch_.resize(refs_.size());
    }

    Bvh build(const std::vector<glm::vec3>& positions) {
        bvh_.stats.triangles = static_cast<std::int64_t>(refs_.size());
        if (refs_.empty()) return std::move(bvh_);
        bvh_.nodes.reserve(2 * refs_.size());
        bvh_.nodes.emplace_back();
        std::vector<BuildTask> tasks{{0, 0, static_cast<std::uint32_t>(refs_.size()), 0}};
        while (!tasks.empty()) {
            const BuildTask task = tasks.back();
            tasks.pop_back();
            build_node(task, tasks);
        }

        // Leaf-order triangle data.
        bvh_.primitives = refs_;
        bvh_.triangle_corners.reserve(3 * refs_.size());
        for (std::uint32_t t : refs_)
            for (int k = 0; k < 3; ++k) bvh_.triangle_corners.push_back(positions[3 * t + k]);

        // Statistics; the SAH cost is summed in binary64 in node order.
        const double root_area = node_box(bvh_.nodes[0]).half_area();
        double cost = 0.0;
        for (const BvhNode& n : bvh_.nodes) {
            const double area = node_box(n).half_area();
            if (n.count > 0) {
                ++bvh_.stats.leaves;
                cost += static_cast<double>(settings_.intersection_cost) * n.count * area;
            } else {
                cost += static_cast<double>(settings_.traversal_cost) * area;
            }
        }
        bvh_.stats.nodes = static_cast<std::int64_t>(bvh_.nodes.size());
        bvh_.stats.sah_cost = root_area > 0.0 ? cost / root_area : 0.0;
        return std::move(bvh_);
    }

private:
    static Box node_box(const BvhNode& n) {
        Box b;
        b.lo = n.bounds_min;
        b.hi = n.bounds_max;
        return b;
    }

    void make_leaf(const BuildTask& task) {
        BvhNode& node = bvh_.nodes[task.node];
        node.first = task.begin;
        node.count = task.end - task.begin;
    }

    void build_node(const BuildTask& task, std::vector<BuildTask>& tasks) {
        // Bounds of the triangles and of their centroids.
        Box bounds, centroid_bounds;
        for (std::uint32_t i = task.begin; i < task.end; ++i) {
            bounds.grow(boxes_[refs_[i]]);
            centroid_bounds.grow(centroids_[refs_[i]]);
        }
        BvhNode& node = bvh_.nodes[task.node];
        node.bounds_min = bounds.lo;
        node.bounds_max = bounds.hi;
        bvh_.stats.max_depth = std::max<std::int64_t>(bvh_.stats.max_depth, task.depth);

        const std::uint32_t count = task.end - task.begin;
        const bool may_be_leaf = count <= static_cast<std::uint32_t>(settings_.max_leaf_size);
        if (count == 1 || task.depth >= bvh_max_depth) return make_leaf(task);

        // Binned SAH: bin the centroids along each axis, then sweep the split planes. The first
        // best (axis x, y, z, then plane from low to high) wins: strict '<'.
        const int bins = settings_.bins;
        float best_cost = inf;
        int best_axis = -1, best_split = 0;
        float scales[3] = {0.0f, 0.0f, 0.0f};
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = centroid_bounds.hi[axis] - centroid_bounds.lo[axis];
            const float scale = static_cast<float>(bins) / extent;
            if (!(extent > 0.0f) || !std::isfinite(scale)) continue;
            scales[axis] = scale;
            Bin* axis_bins = bins_[axis];
            for (int b = 0; b < bins; ++b) axis_bins[b] = Bin{};
            const float c_min = centroid_bounds.lo[axis];
            for (std::uint32_t i = task.begin; i < task.end; ++i) {
                const std::uint32_t t = refs_[i];
                Bin& bin = axis_bins[bin_index(centroids_[t][axis], c_min, scale, bins)];
                bin.box.grow(boxes_[t]);
                ++bin.count;
            }
            // Right-to-left sweep: area-weighted counts of the right side of each plane.
            Box right;
            std::uint32_t right_count = 0;
            for (int b = bins - 1; b > 0; --b) {
                right.grow(axis_bins[b].box);
                right_count += axis_bins[b].count;
                right_cost_[b] = right.half_area() * static_cast<float>(right_count);
                right_counts_[b] = right_count;
            }
            // Left-to-right sweep: plane b separates bins [0, b) from [b, bins).
            Box left;
            std::uint32_t left_count = 0;
            for (int b = 1; b < bins; ++b) {
                left.grow(axis_bins[b - 1].box);
                left_count += axis_bins[b - 1].count;
                if (left_count == 0 || right_counts_[b] == 0) continue;
                const float cost =
                    left.half_area() * static_cast<float>(left_count) + right_cost_[b];
                if (cost < best_cost) {
                    best_cost = cost;
                    best_axis = axis;
                    best_split = b;
                }
            }
        }

        std::uint32_t mid = 0;
        if (best_axis < 0) {
            // All centroids coincide: SAH cannot separate them. Split the range in the middle
            // (it is in a deterministic order) unless it fits into a leaf.
            if (may_be_leaf) return make_leaf(task);
            mid = task.begin + count / 2;
        } else {
            const float area = bounds.half_area();
            const float split_cost =
                settings_.traversal_cost + settings_.intersection_cost * best_cost / area;
            const float leaf_cost = settings_.intersection_cost * static_cast<float>(count);
            if (may_be_leaf && !(split_cost < leaf_cost)) return make_leaf(task);
            mid = partition(task, best_axis, best_split, centroid_bounds.lo[best_axis],
                            scales[best_axis]);
        }

        // Children: a pair of adjacent nodes; the left subtree is built first (depth first).
        const auto children = static_cast<std::uint32_t>(bvh_.nodes.size());
        bvh_.nodes[task.node].first = children;
        bvh_.nodes[task.node].count = 0;
        bvh_.nodes.emplace_back();
        bvh_.nodes.emplace_back();
        tasks.push_back({children + 1, mid, task.end, task.depth + 1});
        tasks.push_back({children, task.begin, mid, task.depth + 1});
    }

    /// Stable partition of refs[begin, end) by bin < split: both sides keep their order, so the
    /// tree depends only on the input order (ties between equal centroids follow triangle index).
    std::uint32_t partition(const BuildTask& task, int axis, int split, float c_min, float scale) {
        std::uint32_t write = task.begin;
        std::size_t right = 0;
        for (std::uint32_t i = task.begin; i < task.end; ++i) {
            const std::uint32_t t = refs_[i];
            if (bin_index(centroids_[t][axis], c_min, scale, settings_.bins) < split)
                refs_[write++] = t;
            else
                scratch_[right++] = t;
        }
        std::copy(scratch_.begin(), scratch_.begin() + static_cast<std::ptrdiff_t>(right),
                  refs_.begin() + write);
        return write;
    }

    static constexpr int max_bins = 256;
    BvhBuildSettings settings_;
    Bvh bvh_;
    std::vector<Box> boxes_;            // per input triangle
    std::vector<glm::vec3> centroids_;  // per input triangle: centre of its box
    std::vector<std::uint32_t> refs_;   // hittable triangles; becomes leaf order
    std::vector<std::uint32_t> scratch_;
    Bin bins_x_[max_bins], bins_y_[max_bins], bins_z_[max_bins];
    Bin* bins_[3] = {bins_x_, bins_y_, bins_z_};
    float right_cost_[max_bins] = {};
    std::uint32_t right_counts_[max_bins] = {};
};

// ---- traversal --------------------------------------------------------------------------------

/// Relative margin on the ray interval used to cull boxes (never to accept hits). The triangle
/// test's t is rounded and, for grazing triangles, can lie slightly outside the box interval
/// that contains the exact hit; boxes are culled only when their entry lies beyond
/// t_best * (1 + margin), so such a triangle is still tested and the result stays independent
/// of the traversal order (docs/bvh.md).
constexpr float cull_margin = 1.0f / 4096.0f;

/// Per-ray constants of the slab test. The box is padded by `pad` in every direction (see
/// make_traversal_ray); a padded plane is reached from the shifted origins, so the test costs
/// no more than an unpadded one.
struct TraversalRay {
    WatertightRay triangle;
    glm::vec3 inv_direction{0.0f};
    glm::vec3 origin_near{0.0f};  ///< origin + pad * sign(direction): reaches the near planes
    glm::vec3 origin_far{0.0f};   ///< origin - pad * sign(direction): reaches the far planes
    bool negative[3] = {false, false, false};
    float t_lo = 0.0f;  ///< t_min, widened by the margin (boxes only)
};

bool ray_is_valid(const Ray& ray) {
    const glm::vec3 o = ray.origin, d = ray.direction;
    const bool finite = std::isfinite(o.x) && std::isfinite(o.y) && std::isfinite(o.z) &&
                        std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
    return finite && (d.x != 0.0f || d.y != 0.0f || d.z != 0.0f) && !std::isnan(ray.t_min) &&
           !std::isnan(ray.t_max);
}

/// The watertight setup; t_max is clamped to the largest float so that t is always finite.
WatertightRay make_triangle_ray(const Ray& ray) {
    return make_watertight_ray(ray.origin, ray.direction, ray.t_min,
                               std::min(ray.t_max, float_max));
}

float widen_up(float t) { return std::min(t + std::fabs(t) * cull_margin, float_max); }
float widen_down(float t) { return std::max(t - std::fabs(t) * cull_margin, -float_max); }

/// Robust slab test setup. The watertight test decides a hit exactly for its rounded, sheared
/// corners, which lie within 6 eps |corner - origin| (eps = 2^-24) of the true corners along the
/// two sheared axes; the slab distances themselves carry up to 3 eps relative rounding (the
/// concern of Ize 2013, "Robust BVH Ray Traversal"). Padding every box by
/// pad = 2^-19 (max |scene coordinate| + max |origin coordinate|), i.e. 32 eps times a bound on
/// |corner - origin|, covers both with room to spare, so a box is never culled when the triangle
/// test would report a hit inside it (the argument of Woop et al. 2013 for a conservative box
/// test).
TraversalRay make_traversal_ray(const Bvh& bvh, const Ray& ray) {
    TraversalRay r;
    r.triangle = make_triangle_ray(ray);
    const BvhNode& root = bvh.nodes[0];
    const glm::vec3 scene_abs = glm::max(glm::abs(root.bounds_min), glm::abs(root.bounds_max));
    const glm::vec3 origin_abs = glm::abs(ray.origin);
    const float scene_max = std::max(std::max(scene_abs.x, scene_abs.y), scene_abs.z);
    const float origin_max = std::max(std::max(origin_abs.x, origin_abs.y), origin_abs.z);
    const float pad = (scene_max + origin_max) * (1.0f / 524288.0f);
    for (int a = 0; a < 3; ++a) {
        r.inv_direction[a] = 1.0f / ray.direction[a];  // +-inf for a zero component
        r.negative[a] = std::signbit(r.inv_direction[a]);
        const float shift = r.negative[a] ? -pad : pad;
        r.origin_near[a] = ray.origin[a] + shift;
        r.origin_far[a] = ray.origin[a] - shift;
    }
    r.t_lo = widen_down(ray.t_min);
    return r;
}

/// Entry distance of the ray into the padded box within [t_lo, t_hi], or +inf when it misses.
/// A zero direction component gives (plane - shifted origin) * inf = +-inf, or NaN when the
/// shifted origin lies exactly on the plane; std::max(acc, x) and std::min(acc, x) keep the
/// accumulator when x is NaN, so that axis then decides nothing and the ray counts as inside the
/// slab (IEEE comparisons, as fmaxf / fminf on GPUs).
FOVREF_FORCE_INLINE float box_entry(const BvhNode& node, const TraversalRay& r, float t_hi) {
    const glm::vec3 near_plane{r.negative[0] ? node.bounds_max.x : node.bounds_min.x,
                               r.negative[1] ? node.bounds_max.y : node.bounds_min.y,
                               r.negative[2] ? node.bounds_max.z : node.bounds_min.z};
    const glm::vec3 far_plane{r.negative[0] ? node.bounds_min.x : node.bounds_max.x,
                              r.negative[1] ? node.bounds_min.y : node.bounds_max.y,
                              r.negative[2] ? node.bounds_min.z : node.bounds_max.z};
    const glm::vec3 t_near = (near_plane - r.origin_near) * r.inv_direction;
    const glm::vec3 t_far = (far_plane - r.origin_far) * r.inv_direction;
    float entry = r.t_lo, exit = t_hi;
    entry = std::max(entry, t_near.x);
    entry = std::max(entry, t_near.y);
    entry = std::max(entry, t_near.z);
    exit = std::min(exit, t_far.x);
    exit = std::min(exit, t_far.y);
    exit = std::min(exit, t_far.z);
    return entry <= exit ? entry : inf;
}

struct StackEntry {
    std::uint32_t node;
    float entry;  ///< the box's entry distance when pushed: skipped if beyond the best hit
};

/// Ordered depth-first traversal. At an inner node both children's boxes are tested; the nearer
/// is visited next (the left one on equal entry distances) and the farther is pushed with its
/// entry distance. `visit_leaf(node)` tests the leaf's triangles and returns the new cull
/// distance t_hi (or a negative infinity to stop, used by any-hit queries).
template <class LeafVisitor>
void traverse(const Bvh& bvh, const TraversalRay& r, float t_hi, TraceStats& stats,
              LeafVisitor&& visit_leaf) {
    const BvhNode* nodes = bvh.nodes.data();
    if (box_entry(nodes[0], r, t_hi) == inf) return;
    StackEntry stack[bvh_max_depth + 2];
    int stack_size = 0;
    std::uint32_t current = 0;
    while (true) {
        ++stats.nodes_visited;
        const BvhNode& node = nodes[current];
        if (node.count > 0) {
            t_hi = visit_leaf(node);
            if (t_hi == -inf) return;
        } else {
            const float entry_left = box_entry(nodes[node.first], r, t_hi);
            const float entry_right = box_entry(nodes[node.first + 1], r, t_hi);
            if (entry_left != inf && entry_right != inf) {
                const bool left_first = entry_left <= entry_right;
                current = left_first ? node.first : node.first + 1;
                stack[stack_size++] = {left_first ? node.first + 1 : node.first,
                                       left_first ? entry_right : entry_left};
                continue;
            }
            if (entry_left != inf) {
                current = node.first;
                continue;
            }
            if (entry_right != inf) {
                current = node.first + 1;
                continue;
            }
        }
        // Pop the next box that may still hold a hit.
        bool found = false;
        while (stack_size > 0) {
            const StackEntry e = stack[--stack_size];
            if (e.entry <= t_hi) {
                current = e.node;
                found = true;
                break;
            }
        }
        if (!found) return;
    }
}

/// The closest-hit order of SPEC §3: smaller t first, then the lower primitive index.
inline bool closer(float t, std::int32_t primitive, const Hit& best) {
    return best.primitive < 0 || t < best.t || (t == best.t && primitive < best.primitive);
}

}  // namespace

Bvh build_bvh(const std::vector<glm::vec3>& positions, const BvhBuildSettings& settings) {
    if (positions.size() % 3 != 0)
        throw Error("build_bvh: " + std::to_string(positions.size()) +
                    " positions is not a multiple of 3 (3 corners per triangle)");
    if (positions.size() / 3 > std::numeric_limits<std::int32_t>::max())
        throw Error("build_bvh: too many triangles for 32-bit primitive ids");
    if (settings.bins < 2 || settings.bins > 256)
        throw Error("build_bvh: bins must be in 2..256, got " + std::to_string(settings.bins));
    if (settings.max_leaf_size < 1 || settings.max_leaf_size > 64)
        throw Error("build_bvh: max_leaf_size must be in 1..64, got " +
                    std::to_string(settings.max_leaf_size));
    if (!(settings.traversal_cost >= 0.0f && settings.intersection_cost > 0.0f) ||
        !std::isfinite(settings.traversal_cost) || !std::isfinite(settings.intersection_cost))
        throw Error("build_bvh: SAH costs must be finite, traversal >= 0, intersection > 0");
    Builder builder(positions, settings);
    return builder.build(positions);
}

Hit trace_closest(const Bvh& bvh, const Ray& ray, TraceStats& stats) {
    ++stats.rays;
    Hit best;
    if (bvh.nodes.empty() || !ray_is_valid(ray)) return best;
    const TraversalRay r = make_traversal_ray(bvh, ray);
    const glm::vec3* corners = bvh.triangle_corners.data();
    const std::uint32_t* primitives = bvh.primitives.data();
    traverse(bvh, r, widen_up(r.triangle.t_max), stats, [&](const BvhNode& leaf) {
        stats.triangles_tested += leaf.count;
        for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
            float t, u, v;
            if (!intersect_watertight(r.triangle, corners[3 * i], corners[3 * i + 1],
                                      corners[3 * i + 2], t, u, v))
                continue;
            const auto primitive = static_cast<std::int32_t>(primitives[i]);
            if (closer(t, primitive, best)) best = Hit{t, primitive, u, v};
        }
        return best.hit() ? widen_up(best.t) : widen_up(r.triangle.t_max);
    });
    if (best.hit()) ++stats.hits;
    return best;
}

bool trace_any(const Bvh& bvh, const Ray& ray, TraceStats& stats) {
    ++stats.rays;
    if (bvh.nodes.empty() || !ray_is_valid(ray)) return false;
    const TraversalRay r = make_traversal_ray(bvh, ray);
    const glm::vec3* corners = bvh.triangle_corners.data();
    const float t_hi = widen_up(r.triangle.t_max);
    bool found = false;
    traverse(bvh, r, t_hi, stats, [&](const BvhNode& leaf) {
        for (std::uint32_t i = leaf.first; i < leaf.first + leaf.count; ++i) {
            ++stats.triangles_tested;
            float t, u, v;
            if (intersect_watertight(r.triangle, corners[3 * i], corners[3 * i + 1],
                                     corners[3 * i + 2], t, u, v)) {
                found = true;
                return -inf;
            }
        }
        return t_hi;
    });
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
