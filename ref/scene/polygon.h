// Polygon triangulation for OBJ faces (docs/obj-quirks.md, "Polygons"): a fan where the polygon
// is convex, deterministic ear clipping where it is not.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace fovref {

/// Concave polygons with more corners than this are fanned (PolygonSplit::not_simple): ear
/// clipping costs up to n^3 / 6 point tests.
constexpr int max_ear_clipping_corners = 1024;

/// Point tests ear clipping may spend on one file (a loader passes a budget of this many to
/// triangulate_polygon for all of a file's faces): with the per-face bound above, it bounds a
/// file's load time whatever its faces (about a second).
constexpr std::int64_t ear_clipping_budget = std::int64_t{1} << 28;

/// How triangulate_polygon split a polygon.
enum class PolygonSplit {
    triangle,     ///< 3 corners: the polygon itself
    fan,          ///< convex (or flat): (0, k, k+1) for k = 1 .. n-2, as before ear clipping
    ear_clipped,  ///< concave: ear clipping
    not_simple    ///< concave, but no ear was found (self-intersecting) or the polygon has more
                  ///< than max_ear_clipping_corners corners: (the rest) fanned
};

/// Splits the polygon p[0 .. n) (n >= 3, corners in order) into n - 2 triangles of corner
/// indices, each wound like the polygon. The polygon is projected onto the coordinate plane
/// that its Newell normal is most perpendicular to (ties: x before y before z), in binary64.
/// When every corner turns the same way (no turn against the Newell normal), the result is the
/// fan (0, k, k+1). Otherwise ears are clipped: repeatedly, the first remaining corner c in
/// polygon order whose triangle (previous, c, next) turns with the normal and contains no other
/// remaining corner (on its edges counts as inside; a corner at the same place as one of its three
/// does not count) is cut off as (previous, c, next). Should no
/// corner qualify (a self-intersecting polygon), the remaining corners are fanned from the
/// first of them; a concave polygon of more than max_ear_clipping_corners corners is fanned whole.
/// `budget`, when given, is the number of point tests ear clipping may still spend; it is
/// decreased by what this polygon spends, and a polygon that would overdraw it is fanned
/// (PolygonSplit::not_simple).
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<glm::vec3>& p,
                                                    PolygonSplit* split = nullptr,
                                                    std::int64_t* budget = nullptr);

}  // namespace fovref
