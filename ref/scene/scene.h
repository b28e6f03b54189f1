// Scenes (SPEC §2): triangles with materials and textures, lights, a camera, an optional camera
// path, the display model and named presets. A Scene is plain data: the loader (scene_file.h) and
// the procedural generators (procedural.h) both produce one, and the exporter writes one back as
// OBJ + MTL + textures + JSON so other tools load exactly the same geometry.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ref/image/image.h"
#include "ref/scene/camera.h"

namespace fovref {

struct Material {
    std::string name;
    glm::vec3 albedo{0.8f};    ///< diffuse albedo, linear; multiplied by the texture when present
    int texture = -1;          ///< index into Scene::textures, -1 = none
    glm::vec3 emission{0.0f};  ///< emitted radiance, linear
    glm::vec3 specular{0.0f};  ///< GGX specular albedo; zero = purely diffuse
    float roughness = 1.0f;    ///< GGX roughness (alpha = roughness^2), used when specular > 0
    bool operator==(const Material&) const = default;
};

/// A texture: linear RGB floats (sRGB-decoded when loaded from an 8-bit file). Sampled
/// bilinearly with repeat wrap (SPEC §4); v = 0 is the bottom row of the file (OBJ convention).
struct Texture {
    std::string name;  ///< file name as given, or a generated name for procedural textures
    Image image;       ///< 3 channels
    bool operator==(const Texture&) const = default;
};

/// Area lights (quad, triangle) emit from the side their normal cross(edge_u, edge_v) points to.
struct Light {
    enum class Type { point, quad, triangle };
    Type type = Type::point;
    glm::vec3 position{0.0f};   ///< point: position; quad: corner; triangle: vertex 0
    glm::vec3 edge_u{0.0f};     ///< quad/triangle: first edge (vertex 1 - vertex 0)
    glm::vec3 edge_v{0.0f};     ///< quad/triangle: second edge (vertex 2 - vertex 0)
    glm::vec3 intensity{0.0f};  ///< point: radiant intensity (W/sr); area: emitted radiance
    int primitive = -1;         ///< triangle lights: the emissive triangle's index
    bool operator==(const Light&) const = default;
};

/// "point", "quad" or "triangle".
const char* light_type_name(Light::Type type);

/// What the loader dropped or repaired, so `fovref scene info` can say it.
struct SceneLoadStats {
    std::int64_t zero_area_triangles_dropped = 0;
    std::int64_t polygons_triangulated = 0;
    std::int64_t concave_polygons = 0;   ///< of those, split by ear clipping instead of a fan
    std::int64_t normals_generated = 0;  ///< triangles that had no vertex normals
    std::int64_t points_ignored = 0;     ///< OBJ "p" / glTF point primitives (not rendered)
    std::int64_t lines_ignored = 0;      ///< OBJ "l" / glTF line primitives (not rendered)
    std::vector<std::string> warnings;   ///< file:line: message
    /// What a bare model file did not give and the loader chose (camera, light), or what the
    /// command line replaced (--camera): "camera: ...", "light: ...".
    std::vector<std::string> defaulted;
    /// Features of the file the loader does not represent, and what it did instead (glTF).
    std::vector<std::string> unsupported;
    bool operator==(const SceneLoadStats&) const = default;
};

struct Bounds {
    glm::vec3 min{0.0f};
    glm::vec3 max{0.0f};
    bool operator==(const Bounds&) const = default;
};

/// Triangle data is stored per corner (three entries per triangle) so that a triangle is
/// self-contained: corner k of triangle t is element 3t + k.
struct Scene {
    std::string name;
    std::string source;  ///< file path, or "procedural:<name>"

    std::vector<glm::vec3> positions;        ///< 3 per triangle, world space
    std::vector<glm::vec3> normals;          ///< 3 per triangle, unit shading normals
    std::vector<glm::vec2> uvs;              ///< 3 per triangle (0,0 when the mesh has none)
    std::vector<std::int32_t> material_ids;  ///< 1 per triangle

    std::vector<Material> materials;
    std::vector<Texture> textures;
    std::vector<Light> lights;  ///< explicit lights, then one per emissive triangle

    Camera camera;
    std::vector<CameraKey> camera_path;  ///< empty = static camera
    DisplayModel display;
    float scene_scale = 1.0f;  ///< length of the bounds' diagonal (shadow-ray epsilon, SPEC §3)

    /// Named parameter presets from the scene file: preset name -> JSON object text.
    std::map<std::string, std::string> presets;

    SceneLoadStats load_stats;

    std::size_t triangle_count() const { return material_ids.size(); }
    bool operator==(const Scene&) const = default;
};

/// Axis-aligned bounds of all triangle corners (zero bounds for an empty scene).
Bounds scene_bounds(const Scene& scene);

/// Appends one light per triangle whose material emits, recomputes scene_scale, and checks the
/// invariants (array sizes, material and texture indices, finite values); throws on violation.
void finalize_scene(Scene& scene);

/// Camera at `time` along the path (clamped to its ends); the scene camera when there is none.
Camera camera_at(const Scene& scene, float time);

/// Twice the area of a triangle, in float (|cross(b - a, c - a)|): zero-area triangles are those
/// where this is 0 or not finite.
float triangle_double_area(glm::vec3 a, glm::vec3 b, glm::vec3 c);

/// The four texels sample_texture_bilinear reads and its lerp fractions: the result is
/// lerp(lerp(t(x0,y0), t(x1,y0), tx), lerp(t(x0,y1), t(x1,y1), tx), ty), i.e. texel weights
/// (1-tx)(1-ty), tx(1-ty), (1-tx)ty, tx ty. `valid` is false for non-finite uv (result 0).
struct BilinearTaps {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    float tx = 0.0f, ty = 0.0f;
    bool valid = false;
};
BilinearTaps bilinear_taps(const Texture& texture, glm::vec2 uv);

/// What sample_texture_bilinear computed (for `fovref probe`): its taps, the four texels, and the
/// two lerps in x (top = texel0 (1 - tx) + texel1 tx, bottom likewise) before the lerp in y.
struct BilinearTrace {
    BilinearTaps taps;
    glm::vec3 texels[4]{};  ///< (x0, y0), (x1, y0), (x0, y1), (x1, y1)
    glm::vec3 top{0.0f}, bottom{0.0f};
};

/// Bilinear texture lookup with repeat wrap; (u, v) in OBJ convention (v up). `trace`, when
/// given, receives what it computed.
glm::vec3 sample_texture_bilinear(const Texture& texture, glm::vec2 uv,
                                  BilinearTrace* trace = nullptr);

}  // namespace fovref
