// Rays and hits (SPEC §3).
#pragma once

#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

namespace fovref {

struct Ray {
    glm::vec3 origin{0.0f};
    glm::vec3 direction{0.0f, 0.0f, -1.0f};  ///< need not be normalised; t is in its units
    float t_min = 0.0f;                      ///< hits need t > t_min
    float t_max = std::numeric_limits<float>::infinity();  ///< and t <= t_max
};

/// Closest hit: the smallest t in (t_min, t_max]; equal t -> the lowest primitive index, so the
/// result does not depend on traversal order (SPEC §3). Barycentrics (u, v) weight corners 1
/// and 2: P = (1 - u - v) p0 + u p1 + v p2.
struct Hit {
    float t = -1.0f;
    std::int32_t primitive = -1;  ///< -1: miss
    float u = 0.0f;
    float v = 0.0f;
    bool hit() const { return primitive >= 0; }
    bool operator==(const Hit&) const = default;
};

/// Per-render traversal statistics (SPEC §3).
struct TraceStats {
    std::int64_t rays = 0;
    std::int64_t nodes_visited = 0;
    std::int64_t triangles_tested = 0;
    std::int64_t hits = 0;
    TraceStats& operator+=(const TraceStats& o) {
        rays += o.rays;
        nodes_visited += o.nodes_visited;
        triangles_tested += o.triangles_tested;
        hits += o.hits;
        return *this;
    }
};

}  // namespace fovref
