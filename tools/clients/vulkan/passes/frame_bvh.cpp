// The frame pass's GPU BVH2 (frame_bvh.h): binned SAH, flattened depth first.
#include "tools/clients/vulkan/passes/frame_bvh.h"

#include <algorithm>
#include <limits>

namespace fovref_client {
namespace {

constexpr int bins = 16;
constexpr int max_leaf_size = 4;
constexpr int max_depth = 64;  // the shader's stack holds max_depth entries

struct Box {
    float lo[3] = {std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
                   std::numeric_limits<float>::infinity()};
    float hi[3] = {-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
                   -std::numeric_limits<float>::infinity()};
    void grow(const float p[3]) {
        for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
    }
    void grow(const Box& b) {  // an empty b (lo +inf, hi -inf) changes nothing
        for (int a = 0; a < 3; ++a)
            lo[a] = std::min(lo[a], b.lo[a]), hi[a] = std::max(hi[a], b.hi[a]);
    }
    float half_area() const {
        if (!(hi[0] >= lo[0])) return 0.0f;
        const float dx = hi[0] - lo[0], dy = hi[1] - lo[1], dz = hi[2] - lo[2];
        return dx * dy + dy * dz + dz * dx;
    }
};

struct Item {  // one triangle during the build
    Box box;
    float centroid[3];
    std::uint32_t primitive;
};

struct Builder {
    std::vector<Item> items;
    GpuBvh bvh;
};

struct Split {
    int axis = -1;
    float plane = 0.0f;  // centroid coordinate: left when bin < plane bin
    int bin = 0;
    float cost = std::numeric_limits<float>::infinity();
};

// The best binned-SAH plane over items[begin, end) (axis -1 when none has both sides non-empty).
Split best_split(const std::vector<Item>& items, std::size_t begin, std::size_t end,
                 const Box& centroids) {
    Split best;
    for (int axis = 0; axis < 3; ++axis) {
        const float lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
        if (!(extent > 0.0f)) continue;
        Box box[bins];
        int count[bins] = {};
        for (std::size_t k = begin; k < end; ++k) {
            const int b = std::clamp(
                static_cast<int>((items[k].centroid[axis] - lo) * (bins / extent)), 0, bins - 1);
            box[b].grow(items[k].box);
            ++count[b];
        }
        // Right-to-left sweep of the right side's area x count, then left to right.
        float right_cost[bins] = {};
        Box right;
        int right_count = 0;
        for (int b = bins - 1; b > 0; --b) {
            right.grow(box[b]);
            right_count += count[b];
            right_cost[b] = right.half_area() * static_cast<float>(right_count);
        }
        Box left;
        int left_count = 0;
        for (int b = 1; b < bins; ++b) {
            left.grow(box[b - 1]);
            left_count += count[b - 1];
            const int rest = static_cast<int>(end - begin) - left_count;
            if (left_count == 0 || rest == 0) continue;
            const float cost = left.half_area() * static_cast<float>(left_count) + right_cost[b];
            if (cost < best.cost) best = {axis, lo, b, cost};
        }
    }
    return best;
}

// Builds the subtree of items[begin, end) at node index `node` (already allocated).
void build(Builder& s, std::uint32_t node, std::size_t begin, std::size_t end, int depth) {
    Box bounds, centroids;
    for (std::size_t k = begin; k < end; ++k)
        bounds.grow(s.items[k].box), centroids.grow(s.items[k].centroid);
    GpuBvhNode& n = s.bvh.nodes[node];
    std::copy(bounds.lo, bounds.lo + 3, n.lo);
    std::copy(bounds.hi, bounds.hi + 3, n.hi);
    s.bvh.depth = std::max(s.bvh.depth, depth);
    const std::size_t size = end - begin;
    Split split;
    if (size > 1 && depth < max_depth - 1) split = best_split(s.items, begin, end, centroids);
    const float leaf_cost = static_cast<float>(size);
    const float split_cost = 1.0f + split.cost / std::max(bounds.half_area(), 1e-30f);
    if (split.axis < 0 || (static_cast<int>(size) <= max_leaf_size && !(split_cost < leaf_cost))) {
        n.a = static_cast<std::uint32_t>(begin);  // items are in leaf order: triangles follow
        n.count = static_cast<std::uint32_t>(size);
        ++s.bvh.leaves;
        return;
    }
    const int axis = split.axis;
    const float lo = centroids.lo[axis], extent = centroids.hi[axis] - lo;
    const auto middle = std::stable_partition(
        s.items.begin() + static_cast<std::ptrdiff_t>(begin),
        s.items.begin() + static_cast<std::ptrdiff_t>(end), [&](const Item& item) {
            return std::clamp(static_cast<int>((item.centroid[axis] - lo) * (bins / extent)), 0,
                              bins - 1) < split.bin;
        });
    const std::size_t mid = static_cast<std::size_t>(middle - s.items.begin());
    n.count = 0;
    const std::uint32_t left = static_cast<std::uint32_t>(s.bvh.nodes.size());
    s.bvh.nodes.push_back({});
    build(s, left, begin, mid, depth + 1);
    const std::uint32_t right = static_cast<std::uint32_t>(s.bvh.nodes.size());
    s.bvh.nodes[node].a = right;  // `n` may have moved with the vector
    s.bvh.nodes.push_back({});
    build(s, right, mid, end, depth + 1);
}

}  // namespace

GpuBvh build_gpu_bvh(const FrameScene& scene) {
    Builder s;
    for (std::size_t t = 0; t < scene.triangles(); ++t) {
        Item item;
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = scene.positions[3 * t + static_cast<std::size_t>(k)];
            const float corner[3] = {p.x, p.y, p.z};
            item.box.grow(corner);
        }
        for (int a = 0; a < 3; ++a) item.centroid[a] = 0.5f * (item.box.lo[a] + item.box.hi[a]);
        item.primitive = static_cast<std::uint32_t>(t);
        s.items.push_back(item);
    }
    s.bvh.nodes.push_back({});
    if (!s.items.empty()) build(s, 0, 0, s.items.size(), 1);
    for (const Item& item : s.items) {
        const std::size_t base = 3 * static_cast<std::size_t>(item.primitive);
        const Vec3 &p0 = scene.positions[base], &p1 = scene.positions[base + 1],
                   &p2 = scene.positions[base + 2];
        s.bvh.triangles.push_back({{p0.x, p0.y, p0.z},
                                   item.primitive,
                                   {p1.x, p1.y, p1.z},
                                   0.0f,
                                   {p2.x, p2.y, p2.z},
                                   0.0f});
    }
    return s.bvh;
}

}  // namespace fovref_client
