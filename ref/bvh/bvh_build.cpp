// BVH2 build over triangles (SPEC §3): binned SAH, deterministic. build_bvh then lays the tree out
// for traversal (bvh_collapse.cpp: the BVH4 and the triangle blocks). docs/bvh.md, "Build: binned
// SAH, deterministic", explains the constants, the layout and the choices. Order: nodes are built
// depth first, left child first, an inner node's two children stored as an adjacent pair; the best
// split is the first of lowest cost (axes x, y, z, planes from low to high, strict '<'); the
// partition is stable, so the order inside every node (and so the tie between equal centroids)
// follows the triangle index; the SAH cost statistic is summed in binary64 in node order.
#include "ref/bvh/bvh.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "ref/bvh/bvh_internal.h"
#include "ref/bvh/watertight.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

using bvh_internal::Box;
using bvh_internal::inf;
using bvh_internal::node_box;

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

/// The outcome of the split search of one node: no split when axis < 0 (no axis has a positive,
/// finite centroid extent).
struct SplitChoice {
    float cost = inf;    ///< A_left N_left + A_right N_right (half areas) of the best plane
    int axis = -1;       ///< the best plane's axis
    int split = 0;       ///< the best plane: bins [0, split) go left
    float scale = 0.0f;  ///< the best axis' bins / extent (bin_index)
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

    /// The BVH2 (nodes), the leaf-order triangle data (primitives, triangle_corners) and the
    /// statistics; no nodes when no triangle is hittable.
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

        const SplitChoice best = find_split(task, centroid_bounds);

        std::uint32_t mid = 0;
        if (best.axis < 0) {
            // All centroids coincide: SAH cannot separate them. Split the range in the middle
            // (it is in a deterministic order) unless it fits into a leaf.
            if (may_be_leaf) return make_leaf(task);
            mid = task.begin + count / 2;
        } else {
            const float area = bounds.half_area();
            const float split_cost =
                settings_.traversal_cost + settings_.intersection_cost * best.cost / area;
            const float leaf_cost = settings_.intersection_cost * static_cast<float>(count);
            if (may_be_leaf && !(split_cost < leaf_cost)) return make_leaf(task);
            mid = partition(task, best.axis, best.split, centroid_bounds.lo[best.axis], best.scale);
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

    /// Binned SAH: bin the centroids along each axis, then sweep the split planes. The first
    /// best (axis x, y, z, then plane from low to high) wins: strict '<'.
    SplitChoice find_split(const BuildTask& task, const Box& centroid_bounds) {
        const int bins = settings_.bins;
        SplitChoice best;
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = centroid_bounds.hi[axis] - centroid_bounds.lo[axis];
            const float scale = static_cast<float>(bins) / extent;
            if (!(extent > 0.0f) || !std::isfinite(scale)) continue;
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
                if (cost < best.cost) {
                    best.cost = cost;
                    best.axis = axis;
                    best.split = b;
                    best.scale = scale;
                }
            }
        }
        return best;
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
    Bvh bvh = builder.build(positions);
    if (!bvh.nodes.empty()) {
        bvh_internal::make_triangle_blocks(bvh);
        bvh_internal::collapse_to_bvh4(bvh);
    }
    return bvh;
}

}  // namespace fovref
