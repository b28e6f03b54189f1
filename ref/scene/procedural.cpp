// Procedural scenes (SPEC §2). Every scene is built from a handful of shape helpers (rectangle,
// box, UV sphere, heightfield) with float arithmetic and fovref::dm:: trigonometry only, so the
// same name gives the same bits with any compiler and optimisation level. docs/procedural-scenes.md
// lists the scenes with their triangle counts, lights, materials and purpose.
//
// Conventions shared by all scenes:
// - World up is +y, lengths are metres.
// - Every triangle is wound counter-clockwise seen from the side its shading normals point to,
//   i.e. cross(p1 - p0, p2 - p0) agrees with the shading normals (rooms face inwards).
// - A quad light's emitting side is cross(edge_u, edge_v) (all lights here face down).
// - The camera path has keyframes at t = 0, 1, 2, 3 s; Scene::camera is the path's pose at t = 0,
//   bit for bit, so a static render and frame 0 of the path agree.
#include "ref/scene/procedural.h"

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

constexpr glm::vec3 kUp{0.0f, 1.0f, 0.0f};

glm::vec3 normalized(glm::vec3 v) { return v / std::sqrt(glm::dot(v, v)); }

// ---------------------------------------------------------------------------------------------
// Scene assembly

Scene begin_scene(const std::string& name, std::size_t triangles) {
    Scene scene;
    scene.name = name;
    scene.source = "procedural:" + name;
    scene.positions.reserve(3 * triangles);
    scene.normals.reserve(3 * triangles);
    scene.uvs.reserve(3 * triangles);
    scene.material_ids.reserve(triangles);
    return scene;
}

int add_material(Scene& scene, Material material) {
    scene.materials.push_back(std::move(material));
    return static_cast<int>(scene.materials.size()) - 1;
}

Material diffuse(const std::string& name, glm::vec3 albedo) {
    Material material;
    material.name = name;
    material.albedo = albedo;
    return material;
}

Material glossy(const std::string& name, glm::vec3 albedo, glm::vec3 specular, float roughness) {
    Material material = diffuse(name, albedo);
    material.specular = specular;
    material.roughness = roughness;
    return material;
}

void add_triangle(Scene& scene, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 n0,
                  glm::vec3 n1, glm::vec3 n2, glm::vec2 uv0, glm::vec2 uv1, glm::vec2 uv2,
                  int material) {
    scene.positions.insert(scene.positions.end(), {p0, p1, p2});
    scene.normals.insert(scene.normals.end(), {n0, n1, n2});
    scene.uvs.insert(scene.uvs.end(), {uv0, uv1, uv2});
    scene.material_ids.push_back(material);
}

Light point_light(glm::vec3 position, glm::vec3 intensity) {
    Light light;
    light.type = Light::Type::point;
    light.position = position;
    light.intensity = intensity;
    return light;
}

/// Quad light with corner `corner`, emitting radiance `radiance` towards cross(edge_u, edge_v).
Light quad_light(glm::vec3 corner, glm::vec3 edge_u, glm::vec3 edge_v, glm::vec3 radiance) {
    Light light;
    light.type = Light::Type::quad;
    light.position = corner;
    light.edge_u = edge_u;
    light.edge_v = edge_v;
    light.intensity = radiance;
    return light;
}

// ---------------------------------------------------------------------------------------------
// Shapes

/// Flat quad p0 p1 p2 p3 (counter-clockwise seen from its front) as triangles (p0, p1, p2),
/// (p0, p2, p3), facing normalize(cross(p1 - p0, p3 - p0)). UVs run from (0, 0) at p0 to
/// uv_extent at p2, so a texture tiles uv_extent times along each edge.
void add_quad(Scene& scene, glm::vec3 p0, glm::vec3 p1, glm::vec3 p2, glm::vec3 p3,
              glm::vec2 uv_extent, int material) {
    const glm::vec3 n = normalized(glm::cross(p1 - p0, p3 - p0));
    const glm::vec2 t0{0.0f, 0.0f}, t1{uv_extent.x, 0.0f}, t2 = uv_extent, t3{0.0f, uv_extent.y};
    add_triangle(scene, p0, p1, p2, n, n, n, t0, t1, t2, material);
    add_triangle(scene, p0, p2, p3, n, n, n, t0, t2, t3, material);
}

