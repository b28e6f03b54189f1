#include "ref/scene/camera.h"

#include <cmath>
#include <string>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/vec.h"

namespace fovref {

Camera look_at(glm::vec3 position, glm::vec3 target, glm::vec3 world_up, float vfov_deg) {
    if (!is_finite(position) || !is_finite(target) || !is_finite(world_up))
        throw Error("camera: position, target and up must be finite");
    if (!(vfov_deg > 0.0f && vfov_deg < 180.0f))
        throw Error("camera: vfov_deg must be in (0, 180), got " + std::to_string(vfov_deg));
    glm::vec3 to_target = target - position;
    float distance = glm::length(to_target);
    if (!(distance > 0.0f)) throw Error("camera: look_at target equals the position");
    Camera camera;
    camera.position = position;
    camera.forward = to_target / distance;
    glm::vec3 right = glm::cross(camera.forward, world_up);
    float right_length = glm::length(right);
    if (!(right_length > 1e-6f)) throw Error("camera: up vector is parallel to the view direction");
    camera.right = right / right_length;
    camera.up = glm::cross(camera.right, camera.forward);
    camera.vfov_deg = vfov_deg;
    return camera;
}

Camera camera_from_quat(glm::vec3 position, glm::quat orientation, float vfov_deg) {
    float norm = std::sqrt(glm::dot(orientation, orientation));
    if (!(norm > 0.0f) || !std::isfinite(norm))
        throw Error("camera: orientation quaternion is zero or not finite");
    glm::quat q = orientation / norm;
    Camera camera;
    camera.position = position;
    // Rotate the camera-frame axes; glm's quat * vec3 is plain arithmetic.
    camera.right = q * glm::vec3(1.0f, 0.0f, 0.0f);
    camera.up = q * glm::vec3(0.0f, 1.0f, 0.0f);
    camera.forward = q * glm::vec3(0.0f, 0.0f, -1.0f);
    camera.vfov_deg = vfov_deg;
    return camera;
}

glm::quat camera_orientation(const Camera& camera) {
    // Rotation matrix whose columns are the images of +x, +y, +z.
    glm::mat3 rotation(camera.right, camera.up, -camera.forward);
    return glm::quat_cast(rotation);  // arithmetic and sqrt only
}

float tan_half_vfov(const Camera& camera) { return dm::tan(dm::radians(camera.vfov_deg) * 0.5f); }

glm::vec3 primary_ray_direction(const Camera& camera, float tan_half, int width, int height,
                                float x, float y) {
    const float w = static_cast<float>(width);
    const float h = static_cast<float>(height);
    const float sx = ((2.0f * x) / w - 1.0f) * tan_half * (w / h);
    const float sy = ((2.0f * y) / h - 1.0f) * tan_half;
    glm::vec3 d = camera.forward + sx * camera.right - sy * camera.up;
    return d / std::sqrt(glm::dot(d, d));
}

bool project_to_screen(const Camera& camera, float tan_half, int width, int height, glm::vec3 p,
                       glm::vec2& screen, float& depth) {
    // Invert SPEC §1: d = F + sx R - sy U with sx = (2x/W - 1) tan (W/H), sy = (2y/H - 1) tan.
    const glm::vec3 d = p - camera.position;
    depth = glm::dot(d, camera.forward);
    if (!(depth > 0.0f)) return false;
    const float w = static_cast<float>(width), h = static_cast<float>(height);
    const float sx = glm::dot(d, camera.right) / depth;
    const float sy = -glm::dot(d, camera.up) / depth;
    screen.x = (sx / (tan_half * (w / h)) + 1.0f) * 0.5f * w;
    screen.y = (sy / tan_half + 1.0f) * 0.5f * h;
    return true;
}

float display_distance_px(const DisplayModel& display, int width, int height, float vfov_deg) {
    switch (display.kind) {
        case DisplayModel::Kind::field_of_view:
            return (static_cast<float>(height) * 0.5f) / dm::tan(dm::radians(vfov_deg) * 0.5f);
        case DisplayModel::Kind::diagonal: {
            float diagonal = std::sqrt(static_cast<float>(width) * static_cast<float>(width) +
                                       static_cast<float>(height) * static_cast<float>(height));
            return diagonal / dm::tan(dm::radians(display.max_view_angle_deg));
        }
        case DisplayModel::Kind::fixed: return display.distance_px;
    }
    return 0.0f;
}

// Slerp (Shoemake 1985): q(t) = (sin((1 - t) θ) a + sin(t θ) b) / sin θ, θ = acos(a·b), on the
// shorter arc (b negated when a·b < 0).
//
// Threshold: when a·b >= 1 - 1e-6 (θ <= 1.41e-3 rad between the quaternions) normalised lerp is
// used instead. There the slerp weights tend to (1 - t, t), and normalised lerp's angle differs
// from slerp's t θ by at most 0.016 θ³ <= 4.6e-11 rad, far below binary32 resolution; slerp
// itself would divide by a small sin θ computed from a float a·b that has lost most of its
// digits to the "1 -". The same branch takes a·b >= 1 (rounding of unit inputs) and NaN.
glm::quat slerp_deterministic(glm::quat a, glm::quat b, float t) {
    constexpr float nlerp_threshold = 1.0f - 1e-6f;
    float cos_angle = glm::dot(a, b);
    if (cos_angle < 0.0f) {  // shortest arc
        b = -b;
        cos_angle = -cos_angle;
    }
    glm::quat result;
    if (!(cos_angle < nlerp_threshold)) {
        result = a * (1.0f - t) + b * t;
    } else {
        const float angle = dm::acos(cos_angle);
        const float sin_angle = dm::sin(angle);
        result =
            a * (dm::sin((1.0f - t) * angle) / sin_angle) + b * (dm::sin(t * angle) / sin_angle);
    }
    const float norm = std::sqrt(glm::dot(result, result));
    return result / norm;
}

}  // namespace fovref
