// BVH and watertight intersection (SPEC §3): hand-made cases (shared edges and vertices of closed
// meshes, grazing and parallel rays, rays starting on a surface, inclusive t_max, the equal-t
// tie-break, any hit), bit-identical agreement with the brute-force intersector on fixed-seed
// random rays over every procedural scene, determinism and structural invariants of the tree.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/bvh/watertight.h"
#include "ref/bvh/watertight4.h"
#include "ref/core/error.h"
#include "ref/core/rng.h"
#include "ref/core/simd.h"
#include "ref/scene/camera.h"
#include "ref/scene/procedural.h"
#include "tests/core/build_speed.h"

using namespace fovref;

namespace {

using Mesh = std::vector<glm::vec3>;

std::string show(glm::vec3 v) {
    std::ostringstream out;
    out.precision(9);
    out << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return out.str();
}
std::string show(const Hit& h) {
    std::ostringstream out;
    out.precision(9);
    out << "{t " << h.t << ", primitive " << h.primitive << ", u " << h.u << ", v " << h.v << "}";
    return out.str();
}
std::string show(const Ray& r) {
    return "ray " + show(r.origin) + " + t " + show(r.direction) + ", t in (" +
           std::to_string(r.t_min) + ", " + std::to_string(r.t_max) + "]";
}

/// Bit-identical hits (== would equate 0 and -0).
bool same_bits(const Hit& a, const Hit& b) {
    return std::bit_cast<std::uint32_t>(a.t) == std::bit_cast<std::uint32_t>(b.t) &&
           a.primitive == b.primitive &&
           std::bit_cast<std::uint32_t>(a.u) == std::bit_cast<std::uint32_t>(b.u) &&
           std::bit_cast<std::uint32_t>(a.v) == std::bit_cast<std::uint32_t>(b.v);
}

Ray make_ray(glm::vec3 origin, glm::vec3 direction, float t_min = 0.0f,
             float t_max = std::numeric_limits<float>::infinity()) {
    Ray r;
    r.origin = origin;
    r.direction = direction;
    r.t_min = t_min;
    r.t_max = t_max;
    return r;
}

void add_triangle(Mesh& m, glm::vec3 a, glm::vec3 b, glm::vec3 c) {
    m.push_back(a);
    m.push_back(b);
    m.push_back(c);
}

/// Unit cube [0,1]^3, outward winding. Each face is split along the diagonal from its corner
/// nearest the origin to the opposite one, so axis-aligned rays through (0.5, 0.5) cross that
/// diagonal exactly. 12 triangles, every edge shared by exactly two.
Mesh unit_cube() {
    const glm::vec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}};
    // Quads (a, b, c, d) counter-clockwise seen from outside; diagonal a-c.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    Mesh m;
    for (const auto& q : quads) {
        add_triangle(m, p[q[0]], p[q[1]], p[q[2]]);
        add_triangle(m, p[q[0]], p[q[2]], p[q[3]]);
    }
    return m;
}

/// Regular-ish octahedron with vertices on the axes at distance 1: four triangles meet at every
/// vertex, so rays along an axis go through a vertex on entry and exit.
Mesh octahedron() {
    const glm::vec3 px{1, 0, 0}, nx{-1, 0, 0}, py{0, 1, 0}, ny{0, -1, 0}, pz{0, 0, 1}, nz{0, 0, -1};
    Mesh m;
    add_triangle(m, px, py, pz);
    add_triangle(m, py, nx, pz);
    add_triangle(m, nx, ny, pz);
    add_triangle(m, ny, px, pz);
    add_triangle(m, py, px, nz);
    add_triangle(m, nx, py, nz);
    add_triangle(m, ny, nx, nz);
    add_triangle(m, px, ny, nz);
    return m;
}

/// Every triangle the watertight test reports along the whole ray, sorted by t, grouped into
/// surface crossings: reports whose t differ by less than 1e-4 relative belong to one crossing.
/// (A ray through a shared edge or vertex is reported by each triangle that shares it; their t
/// are the same surface point computed from different corners, equal to a few ulp. Distinct
/// surfaces along the rays used here are at least 0.1 apart along t.)
struct Crossing {
    float t;
    std::vector<int> triangles;
};
std::vector<Crossing> crossings(const Mesh& mesh, const Ray& ray) {
    const WatertightRay r = make_watertight_ray(ray.origin, ray.direction, ray.t_min, ray.t_max);
    std::vector<std::pair<float, int>> reports;
    for (std::size_t i = 0; i < mesh.size() / 3; ++i) {
        float t, u, v;
        if (intersect_watertight(r, mesh[3 * i], mesh[3 * i + 1], mesh[3 * i + 2], t, u, v))
            reports.emplace_back(t, static_cast<int>(i));
    }
    std::sort(reports.begin(), reports.end());
    std::vector<Crossing> result;
    for (const auto& [t, i] : reports) {
        if (result.empty() || t - result.back().t > 1e-4f * std::fabs(t)) result.push_back({t, {}});
        result.back().triangles.push_back(i);
    }
    return result;
}

/// BVH closest hit, any hit and brute force agree (bit for bit); returns the hit.
Hit check_agreement(const Mesh& mesh, const Bvh& bvh, const Ray& ray) {
    TraceStats stats;
    const Hit fast = trace_closest(bvh, ray, stats);
    const Hit slow = trace_brute_force(mesh, ray);
    CHECK_MESSAGE(same_bits(fast, slow),
                  (show(ray) + ": bvh " + show(fast) + " vs brute force " + show(slow)));
    CHECK_MESSAGE(trace_any(bvh, ray, stats) == slow.hit(), show(ray));
    return slow;
}

/// A point on the segment a-b (parameter s), computed in float.
glm::vec3 lerp(glm::vec3 a, glm::vec3 b, float s) { return a + (b - a) * s; }

}  // namespace

TEST_CASE(
    "watertight: rays through shared edges and vertices of closed meshes cross each "
    "surface exactly once") {
    for (const Mesh& mesh : {unit_cube(), octahedron()}) {
        const Bvh bvh = build_bvh(mesh);
        glm::vec3 centre{0.0f};
        for (glm::vec3 p : mesh) centre += p;
        centre /= static_cast<float>(mesh.size());

        // Points on every edge (several parameters, including the end points = vertices), and
        // rays from outside through each towards the interior: the ray enters at the point and
        // leaves once, so exactly two crossings, each reported by at least one triangle.
        int rays = 0;
        for (std::size_t tri = 0; tri < mesh.size() / 3; ++tri) {
            for (int k = 0; k < 3; ++k) {
                const glm::vec3 a = mesh[3 * tri + k], b = mesh[3 * tri + (k + 1) % 3];
                for (float s : {0.0f, 0.125f, 0.3f, 0.5f, 0.77f}) {
                    const glm::vec3 p = lerp(a, b, s);
                    // Several directions: straight at the centre, and tilted by hashed offsets.
                    for (std::uint32_t j = 0; j < 4; ++j) {
                        glm::vec3 target = centre;
                        if (j > 0)
                            for (int c = 0; c < 3; ++c)
                                target[c] += 0.3f * (rand_unit(7, rays, c) - 0.5f);
                        const glm::vec3 origin = p + (p - target) * 2.0f;
                        const Ray ray = make_ray(origin, target - origin);
                        const std::vector<Crossing> found = crossings(mesh, ray);
                        CHECK_MESSAGE(found.size() == 2,
                                      (show(ray) + " crossings " + std::to_string(found.size())));
                        const Hit hit = check_agreement(mesh, bvh, ray);
                        // The closest hit is the first crossing's lowest-t report.
                        if (!found.empty()) CHECK(hit.t == found[0].t);
                        ++rays;
                    }
                }
            }
        }
        CHECK(rays > 100);
    }
}