/// Rectangle origin, origin + edge_u, origin + edge_u + edge_v, origin + edge_v; it faces
/// cross(edge_u, edge_v). For free-standing rectangles; shapes whose faces share corners (rooms,
/// boxes) compute each corner once so that shared edges are bit-identical (watertight, SPEC §3).
void add_rect(Scene& scene, glm::vec3 origin, glm::vec3 edge_u, glm::vec3 edge_v,
              glm::vec2 uv_extent, int material) {
    add_quad(scene, origin, origin + edge_u, origin + edge_u + edge_v, origin + edge_v, uv_extent,
             material);
}

/// Corner k of a box (bit 0: x, bit 1: y, bit 2: z; 0 = low side, 1 = high side).
using BoxCorners = std::array<glm::vec3, 8>;
using QuadCorners = std::array<int, 4>;

void add_quad(Scene& scene, const BoxCorners& corners, QuadCorners quad, glm::vec2 uv_extent,
              int material) {
    add_quad(scene, corners[quad[0]], corners[quad[1]], corners[quad[2]], corners[quad[3]],
             uv_extent, material);
}

/// Materials of an axis-aligned room's six faces (-1 = leave the face out). All faces look in.
struct RoomFaces {
    int floor = -1, ceiling = -1, back = -1, front = -1, left = -1, right = -1;
};

