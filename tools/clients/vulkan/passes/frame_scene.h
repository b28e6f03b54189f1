// The scene of the Vulkan client's end-to-end frame pass (passes/frame.cpp), read from a bundle's
// exported scene (`fovref golden export CASE DIR --with-scene`: DIR/scene/scene.json, one OBJ,
// its MTL and PFM textures; docs/scene-format.md). Written as a renderer's loader would be,
// depending on nothing of fovref's:
//
//   OBJ: v, vt, vn, f (3 or more corners v/t/n, fanned), usemtl, mtllib; triangle k of the file
//        is primitive id k. MTL: newmtl, Kd, Ke, map_Kd (a PFM); material k of the MTL is
//        material id k.
//   scene.json: the explicit lights (point, quad), then every triangle whose material emits
//        becomes a triangle light, in triangle order (docs/scene-format.md, "Lights").
//   scene scale: the length of the positions' bounding-box diagonal (1 when 0).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace fovref_client {

struct Vec3 {
    float x = 0.0f, y = 0.0f, z = 0.0f;
};
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

struct FrameTexture {
    int width = 0, height = 0;
    std::vector<float> rgb;  ///< top row first, 3 channels interleaved
};

struct FrameMaterial {
    std::string name;
    Vec3 albedo{0.8f, 0.8f, 0.8f};
    Vec3 emission;
    int texture = -1;  ///< index into FrameScene::textures, -1 without
};

struct FrameLight {
    enum Type : std::int32_t { point = 0, quad = 1, triangle = 2 };
    Type type = point;
    Vec3 position;   ///< point: position; quad: corner; triangle: corner 0
    Vec3 edge_u;     ///< quad, triangle
    Vec3 edge_v;     ///< quad, triangle
    Vec3 intensity;  ///< point: W/sr; area: emitted radiance
};

struct FrameScene {
    std::vector<Vec3> positions;  ///< 3 corners per triangle
    std::vector<Vec3> normals;    ///< 3 per triangle
    std::vector<float> uvs;       ///< 6 per triangle (u, v of each corner)
    std::vector<std::int32_t> material_ids;
    std::vector<FrameMaterial> materials;
    std::vector<FrameTexture> textures;
    std::vector<FrameLight> lights;
    float scene_scale = 1.0f;
    std::size_t triangles() const { return material_ids.size(); }
};

/// Loads `scene_json` (a bundle's scene/scene.json) and the OBJ, MTL and textures it names.
/// Throws std::runtime_error naming the file and what is wrong or unsupported.
FrameScene load_frame_scene(const std::string& scene_json);

}  // namespace fovref_client