TEST_CASE(
    "watertight: an axis-aligned ray exactly through a shared diagonal hits both triangles "
    "at the same t, the closest hit reports the lower index") {
    const Mesh cube = unit_cube();
    const Bvh bvh = build_bvh(cube);
    // Down the z axis through (0.5, 0.5): the diagonals of the z = 1 face (triangles 2, 3) and
    // the z = 0 face (triangles 0, 1) are crossed exactly (their edge function is exactly 0).
    const Ray ray = make_ray({0.5f, 0.5f, 3.0f}, {0.0f, 0.0f, -1.0f});
    const std::vector<Crossing> found = crossings(cube, ray);
    REQUIRE(found.size() == 2);
    CHECK(found[0].t == 2.0f);
    CHECK(found[0].triangles == std::vector<int>{2, 3});
    CHECK(found[1].t == 3.0f);
    CHECK(found[1].triangles == std::vector<int>{0, 1});
    const Hit hit = check_agreement(cube, bvh, ray);
    CHECK(hit.primitive == 2);
    CHECK(hit.t == 2.0f);
    // Starting just past the entry: the exit face, again the lower index of the pair.
    const Hit exit_hit = check_agreement(cube, bvh, make_ray(ray.origin, ray.direction, 2.0f));
    CHECK(exit_hit.primitive == 0);
    CHECK(exit_hit.t == 3.0f);
    // Through the cube's vertex (1, 1, 1) along -z: enters at the corner, leaves at (1, 1, 0).
    const Ray corner = make_ray({1.0f, 1.0f, 2.0f}, {0.0f, 0.0f, -1.0f});
    const std::vector<Crossing> corner_found = crossings(cube, corner);
    REQUIRE(corner_found.size() == 2);
    CHECK(corner_found[0].t == 1.0f);
    CHECK(corner_found[1].t == 2.0f);
    check_agreement(cube, bvh, corner);
}