/// Room [lo, hi] (back = -z, front = +z, left = -x), 2 triangles per face, UVs tiling the
/// texture `tiles_per_metre` times per metre along both edges of each face; u runs
/// horizontally and v upwards on the walls.
void add_room(Scene& scene, glm::vec3 lo, glm::vec3 hi, RoomFaces faces, float tiles_per_metre) {
    BoxCorners corners;
    for (int k = 0; k < 8; ++k)
        corners[k] = {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
    const glm::vec3 tiles = (hi - lo) * tiles_per_metre;
    // Corner orders, counter-clockwise seen from inside the room.
    if (faces.floor >= 0) add_quad(scene, corners, {4, 5, 1, 0}, {tiles.x, tiles.z}, faces.floor);
    if (faces.ceiling >= 0)
        add_quad(scene, corners, {2, 3, 7, 6}, {tiles.x, tiles.z}, faces.ceiling);
    if (faces.back >= 0) add_quad(scene, corners, {0, 1, 3, 2}, {tiles.x, tiles.y}, faces.back);
    if (faces.front >= 0) add_quad(scene, corners, {5, 4, 6, 7}, {tiles.x, tiles.y}, faces.front);
    if (faces.left >= 0) add_quad(scene, corners, {4, 0, 2, 6}, {tiles.z, tiles.y}, faces.left);
    if (faces.right >= 0) add_quad(scene, corners, {1, 5, 7, 3}, {tiles.z, tiles.y}, faces.right);
}

/// Box of `size` standing on the point `base` (centre of its bottom face), turned by `angle_rad`
/// about the vertical axis (x' = c x + s z, z' = -s x + c z). 6 faces x 2 triangles, outward
/// flat normals, UVs [0, uv_extent]^2 on every face (v upwards on the sides).
void add_box(Scene& scene, glm::vec3 base, glm::vec3 size, float angle_rad, float uv_extent,
             int material) {
    const float c = dm::cos(angle_rad);
    const float s = dm::sin(angle_rad);
    const glm::vec3 half = size * 0.5f;
    BoxCorners corners;
    for (int k = 0; k < 8; ++k) {
        const float x = (k & 1) ? half.x : -half.x, z = (k & 4) ? half.z : -half.z;
        corners[k] = base + glm::vec3(c * x + s * z, (k & 2) ? size.y : 0.0f, -s * x + c * z);
    }
    // Corner orders, counter-clockwise seen from outside: +x, -x, +z, -z, +y, -y.
    const QuadCorners quads[6] = {{5, 1, 3, 7}, {0, 4, 6, 2}, {4, 5, 7, 6},
                                  {1, 0, 2, 3}, {6, 7, 3, 2}, {0, 1, 5, 4}};
    for (const QuadCorners& quad : quads)
        add_quad(scene, corners, quad, glm::vec2(uv_extent), material);
}

/// Unit directions of a UV sphere with `segments` steps in longitude phi and `rings` bands in
/// latitude theta (theta = 0 at +y): d = (sin theta cos phi, cos theta, -sin theta sin phi), so phi
/// turns counter-clockwise seen from above. Shared by every sphere of one resolution.
struct SphereTable {
    int segments = 0;
    int rings = 0;
    std::vector<glm::vec3> directions;  ///< (rings + 1) x segments, ring-major; poles exact

    glm::vec3 at(int ring, int segment) const {
        return directions[static_cast<std::size_t>(ring) * segments + segment % segments];
    }
};

SphereTable make_sphere_table(int segments, int rings) {
    SphereTable table;
    table.segments = segments;
    table.rings = rings;
    table.directions.resize(static_cast<std::size_t>(rings + 1) * segments);
    std::vector<float> sin_phi(segments), cos_phi(segments);
    for (int j = 0; j < segments; ++j) {
        const float phi = 2.0f * dm::pi * (static_cast<float>(j) / static_cast<float>(segments));
        sin_phi[j] = dm::sin(phi);
        cos_phi[j] = dm::cos(phi);
    }
    for (int i = 0; i <= rings; ++i) {
        const float theta = dm::pi * (static_cast<float>(i) / static_cast<float>(rings));
        const float sin_theta = dm::sin(theta), cos_theta = dm::cos(theta);
        for (int j = 0; j < segments; ++j) {
            glm::vec3 d;
            if (i == 0)
                d = {0.0f, 1.0f, 0.0f};  // exact poles: dm::sin(pi_float) is not 0
            else if (i == rings)
                d = {0.0f, -1.0f, 0.0f};
            else
                d = normalized({sin_theta * cos_phi[j], cos_theta, -sin_theta * sin_phi[j]});
            table.directions[static_cast<std::size_t>(i) * segments + j] = d;
        }
    }
    return table;
}

/// UV sphere with smooth normals: one triangle per segment in each polar cap (no degenerate
/// quads at the poles) and two per segment in the rings - 2 other bands, i.e.
/// 2 * segments * (rings - 1) triangles. u = phi / 2 pi, v = 1 - theta / pi.
void add_uv_sphere(Scene& scene, const SphereTable& table, glm::vec3 centre, float radius,
                   int material) {
    const int segments = table.segments, rings = table.rings;
    auto position = [&](glm::vec3 d) { return centre + radius * d; };
    auto uv = [&](int i, float j) {
        return glm::vec2(j / static_cast<float>(segments),
                         1.0f - static_cast<float>(i) / static_cast<float>(rings));
    };
    for (int j = 0; j < segments; ++j) {
        const float fj = static_cast<float>(j);
        // North cap: pole, (1, j), (1, j + 1).
        {
            const glm::vec3 a = table.at(0, j), b = table.at(1, j), c = table.at(1, j + 1);
            add_triangle(scene, position(a), position(b), position(c), a, b, c, uv(0, fj + 0.5f),
                         uv(1, fj), uv(1, fj + 1.0f), material);
        }
        // Bands: quad (i, j) (i + 1, j) (i + 1, j + 1) (i, j + 1), counter-clockwise from outside.
        for (int i = 1; i + 1 < rings; ++i) {
            const glm::vec3 a = table.at(i, j), b = table.at(i + 1, j), c = table.at(i + 1, j + 1),
                            d = table.at(i, j + 1);
            const glm::vec2 ta = uv(i, fj), tb = uv(i + 1, fj), tc = uv(i + 1, fj + 1.0f),
                            td = uv(i, fj + 1.0f);
            add_triangle(scene, position(a), position(b), position(c), a, b, c, ta, tb, tc,
                         material);
            add_triangle(scene, position(a), position(c), position(d), a, c, d, ta, tc, td,
                         material);
        }
        // South cap: (rings - 1, j), pole, (rings - 1, j + 1).
        {
            const glm::vec3 a = table.at(rings - 1, j), b = table.at(rings, j),
                            c = table.at(rings - 1, j + 1);
            add_triangle(scene, position(a), position(b), position(c), a, b, c, uv(rings - 1, fj),
                         uv(rings, fj + 0.5f), uv(rings - 1, fj + 1.0f), material);
        }
    }
}

/// Checkerboard of `square` x `square` texel squares, `light` where (x / square + y / square)
/// is even (texel (0, 0) is light), `dark` elsewhere; grey RGB.
Texture make_checker_texture(int size, int square, float light, float dark) {
    Texture texture;
    texture.name =
        "procedural:checker-" + std::to_string(size) + "-" + std::to_string(square) + "px";
    texture.image = Image(size, size, 3);
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float value = ((x / square + y / square) % 2 == 0) ? light : dark;
            for (int c = 0; c < 3; ++c) texture.image.at(x, y, c) = value;
        }
    return texture;
}

