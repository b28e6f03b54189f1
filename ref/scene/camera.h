// Pinhole camera and display model (SPEC §1).
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace fovref {

/// Right-handed orthonormal frame: cross(right, up) = -forward (an OpenGL view looks down -z).
/// F points into the screen; screen x grows along R, screen y (down) along -U. The constructors
/// below keep the axes orthonormal.
struct Camera {
    glm::vec3 position{0.0f};
    glm::vec3 right{1.0f, 0.0f, 0.0f};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    glm::vec3 forward{0.0f, 0.0f, -1.0f};
    float vfov_deg = 60.0f;

    bool operator==(const Camera&) const = default;  ///< Bit-for-bit pose equality (SPEC §7).
};

/// Camera at `position` looking at `target` with the given world up (must not be parallel).
/// forward = normalize(target - position), right = normalize(cross(forward, up)),
/// up = cross(right, forward). Throws fovref::Error when degenerate.
Camera look_at(glm::vec3 position, glm::vec3 target, glm::vec3 world_up, float vfov_deg);

/// Camera from a unit quaternion: the rotation maps the camera frame's (+x, +y, -z) to
/// (right, up, forward), like an OpenGL view.
Camera camera_from_quat(glm::vec3 position, glm::quat orientation, float vfov_deg);
glm::quat camera_orientation(const Camera& camera);

/// tan(vfov/2), from the deterministic math.
float tan_half_vfov(const Camera& camera);

/// Primary ray direction through screen point (x, y) of a W x H screen (SPEC §1):
/// normalize(F + ((2x/W) - 1) tan(vfov/2) (W/H) R - ((2y/H) - 1) tan(vfov/2) U).
/// `tan_half` is tan_half_vfov(camera), passed in so a pass computes it once.
glm::vec3 primary_ray_direction(const Camera& camera, float tan_half, int width, int height,
                                float x, float y);

/// The inverse of primary_ray_direction: the screen point (x, y) whose primary ray passes
/// through world point p, and p's view depth. Returns false when p is not in front of the camera
/// (depth <= 0); the screen point may lie outside [0, W) x [0, H).
bool project_to_screen(const Camera& camera, float tan_half, int width, int height, glm::vec3 p,
                       glm::vec2& screen, float& depth);

/// View-space depth of world point p along F (SPEC §1, used by TAA).
inline float view_depth(const Camera& camera, glm::vec3 p) {
    return glm::dot(p - camera.position, camera.forward);
}

/// Display model (SPEC §1): viewing distance in pixels, for eccentricity angles.
struct DisplayModel {
    enum class Kind {
        field_of_view,  ///< d_px = (H/2) / tan(vfov/2): the display subtends the camera's FOV.
        diagonal,       ///< Lund §5.1.1: d_px = diagonal / tan(max_view_angle).
        fixed           ///< d_px given explicitly.
    };
    Kind kind = Kind::field_of_view;
    float max_view_angle_deg = 0.0f;  ///< for Kind::diagonal
    float distance_px = 0.0f;         ///< for Kind::fixed
    bool operator==(const DisplayModel&) const = default;
};

/// Viewing distance in pixels for a W x H screen and the camera's vfov.
float display_distance_px(const DisplayModel& display, int width, int height, float vfov_deg);

/// Camera path keyframe: position linearly interpolated, orientation by slerp (SPEC §2).
struct CameraKey {
    float time = 0.0f;
    glm::vec3 position{0.0f};
    glm::quat orientation{1.0f, 0.0f, 0.0f, 0.0f};
    bool operator==(const CameraKey&) const = default;
};

/// Deterministic quaternion slerp of unit quaternions, using dm::acos / dm::sin: shortest arc,
/// normalised lerp instead when a·b >= 1 - 1e-6 (the two are then equal to float precision).
glm::quat slerp_deterministic(glm::quat a, glm::quat b, float t);

}  // namespace fovref