TEST_CASE("watertight: barycentrics, winding and both faces") {
    const Mesh tri{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    const Bvh bvh = build_bvh(tri);
    TraceStats stats;
    // From the front (+z) and the back (-z): no back-face culling, same point, same u, v.
    for (float side : {1.0f, -1.0f}) {
        const Hit h =
            trace_closest(bvh, make_ray({0.25f, 0.5f, 2.0f * side}, {0, 0, -side}), stats);
        REQUIRE(h.hit());
        CHECK(h.t == 2.0f);
        // P = (1 - u - v) p0 + u p1 + v p2 = (u, v, 0); 0.25 and 0.5 are exact.
        CHECK(h.u == 0.25f);
        CHECK(h.v == 0.5f);
    }
    // Just outside the hypotenuse (x + y > 1) misses; on it hits.
    CHECK_FALSE(trace_closest(bvh, make_ray({0.5f, 0.5000001f, 1.0f}, {0, 0, -1}), stats).hit());
    CHECK(trace_closest(bvh, make_ray({0.5f, 0.5f, 1.0f}, {0, 0, -1}), stats).hit());
    // A non-normalised direction: t is in its units.
    const Hit scaled = trace_closest(bvh, make_ray({0.25f, 0.25f, 4.0f}, {0, 0, -2}), stats);
    CHECK(scaled.t == 2.0f);
}

TEST_CASE("grazing and parallel rays") {
    const Mesh cube = unit_cube();
    const Bvh bvh = build_bvh(cube);
    // In the plane of the face z = 0 and inside it: the face is parallel (det = 0, never hit);
    // the ray meets the faces x = 0 and x = 1 at t = 1 and 2.
    Hit h = check_agreement(cube, bvh, make_ray({-1.0f, 0.5f, 0.0f}, {1, 0, 0}));
    CHECK(h.t == 1.0f);
    // Along the cube's edge line y = 0, z = 0: only the corner vertex (0, 0, 0) of the face x = 0
    // is met, at t = 1; the two faces containing the line are parallel to the ray.
    h = check_agreement(cube, bvh, make_ray({-1.0f, 0.0f, 0.0f}, {1, 0, 0}));
    CHECK(h.t == 1.0f);
    // Parallel to a face, just outside the cube: misses everything.
    h = check_agreement(cube, bvh, make_ray({-1.0f, 0.5f, -1e-6f}, {1, 0, 0}));
    CHECK_FALSE(h.hit());
    // Parallel to the face z = 1 and 1e-6 inside the cube: hits x = 0 at t = 1.
    h = check_agreement(cube, bvh, make_ray({-1.0f, 0.5f, 1.0f - 1e-6f}, {1, 0, 0}));
    CHECK(h.t == 1.0f);
    // Grazing rays at shallow angles over the face z = 1, from above: they meet it (or the
    // side faces) once on entry; BVH and brute force agree bit for bit.
    for (std::uint32_t i = 0; i < 200; ++i) {
        const float slope = 1e-4f * (1.0f + static_cast<float>(i));
        const Ray ray = make_ray({-0.5f, rand_unit(3, i, 0), 1.0f + 0.6f * slope},
                                 {1.0f, 0.1f * (rand_unit(3, i, 1) - 0.5f), -slope});
        check_agreement(cube, bvh, ray);
    }
}

TEST_CASE("rays starting on a surface, t_min exclusive, t_max inclusive") {
    // Floor z = 0 (two triangles) and ceiling z = 2.
    Mesh m;
    add_triangle(m, {-1, -1, 0}, {1, -1, 0}, {1, 1, 0});
    add_triangle(m, {-1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
    add_triangle(m, {-1, -1, 2}, {1, 1, 2}, {1, -1, 2});
    add_triangle(m, {-1, -1, 2}, {-1, 1, 2}, {1, 1, 2});
    const Bvh bvh = build_bvh(m);
    // Origin on the floor: up finds the ceiling, down finds nothing (t = 0 is not > t_min = 0).
    Hit h = check_agreement(m, bvh, make_ray({0.3f, 0.2f, 0.0f}, {0, 0, 1}));
    CHECK(h.t == 2.0f);
    CHECK(h.primitive >= 2);
    h = check_agreement(m, bvh, make_ray({0.3f, 0.2f, 0.0f}, {0, 0, -1}));
    CHECK_FALSE(h.hit());
    // A shadow-style ray from a point on the floor with t_min = 1e-4 and a slanted direction.
    h = check_agreement(m, bvh, make_ray({0.3f, 0.2f, 0.0f}, {0.1f, 0.2f, 1.0f}, 1e-4f));
    CHECK(h.t == 2.0f);
    // t_max = exactly the hit distance: hit (inclusive); one ulp less: miss.
    const glm::vec3 o{0.3f, 0.2f, 0.5f}, d{0, 0, 1};
    const float t_hit = 1.5f;
    h = check_agreement(m, bvh, make_ray(o, d, 0.0f, t_hit));
    CHECK(h.t == t_hit);
    h = check_agreement(m, bvh, make_ray(o, d, 0.0f, std::nextafter(t_hit, 0.0f)));
    CHECK_FALSE(h.hit());
    // t_min = exactly the hit distance: excluded; one ulp less: included.
    h = check_agreement(m, bvh, make_ray(o, d, t_hit, 10.0f));
    CHECK_FALSE(h.hit());
    h = check_agreement(m, bvh, make_ray(o, d, std::nextafter(t_hit, 0.0f), 10.0f));
    CHECK(h.t == t_hit);
    // A non-axis-aligned ray: t_max set to the t the brute force reports is inclusive too.
    const Ray slanted = make_ray({-0.7f, 0.4f, 1.3f}, {0.31f, -0.17f, 0.93f});
    const Hit first = trace_brute_force(m, slanted);
    REQUIRE(first.hit());
    h = check_agreement(m, bvh, make_ray(slanted.origin, slanted.direction, 0.0f, first.t));
    CHECK(same_bits(h, first));
    h = check_agreement(
        m, bvh, make_ray(slanted.origin, slanted.direction, 0.0f, std::nextafter(first.t, 0.0f)));
    CHECK_FALSE(h.hit());
}

TEST_CASE("equal t: the lowest primitive index wins, whatever the order") {
    const glm::vec3 a{0, 0, 0}, b{1, 0, 0}, c{0, 1, 0};
    const Ray ray = make_ray({0.2f, 0.3f, 1.0f}, {0, 0, -1});
    // Two coincident triangles, in both orders and with their corners rotated (same plane, same
    // t, different barycentrics): always primitive 0, with its own barycentrics.
    for (int order = 0; order < 4; ++order) {
        const bool rotated = order & 1, swapped = order & 2;
        Mesh first{a, b, c}, second = rotated ? Mesh{b, c, a} : Mesh{a, b, c};
        if (swapped) std::swap(first, second);
        Mesh m = first;
        m.insert(m.end(), second.begin(), second.end());
        const Bvh bvh = build_bvh(m);
        const Hit h = check_agreement(m, bvh, ray);
        CHECK(h.primitive == 0);
        CHECK(h.t == 1.0f);
    }
    // Many copies among other triangles, so that the coincident ones land in different leaves:
    // copies at indices 37, 50, 63, ...; the lowest (37) must win.
    Mesh m;
    for (int i = 0; i < 200; ++i) {
        if (i >= 37 && (i - 37) % 13 == 0) {
            add_triangle(m, a, b, c);
        } else {
            const glm::vec3 shift{2.0f + static_cast<float>(i % 10), static_cast<float>(i / 10),
                                  0.01f * static_cast<float>(i)};
            add_triangle(m, a + shift, b + shift, c + shift);
        }
    }
    const Bvh bvh = build_bvh(m, BvhBuildSettings{1.0f, 1.0f, 8, 1});
    const Hit h = check_agreement(m, bvh, ray);
    CHECK(h.primitive == 37);
}

TEST_CASE("degenerate triangles are never hit, bad rays miss, input errors") {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    Mesh m;
    add_triangle(m, {0, 0, 0}, {1, 0, 0}, {2, 0, 0});     // collinear: zero area
    add_triangle(m, {0, 0, 0}, {0, 0, 0}, {0, 1, 0});     // repeated corner
    add_triangle(m, {0, 0, 0}, {nan, 0, 0}, {0, 1, 0});   // NaN corner
    add_triangle(m, {0, 0, 0}, {inf, 0, 0}, {0, 1, 0});   // infinite corner
    add_triangle(m, {-1, -1, 0}, {1, -1, 0}, {0, 1, 0});  // the only valid one (index 4)
    const Bvh bvh = build_bvh(m);
    CHECK(bvh.stats.triangles == 1);
    CHECK(bvh.stats.degenerate_triangles == 4);
    CHECK(bvh.primitives == std::vector<std::uint32_t>{4});
    for (float x : {0.0f, 0.5f, 1.5f}) {
        const Hit h = check_agreement(m, bvh, make_ray({x, 0.0f, 1.0f}, {0, 0, -1}));
        CHECK(h.primitive == (x < 1.0f ? 4 : -1));
    }
    // Only degenerate triangles: no nodes, every ray misses.
    const Mesh bad(m.begin(), m.begin() + 12);
    const Bvh empty = build_bvh(bad);
    CHECK(empty.nodes.empty());
    check_agreement(bad, empty, make_ray({0.5f, 0.0f, 1.0f}, {0, 0, -1}));
    const Bvh none = build_bvh({});
    CHECK(none.nodes.empty());
    // Bad rays: zero or non-finite direction, non-finite origin, NaN interval. Counted, missed.
    TraceStats stats;
    for (const Ray& ray :
         {make_ray({0, 0, 1}, {0, 0, 0}), make_ray({0, 0, 1}, {0, nan, -1}),
          make_ray({0, 0, 1}, {0, 0, -inf}), make_ray({nan, 0, 1}, {0, 0, -1}),
          make_ray({0, 0, 1}, {0, 0, -1}, nan), make_ray({0, 0, 1}, {0, 0, -1}, 0, nan)}) {
        CHECK_FALSE(trace_closest(bvh, ray, stats).hit());
        CHECK_FALSE(trace_any(bvh, ray, stats));
        CHECK_FALSE(trace_brute_force(m, ray).hit());
    }
    CHECK(stats.rays == 12);
    CHECK(stats.hits == 0);
    // t_min > t_max: empty interval.
    CHECK_FALSE(check_agreement(m, bvh, make_ray({0, 0, 1}, {0, 0, -1}, 2.0f, 0.5f)).hit());
    // Input errors.
    CHECK_THROWS_AS(build_bvh(Mesh(4)), Error);
    CHECK_THROWS_AS(build_bvh(m, BvhBuildSettings{1.0f, 1.0f, 1, 8}), Error);
    CHECK_THROWS_AS(build_bvh(m, BvhBuildSettings{1.0f, 1.0f, 32, 0}), Error);
    CHECK_THROWS_AS(build_bvh(m, BvhBuildSettings{1.0f, 0.0f, 32, 8}), Error);
    CHECK_THROWS_AS(build_bvh(m, BvhBuildSettings{nan, 1.0f, 32, 8}), Error);
}

namespace {

/// The BVH4 collapsed from the BVH2: its leaf slots are exactly the BVH2's leaves, each once,
/// with the leaf's exact box; an inner slot's box holds its wide child's boxes; an unused slot
/// (after the used ones) has the empty box +inf / -inf; wide nodes come after their parent
/// (depth first) and each is reached once.
void check_wide_structure(const Bvh& bvh) {
    REQUIRE_FALSE(bvh.wide_nodes.empty());
    const float inf = std::numeric_limits<float>::infinity();
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<const BvhNode*, int>> leaves;
    for (const BvhNode& n : bvh.nodes)
        if (n.count > 0) leaves[{n.first, n.count}] = {&n, 0};
    std::vector<int> reached(bvh.wide_nodes.size(), 0);
    // (wide node, the box of the slot that points to it; the root has none)
    std::vector<std::pair<std::uint32_t, std::pair<glm::vec3, glm::vec3>>> stack{
        {0u, {glm::vec3(-inf), glm::vec3(inf)}}};
    bool ok = true;
    while (!stack.empty()) {
        const auto [index, parent] = stack.back();
        stack.pop_back();
        ++reached[index];
        const BvhWideNode& w = bvh.wide_nodes[index];
        bool empty_seen = false;
        for (int i = 0; i < 4; ++i) {
            const glm::vec3 lo(w.bounds[0][0][i], w.bounds[1][0][i], w.bounds[2][0][i]);
            const glm::vec3 hi(w.bounds[0][1][i], w.bounds[1][1][i], w.bounds[2][1][i]);
            if (lo.x == inf) {
                empty_seen = true;
                ok = ok && lo == glm::vec3(inf) && hi == glm::vec3(-inf) && w.first[i] == 0 &&
                     w.count[i] == 0;
                continue;
            }
            ok = ok && !empty_seen;  // used slots first
            ok = ok && glm::all(glm::lessThanEqual(parent.first, lo)) &&
                 glm::all(glm::lessThanEqual(hi, parent.second));
            if (w.count[i] > 0) {
                auto it = leaves.find({w.first[i], w.count[i]});
                if (it == leaves.end()) {
                    FAIL_CHECK("wide node " << index << " has an unknown leaf " << w.first[i]);
                    return;
                }
                ok = ok && it->second.first->bounds_min == lo && it->second.first->bounds_max == hi;
                ++it->second.second;
            } else if (w.first[i] <= index || w.first[i] >= bvh.wide_nodes.size()) {
                FAIL_CHECK("wide node " << index << " has a child at " << w.first[i]);
                return;
            } else {
                stack.push_back({w.first[i], {lo, hi}});
            }
        }
    }
    CHECK(ok);
    for (const auto& [leaf, node_times] : leaves)
        if (node_times.second != 1) {
            FAIL_CHECK("leaf at " << leaf.first << " appears " << node_times.second << " times");
            break;
        }
    CHECK(std::count(reached.begin(), reached.end(), 1) ==
          static_cast<std::ptrdiff_t>(reached.size()));
}

/// Structural invariants: children inside parents, leaves hold their triangles, every hittable
/// triangle exactly once, the corners in leaf order, the depth limit.
void check_structure(const Bvh& bvh, const Mesh& mesh) {
    REQUIRE_FALSE(bvh.nodes.empty());
    std::vector<int> seen(mesh.size() / 3, 0);
    std::vector<std::pair<std::uint32_t, int>> stack{{0u, 0}};
    std::int64_t leaves = 0, max_depth = 0;
    bool ok = true;
    while (!stack.empty()) {
        const auto [index, depth] = stack.back();
        stack.pop_back();
        const BvhNode& n = bvh.nodes[index];
        max_depth = std::max<std::int64_t>(max_depth, depth);
        auto inside = [&](glm::vec3 p) {
            return glm::all(glm::lessThanEqual(n.bounds_min, p)) &&
                   glm::all(glm::lessThanEqual(p, n.bounds_max));
        };
        if (n.count > 0) {
            ++leaves;
            for (std::uint32_t i = n.first; i < n.first + n.count; ++i) {
                const std::uint32_t t = bvh.primitives[i];
                ++seen[t];
                for (int k = 0; k < 3; ++k) {
                    ok = ok && bvh.triangle_corners[3 * i + k] == mesh[3 * t + k];
                    ok = ok && inside(mesh[3 * t + k]);
                }
            }
        } else {
            // Depth-first order: children after their parent, inside the array.
            if (!(n.first > index && n.first + 1 < bvh.nodes.size())) {
                FAIL_CHECK("node " << index << " has children at " << n.first);
                return;
            }
            for (std::uint32_t c = n.first; c < n.first + 2; ++c) {
                ok = ok && inside(bvh.nodes[c].bounds_min) && inside(bvh.nodes[c].bounds_max);
                stack.push_back({c, depth + 1});
            }
        }
    }
    CHECK(ok);
    CHECK(leaves == bvh.stats.leaves);
    CHECK(max_depth == bvh.stats.max_depth);
    CHECK(max_depth <= bvh_max_depth);
    CHECK(static_cast<std::int64_t>(bvh.nodes.size()) == 2 * leaves - 1);
    check_wide_structure(bvh);
    for (std::size_t t = 0; t < seen.size(); ++t) {
        const bool hittable = triangle_is_hittable(mesh[3 * t], mesh[3 * t + 1], mesh[3 * t + 2]);
        if (seen[t] != (hittable ? 1 : 0)) {
            FAIL_CHECK("triangle " << t << " appears " << seen[t] << " times");
            break;
        }
    }
}

struct SceneBvh {
    Scene scene;
    Bvh bvh;
};

/// Each scene and its BVH are built once per test run (million takes a while under ASan).
const SceneBvh& scene_bvh(const std::string& name) {
    static std::map<std::string, std::unique_ptr<SceneBvh>> cache;
    auto& entry = cache[name];
    if (!entry) {
        entry = std::make_unique<SceneBvh>();
        entry->scene = make_procedural_scene(name);
        entry->bvh = build_bvh(entry->scene.positions);
    }
    return *entry;
}

}  // namespace

TEST_CASE("BVH vs brute force on fixed-seed random rays over every procedural scene") {
    for (const ProceduralSceneInfo& info : procedural_scenes()) {
        // (million in the optimised build only: build_speed.h)
        if (test::slow_build && info.name == "million") continue;
        CAPTURE(info.name);
        const SceneBvh& s = scene_bvh(info.name);
        const Mesh& mesh = s.scene.positions;
        check_structure(s.bvh, mesh);
        CHECK(s.bvh.stats.triangles == static_cast<std::int64_t>(s.scene.triangle_count()));

        // Brute force costs O(triangles) per ray: keep ~12M triangle tests per scene (ASan).
        const std::uint32_t rays = static_cast<std::uint32_t>(
            std::clamp<std::size_t>(12'000'000 / (mesh.size() / 3), 64, 2000));
        const Bounds bounds = scene_bounds(s.scene);
        const glm::vec3 extent = bounds.max - bounds.min;
        const Camera& camera = s.scene.camera;
        const float tan_half = tan_half_vfov(camera);
        TraceStats stats;
        int hits = 0, mismatches = 0;
        for (std::uint32_t i = 0; i < rays; ++i) {
            auto r = [&](std::uint32_t dim) { return rand_unit(11, i, dim); };
            Ray ray;
            switch (i % 3) {
                case 0:  // camera ray through a random screen point
                    ray = make_ray(
                        camera.position,
                        primary_ray_direction(camera, tan_half, 320, 180, 320 * r(0), 180 * r(1)));
                    break;
                case 1:  // random origin in the (slightly enlarged) bounds, random direction
                    ray = make_ray(
                        bounds.min - 0.1f * extent + 1.2f * extent * glm::vec3(r(0), r(1), r(2)),
                        glm::vec3(r(3), r(4), r(5)) * 2.0f - 1.0f);
                    break;
                default:  // random segment with t_min and t_max (shadow-ray like)
                    ray = make_ray(bounds.min + extent * glm::vec3(r(0), r(1), r(2)),
                                   glm::vec3(r(3), r(4), r(5)) * 2.0f - 1.0f, 1e-4f, 0.5f * r(6));
                    break;
            }
            const Hit fast = trace_closest(s.bvh, ray, stats);
            const Hit slow = trace_brute_force(mesh, ray);
            const bool any = trace_any(s.bvh, ray, stats);
            if (!same_bits(fast, slow) || any != slow.hit()) {
                if (++mismatches <= 5)
                    FAIL_CHECK(show(ray) << ": bvh " << show(fast) << " brute force " << show(slow)
                                         << " any " << any);
            }
            hits += slow.hit() ? 1 : 0;
        }
        CHECK(mismatches == 0);
        // The rays are not all misses (the comparison would then be vacuous): camera rays hit.
        CHECK(hits >= static_cast<int>(rays / 3));
        CHECK(stats.rays == 2 * static_cast<std::int64_t>(rays));
        // The BVH tests far fewer triangles than brute force would.
        CHECK(stats.triangles_tested < static_cast<std::int64_t>(rays) * (mesh.size() / 3 + 8));
        MESSAGE(info.name << ": " << rays << " rays, " << hits << " hits, nodes "
                          << s.bvh.stats.nodes << ", depth " << s.bvh.stats.max_depth
                          << ", SAH cost " << s.bvh.stats.sah_cost);
    }
}

TEST_CASE("deterministic build: the same input gives the same tree") {
    for (const char* name : {"cornell", "checker-room", "glossy-floor", "sphere-grid"}) {
        CAPTURE(name);
        const SceneBvh& s = scene_bvh(name);
        const Bvh again = build_bvh(s.scene.positions);
        CHECK(again == s.bvh);
        CHECK(again.stats.sah_cost == s.bvh.stats.sah_cost);
    }
    // Other settings give a valid, different tree; one triangle per leaf is allowed.
    const SceneBvh& s = scene_bvh("glossy-floor");
    const Bvh fine = build_bvh(s.scene.positions, BvhBuildSettings{1.0f, 1.0f, 8, 1});
    check_structure(fine, s.scene.positions);
    CHECK_FALSE(fine == s.bvh);
    for (std::uint32_t i = 0; i < 64; ++i) {
        const Ray ray = make_ray(
            s.scene.camera.position,
            glm::vec3(rand_unit(5, i, 0), rand_unit(5, i, 1), rand_unit(5, i, 2)) * 2.0f - 1.0f);
        check_agreement(s.scene.positions, fine, ray);
    }
}

TEST_CASE("statistics count rays, nodes, triangles and hits") {
    const Mesh cube = unit_cube();
    const Bvh bvh = build_bvh(cube);
    TraceStats stats;
    CHECK(trace_closest(bvh, make_ray({0.5f, 0.5f, 3.0f}, {0, 0, -1}), stats).hit());
    CHECK_FALSE(trace_closest(bvh, make_ray({5.0f, 0.5f, 3.0f}, {0, 0, -1}), stats).hit());
    CHECK(trace_any(bvh, make_ray({0.5f, 0.5f, 3.0f}, {0, 0, -1}), stats));
    CHECK(stats.rays == 3);
    CHECK(stats.hits == 2);
    CHECK(stats.nodes_visited >= 2);  // the root, at least, for each hitting ray
    CHECK(stats.triangles_tested >= 2);
    CHECK(stats.triangles_tested <= 2 * 12);
    TraceStats total;
    total += stats;
    total += stats;
    CHECK(total.rays == 6);
}

TEST_CASE("triangle blocks hold the leaf-order corners, four triangles per block") {
    for (const char* name : {"cornell", "checker-room", "glossy-floor"}) {
        CAPTURE(name);
        const Bvh& bvh = scene_bvh(name).bvh;
        const std::size_t triangles = bvh.primitives.size();
        REQUIRE(bvh.triangle_blocks.size() == (triangles + 3) / 4);
        bool ok = true;
        for (std::size_t i = 0; i < 4 * bvh.triangle_blocks.size(); ++i)
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) {
                    const float stored = bvh.triangle_blocks[i / 4].corners[k][a][i % 4];
                    // Lanes after the last triangle are zero (they are never tested).
                    const float expected =
                        i < triangles ? bvh.triangle_corners[3 * i + k][a] : 0.0f;
                    ok = ok && std::bit_cast<std::uint32_t>(stored) ==
                                   std::bit_cast<std::uint32_t>(expected);
                }
        CHECK(ok);
    }
}

#if FOVREF_BVH_SSE
TEST_CASE("the 4-wide watertight test gives the scalar test's bits in every lane") {
    // Triangles on an integer grid and rays along and across the axes through grid points and
    // edge midpoints: many edge functions are exactly 0 (the binary64 recomputation), some
    // triangles are degenerate (collinear corners), and t_min / t_max sit exactly at some hits.
    // Every lane must accept exactly when intersect_watertight does, with the same t, u, v bits.
    const auto corner = [](std::uint32_t i, std::uint32_t dim) {
        return std::floor(4.0f * rand_unit(21, i, dim)) - 2.0f;  // -2 .. 1, exact
    };
    int hits = 0, fallbacks = 0, mismatches = 0;
    for (std::uint32_t trial = 0; trial < 4000; ++trial) {
        BvhTriangleBlock block{};
        glm::vec3 tri[4][3];
        for (int lane = 0; lane < 4; ++lane)
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t id = 12 * trial + 3 * static_cast<std::uint32_t>(lane) + k;
                tri[lane][k] = {corner(id, 0), corner(id, 1), corner(id, 2)};
                for (int a = 0; a < 3; ++a) block.corners[k][a][lane] = tri[lane][k][a];
            }
        auto r = [&](std::uint32_t dim) { return rand_unit(22, trial, dim); };
        // Origin on a half-integer grid; direction along an axis, towards a corner or an edge
        // midpoint of one of the triangles (exact in float), or towards a point inside it.
        const glm::vec3 origin =
            glm::floor(glm::vec3(r(0), r(1), r(2)) * 12.0f) * 0.5f - glm::vec3(3.0f);
        const glm::vec3* target = tri[trial / 4 % 4];
        glm::vec3 direction{0.0f};
        switch (trial % 4) {
            case 0: direction[trial / 4 % 3] = r(3) < 0.5f ? -1.0f : 1.0f; break;
            case 1: direction = target[trial / 4 % 3] - origin; break;
            case 2: direction = 0.5f * (target[0] + target[1]) - origin; break;
            default:
                direction = lerp(lerp(target[0], target[1], r(3)), target[2], 0.5f * r(4)) - origin;
                break;
        }
        if (direction == glm::vec3(0.0f)) direction = {0.0f, 0.0f, 1.0f};
        const float t_min = trial % 5 == 0 ? 1.0f : 0.0f;
        const float t_max = trial % 7 == 0 ? 2.0f : std::numeric_limits<float>::max();
        const WatertightRay ray = make_watertight_ray(origin, direction, t_min, t_max);
        const unsigned lanes = trial % 6 == 0 ? 0x5u : 0xfu;  // some lanes masked out
        Hits4 wide;
        const unsigned mask =
            intersect_watertight4(make_watertight_ray4(ray), &block.corners[0][0][0], lanes, wide);
        for (int lane = 0; lane < 4; ++lane) {
            float t = 0.0f, u = 0.0f, v = 0.0f;
            const bool scalar =
                ((lanes >> lane) & 1u) != 0 &&
                intersect_watertight(ray, tri[lane][0], tri[lane][1], tri[lane][2], t, u, v);
            const bool vector = ((mask >> lane) & 1u) != 0;
            bool same = scalar == vector;
            if (same && scalar)
                same = same_bits(Hit{t, 0, u, v}, Hit{wide.t[lane], 0, wide.u[lane], wide.v[lane]});
            if (!same && ++mismatches <= 5)
                FAIL_CHECK("trial " << trial << " lane " << lane << ": scalar " << scalar << " t "
                                    << t << ", 4-wide " << vector << " t " << wide.t[lane]);
            hits += scalar ? 1 : 0;
            // Count the lanes that took the binary64 path (an edge function exactly 0).
            const WatertightRay& q = ray;
            const float o[3] = {q.origin.x, q.origin.y, q.origin.z};
            float e[3][2];
            for (int k = 0; k < 3; ++k) {
                const float c[3] = {tri[lane][k].x - o[0], tri[lane][k].y - o[1],
                                    tri[lane][k].z - o[2]};
                e[k][0] = c[q.kx] - q.shear_x * c[q.kz];
                e[k][1] = c[q.ky] - q.shear_y * c[q.kz];
            }
            const float U = e[2][0] * e[1][1] - e[2][1] * e[1][0];
            const float V = e[0][0] * e[2][1] - e[0][1] * e[2][0];
            const float W = e[1][0] * e[0][1] - e[1][1] * e[0][0];
            fallbacks += (U == 0.0f || V == 0.0f || W == 0.0f) ? 1 : 0;
        }
    }
    CHECK(mismatches == 0);
    // The cases are not vacuous: lanes hit, and lanes took the binary64 path.
    CHECK(hits > 1000);
    CHECK(fallbacks > 1000);
    MESSAGE(hits << " lane hits, " << fallbacks << " lanes with an edge function exactly 0");
}
#endif

#if FOVREF_BVH_SSE
TEST_CASE("the 4-wide ray setup equals the scalar setup, broadcast") {
    // Directions with every sign, zero components (+0 and -0) and ties between |components|
    // (kz is the first largest axis), plus random ones: the permutation, shear and broadcast
    // constants must match make_watertight_ray's bit for bit.
    const float values[] = {0.0f, -0.0f, 1.0f, -1.0f, 0.5f, -2.0f, 3.0f};
    std::vector<glm::vec3> directions;
    for (float x : values)
        for (float y : values)
            for (float z : values)
                if (x != 0.0f || y != 0.0f || z != 0.0f) directions.push_back({x, y, z});
    for (std::uint32_t i = 0; i < 1000; ++i)
        directions.push_back(
            glm::vec3(rand_unit(23, i, 0), rand_unit(23, i, 1), rand_unit(23, i, 2)) * 2.0f - 1.0f);
    const auto bits = [](__m128 v) {
        alignas(16) float f[4];
        _mm_store_ps(f, v);
        return std::vector<std::uint32_t>{
            std::bit_cast<std::uint32_t>(f[0]), std::bit_cast<std::uint32_t>(f[1]),
            std::bit_cast<std::uint32_t>(f[2]), std::bit_cast<std::uint32_t>(f[3])};
    };
    int mismatches = 0;
    for (std::size_t i = 0; i < directions.size(); ++i) {
        const glm::vec3 origin(0.25f * static_cast<float>(i % 7), -1.5f, 3.0f);
        const WatertightRay4 a =
            make_watertight_ray4(make_watertight_ray(origin, directions[i], 0.125f, 9.0f));
        const WatertightRay4 b = make_watertight_ray4(origin, directions[i], 0.125f, 9.0f);
        const bool same =
            bits(a.origin_x) == bits(b.origin_x) && bits(a.origin_y) == bits(b.origin_y) &&
            bits(a.origin_z) == bits(b.origin_z) && bits(a.shear_x) == bits(b.shear_x) &&
            bits(a.shear_y) == bits(b.shear_y) && bits(a.shear_z) == bits(b.shear_z) &&
            bits(a.t_min) == bits(b.t_min) && bits(a.t_max) == bits(b.t_max) &&
            a.offset_x == b.offset_x && a.offset_y == b.offset_y && a.offset_z == b.offset_z;
        if (!same && ++mismatches <= 5) FAIL_CHECK("direction " << show(directions[i]));
    }
    CHECK(mismatches == 0);
}
#endif

TEST_CASE("triangles tested: a whole leaf for closest hit, up to the first hit for any hit") {
    // Six unit squares' lower triangles, stacked in z; triangles 0 and 1 lie off to the side.
    // A traversal cost of 100 keeps all six in one leaf (a split never beats 6 tests), so the
    // leaf order is the input order and the leaf spans two blocks of 4.
    Mesh mesh;
    for (int i = 0; i < 6; ++i) {
        const float x = i < 2 ? 5.0f : 0.0f, z = static_cast<float>(i);
        add_triangle(mesh, {x, 0, z}, {x + 1, 0, z}, {x, 1, z});
    }
    const Bvh bvh = build_bvh(mesh, BvhBuildSettings{100.0f, 1.0f, 32, 8});
    REQUIRE(bvh.nodes.size() == 1);
    REQUIRE(bvh.triangle_blocks.size() == 2);
    {
        // Down through triangles 5, 4, 3, 2: any hit stops at triangle 2, the third in the leaf.
        TraceStats stats;
        CHECK(trace_any(bvh, make_ray({0.25f, 0.25f, 10.0f}, {0, 0, -1}), stats));
        CHECK(stats.triangles_tested == 3);
        CHECK(stats.nodes_visited == 2);  // the wide root and the leaf
        const Hit hit = trace_closest(bvh, make_ray({0.25f, 0.25f, 10.0f}, {0, 0, -1}), stats);
        CHECK(hit.primitive == 5);
        CHECK(stats.triangles_tested == 3 + 6);
    }
    {
        // Only triangle 5 lies in t in (0, 5.5]: any hit tests all six.
        TraceStats stats;
        CHECK(trace_any(bvh, make_ray({0.25f, 0.25f, 10.0f}, {0, 0, -1}, 0.0f, 5.5f), stats));
        CHECK(stats.triangles_tested == 6);
        // Missing every triangle: all six tested, no hit.
        CHECK_FALSE(trace_any(bvh, make_ray({0.75f, 0.75f, 10.0f}, {0, 0, -1}), stats));
        CHECK(stats.triangles_tested == 12);
    }
}

namespace {

/// Rays of every kind the interleaved query meets, with invalid rays among them: camera rays,
/// random origins and directions, short segments, a zero direction, NaN and infinite values.
std::vector<Ray> mixed_rays(const Scene& scene, std::uint32_t count) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const float inf = std::numeric_limits<float>::infinity();
    const Bounds bounds = scene_bounds(scene);
    const glm::vec3 extent = bounds.max - bounds.min;
    const float tan_half = tan_half_vfov(scene.camera);
    std::vector<Ray> rays;
    for (std::uint32_t i = 0; i < count; ++i) {
        auto r = [&](std::uint32_t dim) { return rand_unit(23, i, dim); };
        const glm::vec3 inside = bounds.min + extent * glm::vec3(r(0), r(1), r(2));
        const glm::vec3 direction = glm::vec3(r(3), r(4), r(5)) * 2.0f - 1.0f;
        switch (i % 7) {
            case 0:
            case 1:
                rays.push_back(make_ray(
                    scene.camera.position,
                    primary_ray_direction(scene.camera, tan_half, 64, 36, 64 * r(6), 36 * r(7))));
                break;
            case 2:
            case 3: rays.push_back(make_ray(inside, direction)); break;
            case 4: rays.push_back(make_ray(inside, direction, 1e-4f, 0.3f * r(6))); break;
            case 5: rays.push_back(make_ray(inside, direction, 0.0f, i % 2 ? inf : nan)); break;
            default:
                rays.push_back(make_ray(i % 3 ? inside : glm::vec3(nan, 0.0f, 0.0f),
                                        i % 2 ? glm::vec3(0.0f) : direction));
                break;
        }
    }
    return rays;
}

/// trace_closest_interleaved against trace_closest one ray at a time: hits and counts.
void check_interleaved(const Bvh& bvh, const std::vector<Ray>& rays) {
    TraceStats one_stats, interleaved_stats;
    std::vector<Hit> interleaved(rays.size(), Hit{7.0f, 7, 7.0f, 7.0f});
    trace_closest_interleaved(bvh, rays.data(), rays.size(), interleaved.data(), interleaved_stats);
    int mismatches = 0, hits = 0;
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const Hit one = trace_closest(bvh, rays[i], one_stats);
        hits += one.hit() ? 1 : 0;
        if (!same_bits(one, interleaved[i]) && ++mismatches <= 5)
            FAIL_CHECK("ray " << i << " " << show(rays[i]) << ": one at a time " << show(one)
                              << ", interleaved " << show(interleaved[i]));
    }
    CHECK(mismatches == 0);
    CHECK(interleaved_stats.rays == one_stats.rays);
    CHECK(interleaved_stats.nodes_visited == one_stats.nodes_visited);
    CHECK(interleaved_stats.triangles_tested == one_stats.triangles_tested);
    CHECK(interleaved_stats.hits == one_stats.hits);
    CHECK(interleaved_stats.hits == hits);
    // Not vacuous: a tree with nodes is hit by some of the rays.
    if (!bvh.nodes.empty() && rays.size() >= 8) CHECK(hits > 0);
}

}  // namespace