/// Keyframes at t = 0, 1, 2, ... looking from positions[k] at targets[k]; the scene camera is the
/// pose at t = 0 as camera_at computes it.
void set_camera_path(Scene& scene, const std::vector<glm::vec3>& positions,
                     const std::vector<glm::vec3>& targets, float vfov_deg) {
    FOVREF_CHECK(positions.size() == targets.size() && !positions.empty(),
                 "camera path: " + std::to_string(positions.size()) + " positions, " +
                     std::to_string(targets.size()) + " targets");
    scene.camera_path.clear();
    for (std::size_t k = 0; k < positions.size(); ++k) {
        CameraKey key;
        key.time = static_cast<float>(k);
        key.position = positions[k];
        key.orientation = camera_orientation(look_at(positions[k], targets[k], kUp, vfov_deg));
        scene.camera_path.push_back(key);
    }
    scene.camera.vfov_deg = vfov_deg;
    scene.camera = camera_at(scene, scene.camera_path.front().time);
}

// ---------------------------------------------------------------------------------------------
// Scenes

/// Cornell box: room [-1, 1] x [0, 2] x [-1, 1] open at the front (+z), the 0.5 m emissive
/// panel 1 cm below the ceiling, a short and a tall box turned by -/+17 degrees, and an explicit
/// quad fill light (no geometry) near the front of the ceiling. 5 x 2 + 2 + 2 x 12 = 36 triangles.
Scene make_cornell() {
    Scene scene = begin_scene("cornell", 36);
    const int white = add_material(scene, diffuse("white", glm::vec3(0.73f)));
    const int red = add_material(scene, diffuse("red", {0.65f, 0.05f, 0.05f}));
    const int green = add_material(scene, diffuse("green", {0.12f, 0.45f, 0.15f}));
    Material panel = diffuse("light", glm::vec3(0.78f));
    // The original box's (17, 12, 4) scaled by its panel-to-ceiling area ratio over ours.
    panel.emission = {12.0f, 8.5f, 2.8f};
    const int light = add_material(scene, panel);

    RoomFaces faces;
    faces.floor = faces.ceiling = faces.back = white;
    faces.left = red;
    faces.right = green;
    add_room(scene, {-1.0f, 0.0f, -1.0f}, {1.0f, 2.0f, 1.0f}, faces, 0.5f);
    add_rect(scene, {-0.25f, 1.99f, -0.25f}, {0.5f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.5f}, {1.0f, 1.0f},
             light);
    add_box(scene, {0.35f, 0.0f, 0.35f}, glm::vec3(0.6f), dm::radians(-17.0f), 1.0f, white);
    add_box(scene, {-0.35f, 0.0f, -0.3f}, {0.6f, 1.2f, 0.6f}, dm::radians(17.0f), 1.0f, white);

    scene.lights.push_back(
        quad_light({-0.3f, 1.95f, 0.45f}, {0.6f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.3f}, glm::vec3(1.5f)));
    set_camera_path(
        scene, {{0.0f, 1.0f, 3.9f}, {0.3f, 1.05f, 3.8f}, {0.5f, 1.15f, 3.6f}, {0.2f, 1.1f, 3.5f}},
        {{0.0f, 1.0f, 0.0f}, {0.05f, 1.0f, 0.0f}, {0.1f, 0.95f, 0.0f}, {0.0f, 0.9f, 0.0f}}, 40.0f);
    finalize_scene(scene);
    return scene;
}

