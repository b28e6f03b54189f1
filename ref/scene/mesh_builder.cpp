#include "ref/scene/mesh_builder.h"

#include <cmath>

#include "ref/core/error.h"
#include "ref/core/limits.h"

namespace fovref {

namespace {

// Normals whose squared length is within this of 1 are kept as written (so an exported scene
// reloads bit-exactly); others are normalised. Float normalisation leaves |n|^2 - 1 within a
// few ulp (~2e-7), well inside it.
constexpr float unit_length_tolerance = 1e-6f;

}  // namespace

TransformCheck object_to_world(const glm::mat4& transform) {
    TransformCheck check;
    ObjectToWorld& to_world = check.to_world;
    to_world.identity = transform == glm::mat4(1.0f);
    to_world.transform = transform;
    const glm::mat3 linear(transform);
    const float determinant = glm::determinant(linear);
    check.finite = std::isfinite(determinant);
    check.singular = !(std::fabs(determinant) > 0.0f);
    if (check.finite && !check.singular) {
        to_world.normal_matrix = glm::transpose(glm::inverse(linear));
        to_world.mirror = determinant < 0.0f;
    }
    return check;
}

bool append_triangle(Scene& scene, WorldTriangle& t, std::int32_t material,
                     const std::string& file) {
    // Zero-area (or non-finite) triangles are dropped: they are never hit (SPEC §2).
    const float double_area = triangle_double_area(t.position[0], t.position[1], t.position[2]);
    if (!(double_area > 0.0f) || !std::isfinite(double_area)) {
        ++scene.load_stats.zero_area_triangles_dropped;
        return false;
    }
    const std::uint64_t limit = input_limits().max_scene_triangles;
    if (scene.material_ids.size() >= limit)
        check_limit(file + ": triangles of the scene", scene.material_ids.size() + 1, limit,
                    "triangles", "FOVREF_MAX_SCENE_TRIANGLES");
    const glm::vec3 geometric =
        glm::cross(t.position[1] - t.position[0], t.position[2] - t.position[0]) / double_area;
    bool generated = false;
    for (int c = 0; c < 3; ++c) {
        const float length2 = t.has_normal[c] ? glm::dot(t.normal[c], t.normal[c]) : 0.0f;
        if (!(length2 > 0.0f) || !std::isfinite(length2)) {
            t.normal[c] = geometric;
            generated = true;
        } else if (std::fabs(length2 - 1.0f) > unit_length_tolerance) {
            t.normal[c] = t.normal[c] / std::sqrt(length2);
        }
    }
    if (generated) ++scene.load_stats.normals_generated;
    for (int c = 0; c < 3; ++c) {
        scene.positions.push_back(t.position[c]);
        scene.normals.push_back(t.normal[c]);
        scene.uvs.push_back(t.uv[c]);
    }
    scene.material_ids.push_back(material);
    return true;
}

void note_dropped_total(Scene& scene, const std::string& file, std::int64_t dropped_in_file) {
    if (dropped_in_file > max_listed_warnings)
        scene.load_stats.warnings.push_back(file + ": " + std::to_string(dropped_in_file) +
                                            " zero-area triangles dropped (the first " +
                                            std::to_string(max_listed_warnings) + " are listed)");
}

}  // namespace fovref