TEST_CASE("interleaved closest-hit queries give trace_closest's hits and counts bit for bit") {
    // million is left out: its build would add ~10 s to the -O0 and sanitizer runs, and the
    // lanes' bookkeeping does not depend on the tree's size (sphere-grid's BVH2 is 20 levels deep).
    for (const char* name : {"cornell", "checker-room", "glossy-floor", "sphere-grid"}) {
        CAPTURE(name);
        const SceneBvh& s = scene_bvh(name);
        // Fewer rays than lanes, a few more, and many (lanes finish at different times and
        // take new rays); invalid rays in between (every seventh ray from the seventh on).
        for (std::uint32_t count : {0u, 1u, 5u, 17u, 40u, 3001u}) {
            CAPTURE(count);
            check_interleaved(s.bvh, mixed_rays(s.scene, count));
        }
        // Invalid rays only, and a batch that starts and ends with a run of them.
        const std::vector<Ray> invalid(5, make_ray({0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}));
        check_interleaved(s.bvh, invalid);
        std::vector<Ray> framed = invalid;
        for (const Ray& ray : mixed_rays(s.scene, 40)) framed.push_back(ray);
        framed.insert(framed.end(), invalid.begin(), invalid.end());
        check_interleaved(s.bvh, framed);
    }
    // A tree without nodes: every ray misses, and is counted.
    const SceneBvh& s = scene_bvh("cornell");
    const Bvh empty = build_bvh({});
    check_interleaved(empty, mixed_rays(s.scene, 20));
}