/// 10 x 10 UV spheres (radius 0.4 m, 50 segments x 26 rings = 2500 triangles each) on a 12 m
/// ground square: 250 002 triangles.
Scene make_sphere_grid() {
    constexpr int grid = 10, segments = 50, rings = 26;
    Scene scene = begin_scene("sphere-grid", 2 + grid * grid * 2 * segments * (rings - 1));
    const int ground = add_material(scene, diffuse("ground", glm::vec3(0.5f)));
    const int sphere_materials[4] = {
        add_material(scene, diffuse("red", {0.7f, 0.1f, 0.1f})),
        add_material(scene, diffuse("white", glm::vec3(0.8f))),
        add_material(scene, glossy("blue-glossy", {0.1f, 0.2f, 0.6f}, glm::vec3(0.5f), 0.2f)),
        add_material(scene, glossy("gold-glossy", {0.2f, 0.15f, 0.05f}, {0.9f, 0.7f, 0.3f}, 0.35f)),
    };
    add_rect(scene, {-6.0f, 0.0f, 6.0f}, {12.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -12.0f}, {1.0f, 1.0f},
             ground);
    const SphereTable table = make_sphere_table(segments, rings);
    for (int j = 0; j < grid; ++j)
        for (int i = 0; i < grid; ++i) {
            const glm::vec3 centre{-4.5f + static_cast<float>(i), 0.4f,
                                   -4.5f + static_cast<float>(j)};
            add_uv_sphere(scene, table, centre, 0.4f, sphere_materials[(i + 2 * j) % 4]);
        }

    scene.lights.push_back(point_light({-3.0f, 6.0f, 4.0f}, glm::vec3(60.0f)));
    scene.lights.push_back(
        quad_light({-1.5f, 7.0f, -1.5f}, {3.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 3.0f}, glm::vec3(3.0f)));
    // Orbit at radius 10 m, 4.5 m high, from -10 to +20 degrees.
    std::vector<glm::vec3> positions, targets;
    for (int k = 0; k < 4; ++k) {
        const float angle = dm::radians(-10.0f + 10.0f * static_cast<float>(k));
        positions.push_back({10.0f * dm::sin(angle), 4.5f, 10.0f * dm::cos(angle)});
        targets.push_back({0.0f, 0.3f, 0.0f});
    }
    set_camera_path(scene, positions, targets, 45.0f);
    finalize_scene(scene);
    return scene;
}

/// Height of the `million` terrain as a sum of separable terms a_k f_k(w_k x + b_k) g_k(...),
/// each f, g a sine or cosine, so that columns and rows can be tabulated once.
struct HeightTerm {
    float amplitude;
    bool x_is_sin;
    float x_freq, x_phase;
    bool z_is_sin;
    float z_freq, z_phase;
};
constexpr HeightTerm kHeightTerms[] = {
    {1.6f, true, 0.13f, 0.4f, false, 0.11f, -0.2f},
    {0.7f, true, 0.37f, -1.1f, true, 0.29f, 0.6f},
    {0.25f, false, 1.3f, 0.5f, false, 0.9f, -0.3f},
    {0.06f, true, 4.1f, 0.0f, false, 3.7f, 1.0f},
};
constexpr int kTerms = 4;

/// One axis of the heightfield: value and derivative of each term's factor at each grid line.
struct AxisTable {
    std::vector<float> value[kTerms], slope[kTerms];
};

AxisTable tabulate_axis(const std::vector<float>& coords, bool is_x) {
    AxisTable table;
    for (int k = 0; k < kTerms; ++k) {
        const HeightTerm& term = kHeightTerms[k];
        const bool is_sin = is_x ? term.x_is_sin : term.z_is_sin;
        const float freq = is_x ? term.x_freq : term.z_freq;
        const float phase = is_x ? term.x_phase : term.z_phase;
        for (float coord : coords) {
            const float arg = freq * coord + phase;
            const float s = dm::sin(arg), c = dm::cos(arg);
            // d/dx sin(w x + b) = w cos(w x + b), d/dx cos(w x + b) = -w sin(w x + b).
            table.value[k].push_back(is_sin ? s : c);
            table.slope[k].push_back(is_sin ? freq * c : -freq * s);
        }
    }
    return table;
}

