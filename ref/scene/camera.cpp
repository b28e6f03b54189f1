#include "ref/scene/camera.h"

#include <cmath>
#include <string>

#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

namespace {
bool finite3(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
}  // namespace

Camera look_at(glm::vec3 position, glm::vec3 target, glm::vec3 world_up, float vfov_deg) {
    if (!finite3(position) || !finite3(target) || !finite3(world_up))
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

glm::quat slerp_deterministic(glm::quat a, glm::quat b, float t) {
    float cos_angle = glm::dot(a, b);
    if (cos_angle < 0.0f) {  // shortest arc
        b = -b;
        cos_angle = -cos_angle;
    }
    glm::quat result;
    if (cos_angle > 1.0f - 5e-9f || !(cos_angle < 1.0f)) {
        result = a * (1.0f - t) + b * t;  // nearly parallel: normalised lerp
    } else {
        float angle = dm::acos(cos_angle);
        if (angle < 1e-4f) {
            result = a * (1.0f - t) + b * t;
        } else {
            float sin_angle = dm::sin(angle);
            float wa = dm::sin((1.0f - t) * angle) / sin_angle;
            float wb = dm::sin(t * angle) / sin_angle;
            result = a * wa + b * wb;
        }
    }
    float norm = std::sqrt(glm::dot(result, result));
    return result / norm;
}

}  // namespace fovref