namespace {

/// The shadow rays packets are made for: from the first hits of a W x H camera grid (pixel
/// order) towards a point of the scene's first light, as a shading pass traces them.
std::vector<Ray> shadow_rays(const Scene& scene, const Bvh& bvh, int width, int height) {
    glm::vec3 light{0.0f, 10.0f, 0.0f};
    if (!scene.lights.empty()) {
        const Light& l = scene.lights[0];
        light = l.type == Light::Type::point ? l.position
                                             : l.position + 0.5f * l.edge_u + 0.5f * l.edge_v;
    }
    const float tan_half = tan_half_vfov(scene.camera);
    std::vector<Ray> rays;
    TraceStats stats;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const Ray primary = make_ray(
                scene.camera.position,
                primary_ray_direction(scene.camera, tan_half, width, height,
                                      static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f));
            const Hit hit = trace_closest(bvh, primary, stats);
            if (!hit.hit()) continue;
            const glm::vec3 p = primary.origin + primary.direction * hit.t;
            const glm::vec3 to_light = light - p;
            const float distance = std::sqrt(glm::dot(to_light, to_light));
            rays.push_back(make_ray(p, to_light / distance, 1e-4f * scene.scene_scale,
                                    distance * (1.0f - 1e-4f)));
        }
    return rays;
}