/// 708 x 708 quads (2 triangles each) over [-32, 32]^2, height
///   h(x, z) = 1.6 sin(0.13 x + 0.4) cos(0.11 z - 0.2) + 0.7 sin(0.37 x - 1.1) sin(0.29 z + 0.6)
///           + 0.25 cos(1.3 x + 0.5) cos(0.9 z - 0.3) + 0.06 sin(4.1 x) cos(3.7 z + 1.0),
/// terms summed in this order in float; smooth normals from the analytic gradient,
/// n = normalize(-dh/dx, 1, -dh/dz). "rock" where a triangle's mean height exceeds 0.5 m, else
/// "grass". 1 002 528 triangles.
Scene make_million() {
    constexpr int quads = 708;
    constexpr float half_size = 32.0f;
    Scene scene = begin_scene("million", 2 * static_cast<std::size_t>(quads) * quads);
    const int grass = add_material(scene, diffuse("grass", {0.25f, 0.45f, 0.15f}));
    const int rock = add_material(scene, diffuse("rock", {0.45f, 0.4f, 0.35f}));

    // Grid lines: coordinate -32 + 64 (i / 708), exact at both ends.
    constexpr int lines = quads + 1;
    std::vector<float> coords(lines);
    for (int i = 0; i < lines; ++i)
        coords[i] =
            -half_size + 2.0f * half_size * (static_cast<float>(i) / static_cast<float>(quads));
    const AxisTable along_x = tabulate_axis(coords, true);
    const AxisTable along_z = tabulate_axis(coords, false);

    // Vertex grid, index i (x) + lines * j (z).
    std::vector<glm::vec3> grid_positions(static_cast<std::size_t>(lines) * lines);
    std::vector<glm::vec3> grid_normals(grid_positions.size());
    for (int j = 0; j < lines; ++j)
        for (int i = 0; i < lines; ++i) {
            float h = 0.0f, dh_dx = 0.0f, dh_dz = 0.0f;
            for (int k = 0; k < kTerms; ++k) {
                const float a = kHeightTerms[k].amplitude;
                h += a * along_x.value[k][i] * along_z.value[k][j];
                dh_dx += a * along_x.slope[k][i] * along_z.value[k][j];
                dh_dz += a * along_x.value[k][i] * along_z.slope[k][j];
            }
            const std::size_t v = static_cast<std::size_t>(j) * lines + i;
            grid_positions[v] = {coords[i], h, coords[j]};
            grid_normals[v] = normalized({-dh_dx, 1.0f, -dh_dz});
        }

    auto uv = [&](int i, int j) {
        return glm::vec2(static_cast<float>(i) / static_cast<float>(quads),
                         static_cast<float>(j) / static_cast<float>(quads));
    };
    auto emit = [&](int i0, int j0, int i1, int j1, int i2, int j2) {
        const std::size_t a = static_cast<std::size_t>(j0) * lines + i0,
                          b = static_cast<std::size_t>(j1) * lines + i1,
                          c = static_cast<std::size_t>(j2) * lines + i2;
        const float mean_height =
            (grid_positions[a].y + grid_positions[b].y + grid_positions[c].y) / 3.0f;
        add_triangle(scene, grid_positions[a], grid_positions[b], grid_positions[c],
                     grid_normals[a], grid_normals[b], grid_normals[c], uv(i0, j0), uv(i1, j1),
                     uv(i2, j2), mean_height > 0.5f ? rock : grass);
    };
    // Quad (i, j) as (i,j)(i,j+1)(i+1,j+1) and (i,j)(i+1,j+1)(i+1,j): both face +y.
    for (int j = 0; j < quads; ++j)
        for (int i = 0; i < quads; ++i) {
            emit(i, j, i, j + 1, i + 1, j + 1);
            emit(i, j, i + 1, j + 1, i + 1, j);
        }

    scene.lights.push_back(point_light({20.0f, 40.0f, 10.0f}, glm::vec3(2500.0f)));
    scene.lights.push_back(quad_light({-10.0f, 30.0f, -10.0f}, {20.0f, 0.0f, 0.0f},
                                      {0.0f, 0.0f, 20.0f}, glm::vec3(1.0f)));
    // Fly-over towards -z, 12 m above the terrain's mid-plane (heights stay within +-2.61 m).
    set_camera_path(
        scene,
        {{0.0f, 12.0f, 40.0f}, {2.0f, 11.5f, 34.0f}, {0.0f, 11.0f, 28.0f}, {-2.0f, 10.5f, 22.0f}},
        {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, -6.0f}, {0.0f, 0.0f, -12.0f}, {-1.0f, 0.0f, -18.0f}},
        50.0f);
    finalize_scene(scene);
    return scene;
}

