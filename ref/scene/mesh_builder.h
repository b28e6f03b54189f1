// Triangles into a Scene: what the OBJ and glTF loaders share (internal to ref/scene). A loader
// builds each triangle in world space with ObjectToWorld, then append_triangle drops it when its
// area is zero, gives it its final normals and appends it, within the scene triangle limit.
#pragma once

#include <cstdint>
#include <string>

#include "ref/scene/scene.h"

namespace fovref {

/// How many warnings of one kind a loader lists per file before it gives only a total.
constexpr int max_listed_warnings = 5;

/// Object-to-world transform: positions by M, normals by the inverse transpose; a mirroring
/// transform (det < 0) swaps corners 1 and 2 to keep the winding (and the geometric normal)
/// facing the same way relative to the surface. With the identity, values are taken as they are.
struct ObjectToWorld {
    bool identity = true;
    glm::mat4 transform{1.0f};
    glm::mat3 normal_matrix{1.0f};
    bool mirror = false;

    glm::vec3 point(glm::vec3 p) const {
        return identity ? p : glm::vec3(transform * glm::vec4(p, 1.0f));
    }
    glm::vec3 normal(glm::vec3 n) const { return identity ? n : normal_matrix * n; }
};

/// The object-to-world transform of `transform`; `singular` tells a zero determinant, and
/// `finite` whether the determinant is finite (to_world is only usable when both are fine).
struct TransformCheck {
    ObjectToWorld to_world;
    bool singular = false;
    bool finite = true;
};
TransformCheck object_to_world(const glm::mat4& transform);

/// A triangle's corners in world space; normal[c] is used only where has_normal[c].
struct WorldTriangle {
    glm::vec3 position[3];
    glm::vec3 normal[3];
    glm::vec2 uv[3];
    bool has_normal[3];
};

/// Appends the triangle to the scene with material `material`, or drops it when its area
/// (triangle_double_area) is zero or not finite: then it counts it in
/// load_stats.zero_area_triangles_dropped and returns false (the caller names it in a warning).
/// Normals: as written when their squared length is within 1e-6 of 1 (so exported scenes reload
/// bit-exactly), normalised otherwise, the geometric normal cross(p1 - p0, p2 - p0) / |...| where
/// missing, zero or not finite (the triangle is counted in load_stats.normals_generated).
/// Throws "<file>: triangles of the scene: ..." beyond input_limits().max_scene_triangles.
bool append_triangle(Scene& scene, WorldTriangle& triangle, std::int32_t material,
                     const std::string& file);

/// The total after the first max_listed_warnings zero-area warnings of a file:
/// "<file>: N zero-area triangles dropped (the first 5 are listed)", when N > 5.
void note_dropped_total(Scene& scene, const std::string& file, std::int64_t dropped_in_file);

}  // namespace fovref