/// trace_any_packets against trace_any one ray at a time: each answer, and the ray and hit
/// counts (with the SIMD paths off, every count: it is then trace_any ray by ray). Returns the
/// rays occluded; `walked` (when given) whether the packets' node count differed from trace_any's
/// (the packets' own walk ran).
int check_packets(const Bvh& bvh, const std::vector<Ray>& rays, bool* walked = nullptr) {
    TraceStats one_stats;
    std::vector<std::uint8_t> one(rays.size());
    for (std::size_t i = 0; i < rays.size(); ++i) one[i] = trace_any(bvh, rays[i], one_stats);
    int occluded = 0;
    for (std::uint8_t o : one) occluded += o;
    for (const bool simd : {true, false}) {
        CAPTURE(simd);
        set_simd_allowed(simd);
        TraceStats stats;
        std::vector<std::uint8_t> packets(rays.size(), 7);
        trace_any_packets(bvh, rays.data(), rays.size(), packets.data(), stats);
        set_simd_allowed(true);
        int mismatches = 0;
        for (std::size_t i = 0; i < rays.size(); ++i)
            if (packets[i] != one[i] && ++mismatches <= 5)
                FAIL_CHECK("ray " << i << " " << show(rays[i]) << ": trace_any " << int(one[i])
                                  << ", packets " << int(packets[i]));
        CHECK(mismatches == 0);
        CHECK(stats.rays == one_stats.rays);
        CHECK(stats.hits == one_stats.hits);
        if (!simd) {
            CHECK(stats.nodes_visited == one_stats.nodes_visited);
            CHECK(stats.triangles_tested == one_stats.triangles_tested);
        } else if (walked) {
            *walked = stats.nodes_visited != one_stats.nodes_visited;
        }
    }
    return occluded;
}

}  // namespace