/// Closed room [-3, 3] x [0, 3] x [-3, 3] whose floor and walls carry a 512 x 512 checkerboard
/// of 2-texel squares tiled once per metre (3.9 mm squares: far below a pixel at a few metres, the
/// aliasing stress case), a sphere (32 x 16, 960 triangles) and a checker-textured box.
/// 12 + 960 + 12 = 984 triangles.
Scene make_checker_room() {
    Scene scene = begin_scene("checker-room", 984);
    scene.textures.push_back(make_checker_texture(512, 2, 0.8f, 0.05f));
    Material checker_floor = diffuse("checker-floor", glm::vec3(1.0f));
    checker_floor.texture = 0;
    Material checker_wall = diffuse("checker-wall", {0.9f, 0.85f, 0.75f});
    checker_wall.texture = 0;
    Material checker_box = diffuse("checker-box", glm::vec3(1.0f));
    checker_box.texture = 0;
    const int floor_id = add_material(scene, checker_floor);
    const int wall_id = add_material(scene, checker_wall);
    const int ceiling_id = add_material(scene, diffuse("ceiling", glm::vec3(0.8f)));
    const int sphere_id = add_material(scene, diffuse("orange", {0.8f, 0.35f, 0.1f}));
    const int box_id = add_material(scene, checker_box);

    RoomFaces faces;
    faces.floor = floor_id;
    faces.ceiling = ceiling_id;
    faces.back = faces.front = faces.left = faces.right = wall_id;
    add_room(scene, {-3.0f, 0.0f, -3.0f}, {3.0f, 3.0f, 3.0f}, faces, 1.0f);
    add_uv_sphere(scene, make_sphere_table(32, 16), {-1.2f, 0.7f, -0.8f}, 0.7f, sphere_id);
    add_box(scene, {1.1f, 0.0f, -0.5f}, glm::vec3(1.0f), dm::radians(30.0f), 2.0f, box_id);

    scene.lights.push_back(quad_light({-0.75f, 2.99f, -0.75f}, {1.5f, 0.0f, 0.0f},
                                      {0.0f, 0.0f, 1.5f}, glm::vec3(4.0f)));
    scene.lights.push_back(point_light({1.5f, 2.5f, 1.5f}, glm::vec3(3.0f)));
    // Walking sideways inside the room; the floor is seen at grazing angles.
    set_camera_path(
        scene, {{0.5f, 1.6f, 2.6f}, {0.1f, 1.6f, 2.4f}, {-0.3f, 1.55f, 2.2f}, {-0.7f, 1.5f, 2.0f}},
        {{-0.4f, 0.5f, -2.0f}, {-0.5f, 0.5f, -2.0f}, {-0.6f, 0.55f, -2.0f}, {-0.7f, 0.6f, -2.0f}},
        60.0f);
    finalize_scene(scene);
    return scene;
}

