#include "ref/scene/polygon.h"

#include <cmath>

namespace fovref {

namespace {

struct Point2 {
    double x = 0.0, y = 0.0;
};

// Twice the signed area of (a, b, c): > 0 when it turns counter-clockwise.
double turn(Point2 a, Point2 b, Point2 c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

bool same(Point2 a, Point2 b) { return a.x == b.x && a.y == b.y; }

// Whether q lies inside or on the counter-clockwise triangle (a, b, c).
bool inside_or_on(Point2 q, Point2 a, Point2 b, Point2 c) {
    return turn(a, b, q) >= 0.0 && turn(b, c, q) >= 0.0 && turn(c, a, q) >= 0.0;
}

std::vector<std::array<int, 3>> fan(const std::vector<int>& corners) {
    std::vector<std::array<int, 3>> triangles;
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
        triangles.push_back({corners[0], corners[k], corners[k + 1]});
    return triangles;
}

}  // namespace

std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<glm::vec3>& p,
                                                    PolygonSplit* split, std::int64_t* budget) {
    const int n = static_cast<int>(p.size());
    std::vector<int> corners(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) corners[static_cast<std::size_t>(k)] = k;
    auto result = [&](PolygonSplit how, std::vector<std::array<int, 3>> triangles) {
        if (split != nullptr) *split = how;
        return triangles;
    };
    if (n <= 3) return result(PolygonSplit::triangle, fan(corners));

    // Newell normal, binary64, corners in order.
    double normal[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < n; ++i) {
        const glm::dvec3 a(p[static_cast<std::size_t>(i)]);
        const glm::dvec3 b(p[static_cast<std::size_t>((i + 1) % n)]);
        normal[0] += (a.y - b.y) * (a.z + b.z);
        normal[1] += (a.z - b.z) * (a.x + b.x);
        normal[2] += (a.x - b.x) * (a.y + b.y);
    }
    int axis = 0;  // the dropped axis: largest |normal| component, lowest index on ties
    for (int k = 1; k < 3; ++k)
        if (std::fabs(normal[k]) > std::fabs(normal[axis])) axis = k;
    if (!(std::fabs(normal[axis]) > 0.0) || !std::isfinite(normal[axis]))
        return result(PolygonSplit::fan, fan(corners));  // flat or not finite: nothing to clip
    // Project onto the other two axes (u, v) = (axis+1, axis+2) cyclically, which keeps the
    // right-handedness; flip v when the normal points down the dropped axis, so that the
    // polygon's own winding is counter-clockwise in 2D.
    const int u_axis = (axis + 1) % 3, v_axis = (axis + 2) % 3;
    const double v_sign = normal[axis] > 0.0 ? 1.0 : -1.0;
    std::vector<Point2> q(static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
        const glm::dvec3 a(p[static_cast<std::size_t>(k)]);
        q[static_cast<std::size_t>(k)] = {a[u_axis], v_sign * a[v_axis]};
    }

    bool convex = true;
    for (int k = 0; k < n && convex; ++k)
        convex = turn(q[static_cast<std::size_t>((k + n - 1) % n)], q[static_cast<std::size_t>(k)],
                      q[static_cast<std::size_t>((k + 1) % n)]) >= 0.0;
    if (convex) return result(PolygonSplit::fan, fan(corners));
    if (n > max_ear_clipping_corners) return result(PolygonSplit::not_simple, fan(corners));

    std::vector<std::array<int, 3>> triangles;
    while (corners.size() > 3) {
        const std::size_t m = corners.size();
        bool clipped = false;
        for (std::size_t i = 0; i < m && !clipped; ++i) {
            const int a = corners[(i + m - 1) % m], b = corners[i], c = corners[(i + 1) % m];
            const Point2 qa = q[static_cast<std::size_t>(a)], qb = q[static_cast<std::size_t>(b)],
                         qc = q[static_cast<std::size_t>(c)];
            if (!(turn(qa, qb, qc) > 0.0)) continue;  // reflex or flat corner: not an ear
            if (budget != nullptr && (*budget -= static_cast<std::int64_t>(m)) < 0) {
                for (const std::array<int, 3>& t : fan(corners)) triangles.push_back(t);
                return result(PolygonSplit::not_simple, triangles);
            }
            bool empty = true;
            for (std::size_t j = 0; j < m && empty; ++j) {
                const int other = corners[j];
                if (other == a || other == b || other == c) continue;
                // A corner at the same place as one of the ear's (a polygon that touches itself
                // there, as where a hole is joined to the outline) does not block the ear.
                const Point2 qo = q[static_cast<std::size_t>(other)];
                if (same(qo, qa) || same(qo, qb) || same(qo, qc)) continue;
                empty = !inside_or_on(qo, qa, qb, qc);
            }
            if (!empty) continue;
            triangles.push_back({a, b, c});
            corners.erase(corners.begin() + static_cast<std::ptrdiff_t>(i));
            clipped = true;
        }
        if (!clipped) {
            for (const std::array<int, 3>& t : fan(corners)) triangles.push_back(t);
            return result(PolygonSplit::not_simple, triangles);
        }
    }
    triangles.push_back({corners[0], corners[1], corners[2]});
    return result(PolygonSplit::ear_clipped, triangles);
}

}  // namespace fovref