TEST_CASE("shadow-ray packets answer as trace_any, ray by ray") {
    for (const char* name : {"cornell", "checker-room", "glossy-floor", "sphere-grid"}) {
        CAPTURE(name);
        const SceneBvh& s = scene_bvh(name);
        // Coherent rays (full packets, mostly) towards the light: some occluded, some not.
        const std::vector<Ray> shadow = shadow_rays(s.scene, s.bvh, 64, 36);
        bool walked = false;
        const int occluded = check_packets(s.bvh, shadow, &walked);
        CHECK(occluded > 0);
        CHECK(occluded < static_cast<int>(shadow.size()));
        // Not vacuous: where the CPU has AVX the packets walked the tree themselves (their node
        // count follows the packets, not trace_any).
        INFO("AVX: " << cpu_has_avx());
        if (cpu_has_avx()) CHECK(walked);
        // Rays of every octant and axis order (packets cut short), invalid rays between them,
        // short segments, infinite and NaN ends; fewer rays than lanes, and a few more.
        for (std::uint32_t count : {0u, 1u, 5u, 17u, 40u, 3001u}) {
            CAPTURE(count);
            check_packets(s.bvh, mixed_rays(s.scene, count));
        }
    }
    // Intervals at the ends of the floats, in one packet's octant.
    const SceneBvh& s = scene_bvh("cornell");
    const float inf = std::numeric_limits<float>::infinity();
    std::vector<Ray> ends;
    for (const auto& [t_min, t_max] : std::vector<std::pair<float, float>>{{-inf, inf},
                                                                           {inf, inf},
                                                                           {-inf, -inf},
                                                                           {0.0f, -0.0f},
                                                                           {-1e30f, 1e30f},
                                                                           {3.0f, 3.0f},
                                                                           {-0.0f, 1e-30f},
                                                                           {0.5f, inf}})
        ends.push_back(make_ray({0.1f, 0.2f, 3.0f}, {0.01f, 0.02f, -1.0f}, t_min, t_max));
    CHECK(check_packets(s.bvh, ends) > 0);
    // Huge coordinates (a huge box padding): origins far out, aimed back at the scene.
    std::vector<Ray> far;
    for (int k = 0; k < 12; ++k) {
        const glm::vec3 from(1e30f * static_cast<float>(k + 1), 1e29f, -3e29f);
        far.push_back(make_ray(from, glm::vec3(0.1f * static_cast<float>(k), 0.5f, 0.2f) - from));
    }
    check_packets(s.bvh, far);
    // A tree without nodes: every ray misses, and is counted.
    check_packets(build_bvh({}), mixed_rays(s.scene, 20));
}