/// A dark GGX floor (specular 0.9, roughness 0.15) over [-4, 4]^2 with a back wall 4 m high,
/// three diffuse spheres (48 x 24, 2208 triangles each), a diffuse box, an emissive ceiling panel
/// at 3.5 m and a point light. 2 + 2 + 3 x 2208 + 12 + 2 = 6642 triangles.
Scene make_glossy_floor() {
    Scene scene = begin_scene("glossy-floor", 6642);
    const int floor_id =
        add_material(scene, glossy("glossy-floor", glm::vec3(0.05f), glm::vec3(0.9f), 0.15f));
    const int wall = add_material(scene, diffuse("wall", glm::vec3(0.7f)));
    const int red = add_material(scene, diffuse("red", {0.75f, 0.1f, 0.1f}));
    const int green = add_material(scene, diffuse("green", {0.1f, 0.6f, 0.15f}));
    const int blue = add_material(scene, diffuse("blue", {0.1f, 0.2f, 0.75f}));
    const int box_id = add_material(scene, diffuse("box", glm::vec3(0.8f)));
    Material panel = diffuse("light", glm::vec3(0.0f));
    panel.emission = glm::vec3(10.0f);
    const int light = add_material(scene, panel);

    add_rect(scene, {-4.0f, 0.0f, 4.0f}, {8.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -8.0f}, {8.0f, 8.0f},
             floor_id);
    add_rect(scene, {-4.0f, 0.0f, -4.0f}, {8.0f, 0.0f, 0.0f}, {0.0f, 4.0f, 0.0f}, {8.0f, 4.0f},
             wall);
    const SphereTable table = make_sphere_table(48, 24);
    add_uv_sphere(scene, table, {-1.8f, 0.7f, 0.0f}, 0.7f, red);
    add_uv_sphere(scene, table, {0.0f, 0.7f, -1.2f}, 0.7f, green);
    add_uv_sphere(scene, table, {1.8f, 0.7f, 0.0f}, 0.7f, blue);
    add_box(scene, {1.0f, 0.0f, 1.6f}, glm::vec3(0.6f), dm::radians(25.0f), 1.0f, box_id);
    add_rect(scene, {-1.0f, 3.5f, -1.0f}, {2.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, {1.0f, 1.0f},
             light);

    scene.lights.push_back(point_light({3.0f, 3.0f, 3.0f}, glm::vec3(8.0f)));
    set_camera_path(
        scene, {{-1.0f, 1.6f, 6.5f}, {-0.3f, 1.5f, 6.4f}, {0.4f, 1.4f, 6.3f}, {1.0f, 1.3f, 6.2f}},
        {{0.0f, 0.4f, 0.0f}, {0.0f, 0.4f, 0.0f}, {0.0f, 0.35f, 0.0f}, {0.0f, 0.3f, 0.0f}}, 45.0f);
    finalize_scene(scene);
    return scene;
}

struct Entry {
    ProceduralSceneInfo info;
    Scene (*make)();
};

const std::vector<Entry>& entries() {
    static const std::vector<Entry> table = {
        {{"cornell",
          "Cornell box, 36 triangles: emissive ceiling panel, quad fill light, two boxes"},
         make_cornell},
        {{"sphere-grid",
          "10 x 10 UV spheres (diffuse and GGX) on a ground plane, 250 002 triangles"},
         make_sphere_grid},
        {{"million", "displaced sin/cos heightfield, 708 x 708 quads, 1 002 528 triangles"},
         make_million},
        {{"checker-room",
          "room with a fine 512 x 512 checkerboard (2-texel squares) on floor and walls: aliasing "
          "stress"},
         make_checker_room},
        {{"glossy-floor", "GGX floor (roughness 0.15) under diffuse spheres and an emissive panel"},
         make_glossy_floor},
    };
    return table;
}

}  // namespace

const std::vector<ProceduralSceneInfo>& procedural_scenes() {
    static const std::vector<ProceduralSceneInfo> infos = [] {
        std::vector<ProceduralSceneInfo> result;
        for (const Entry& entry : entries()) result.push_back(entry.info);
        return result;
    }();
    return infos;
}

bool is_procedural_scene(const std::string& name) {
    for (const Entry& entry : entries())
        if (entry.info.name == name) return true;
    return false;
}

Scene make_procedural_scene(const std::string& name) {
    for (const Entry& entry : entries())
        if (entry.info.name == name) return entry.make();
    std::string valid;
    for (const Entry& entry : entries()) valid += (valid.empty() ? "" : ", ") + entry.info.name;
    throw Error("unknown procedural scene '" + name + "'; valid names: " + valid);
}

}  // namespace fovref