TEST_CASE("shadow-ray packets through shared edges and vertices: the binary64 recomputation") {
    // A 4 x 4 grid of unit squares in z = 0, two triangles each; rays from above one point
    // through every grid vertex and every edge midpoint (edge functions exactly 0), one octant.
    Mesh mesh;
    for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 4; ++i) {
            const glm::vec3 a(i, j, 0), b(i + 1, j, 0), c(i + 1, j + 1, 0), d(i, j + 1, 0);
            mesh.insert(mesh.end(), {a, b, c, a, c, d});
        }
    const Bvh bvh = build_bvh(mesh);
    std::vector<Ray> rays;
    const glm::vec3 origin(-0.5f, -0.5f, 5.0f);
    for (int j = 0; j <= 8; ++j)
        for (int i = 0; i <= 8; ++i)
            rays.push_back(make_ray(origin, glm::vec3(0.5f * static_cast<float>(i),
                                                      0.5f * static_cast<float>(j), 0.0f) -
                                                origin));
    // All of them end on the grid, edges and vertices included (watertight: none slips through).
    CHECK(check_packets(bvh, rays) == static_cast<int>(rays.size()));
    // Straight down onto the grid at t = 5 exactly: inside (t_min, t_max] when t_max = 5,
    // outside when t_min = 5 (the interval's inclusive and exclusive ends).
    std::vector<Ray> exact;
    for (int k = 0; k < 8; ++k)
        exact.push_back(make_ray({0.3f + 0.4f * static_cast<float>(k), 1.7f, 5.0f}, {0, 0, -1},
                                 k % 2 ? 5.0f : 0.0f, k % 2 ? 6.0f : 5.0f));
    CHECK(check_packets(bvh, exact) == 4);
    // Directions with a -0 component (the negative side's near plane) that hit the grid, a full
    // packet of each sign.
    std::vector<Ray> signed_zero;
    for (int k = 0; k < 16; ++k) {
        const float zero = k < 8 ? -0.0f : 0.0f, step = 0.3f * static_cast<float>(k % 8);
        signed_zero.push_back(make_ray({0.2f + step, 0.3f, 4.0f}, {zero, 0.1f, -1.0f}));
        signed_zero.push_back(make_ray({0.4f, 0.2f + step, 4.0f}, {0.05f, zero, -1.0f}));
    }
    CHECK(check_packets(bvh, signed_zero) == static_cast<int>(signed_zero.size()));
    // Triangles with corners on an integer grid (overlapping, some degenerate) and rays from a
    // half-integer grid above them, all in one octant (full packets), aimed at their corners and
    // edge midpoints: many edge functions are exactly 0 in float, where the binary64
    // recomputation decides (as in the 4-wide test above).
    Mesh grid;
    for (std::uint32_t i = 0; i < 3 * 600; ++i)
        grid.emplace_back(std::floor(4.0f * rand_unit(24, i, 0)) - 2.0f,
                          std::floor(4.0f * rand_unit(24, i, 1)) - 2.0f,
                          std::floor(4.0f * rand_unit(24, i, 2)) - 2.0f);
    const Bvh grid_bvh = build_bvh(grid);
    std::vector<Ray> aimed;
    for (std::uint32_t i = 0; i < 4000; ++i) {
        auto r = [&](std::uint32_t dim) { return rand_unit(25, i, dim); };
        const glm::vec3 from =
            glm::floor(glm::vec3(r(0), r(1), r(2)) * 4.0f) * 0.5f + glm::vec3(-5.0f, -5.0f, 6.0f);
        const std::size_t t = 3 * static_cast<std::size_t>(r(3) * 600.0f);
        const glm::vec3 target = i % 2 ? grid[t + i % 3] : 0.5f * (grid[t] + grid[t + 1 + i % 2]);
        aimed.push_back(make_ray(from, target - from, 0.0f, i % 5 ? 1e30f : 0.999f));
    }
    check_packets(grid_bvh, aimed);
    {
        // A ray along -z through the origin of the sheared plane, where one edge function is
        // exactly 0 in float (Cy Bx and Cx By round to the same float) and -2^-24 exactly: the
        // binary64 recomputation puts the ray outside the triangle (without it, on its edge).
        const float e11 = 1.0f + 0x1p-11f, e12 = 1.0f + 0x1p-12f;
        const Bvh sliver = build_bvh({{0.0f, -1.0f, 0.0f}, {-e11, -e12, 0.0f}, {e12, 1.0f, 0.0f}});
        const std::vector<Ray> down(8, make_ray({0.0f, 0.0f, 5.0f}, {0.0f, 0.0f, -1.0f}));
        TraceStats stats;
        CHECK_FALSE(trace_any(sliver, down[0], stats));
        CHECK(check_packets(sliver, down) == 0);
    }
    // Rays in the plane of the grid (det 0) and grazing it, in one octant.
    std::vector<Ray> flat;
    for (int k = 0; k < 11; ++k)
        flat.push_back(make_ray({-1.0f, 0.1f * static_cast<float>(k), k % 2 ? 0.0f : 1e-7f},
                                {1.0f, 0.01f, -0.0f}));
    check_packets(bvh, flat);
}
