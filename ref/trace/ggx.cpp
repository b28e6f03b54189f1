#include "ref/trace/ggx.h"

#include <algorithm>
#include <cmath>

#include "ref/core/dmath.h"

namespace fovref {

namespace {

constexpr float pi = 3.14159265358979323846f;
constexpr float two_pi = 6.28318530717958647692f;

// Divisions by quantities that can reach 0 are guarded by this (SPEC §0).
constexpr float tiny = 1e-20f;

}  // namespace

float ggx_alpha(float roughness) { return std::clamp(roughness * roughness, 1e-3f, 1.0f); }

float ggx_d(glm::vec3 h, float alpha) {
    if (!(h.z > 0.0f)) return 0.0f;
    const float a2 = alpha * alpha;
    const float t = h.z * h.z * (a2 - 1.0f) + 1.0f;
    return a2 / std::max(pi * t * t, tiny);
}

float ggx_g1(glm::vec3 v, float alpha) {
    if (!(v.z > 0.0f)) return 0.0f;
    const float a2 = alpha * alpha;
    return 2.0f * v.z / (v.z + std::sqrt(a2 + (1.0f - a2) * v.z * v.z));
}

float ggx_g2(glm::vec3 l, glm::vec3 v, float alpha) {
    if (!(l.z > 0.0f) || !(v.z > 0.0f)) return 0.0f;
    const float a2 = alpha * alpha;
    const float lv = l.z * std::sqrt(a2 + (1.0f - a2) * v.z * v.z);
    const float vl = v.z * std::sqrt(a2 + (1.0f - a2) * l.z * l.z);
    return 2.0f * l.z * v.z / std::max(lv + vl, tiny);
}

glm::vec3 ggx_fresnel(glm::vec3 f0, float v_dot_h) {
    const float m = std::clamp(1.0f - v_dot_h, 0.0f, 1.0f);
    const float m5 = m * m * m * m * m;
    return f0 + (glm::vec3(1.0f) - f0) * m5;
}

glm::vec3 ggx_brdf(glm::vec3 l, glm::vec3 v, float alpha, glm::vec3 f0) {
    if (!(l.z > 0.0f) || !(v.z > 0.0f)) return glm::vec3(0.0f);
    const glm::vec3 sum = l + v;
    const float length2 = glm::dot(sum, sum);
    if (!(length2 > tiny)) return glm::vec3(0.0f);
    const glm::vec3 h = sum / std::sqrt(length2);
    const float scale = ggx_d(h, alpha) * ggx_g2(l, v, alpha) / (4.0f * l.z * v.z);
    return ggx_fresnel(f0, glm::dot(v, h)) * scale;
}

glm::vec3 ggx_sample_visible_normal(glm::vec3 v, float alpha, float u1, float u2) {
    // The view direction in the hemisphere configuration (alpha = 1).
    glm::vec3 vh{alpha * v.x, alpha * v.y, v.z};
    vh /= std::sqrt(glm::dot(vh, vh));
    // An orthonormal basis around it (T1 = (1, 0, 0) when vh is the normal).
    const float lensq = vh.x * vh.x + vh.y * vh.y;
    const glm::vec3 t1 = lensq > 0.0f ? glm::vec3(-vh.y, vh.x, 0.0f) / std::sqrt(lensq)
                                      : glm::vec3(1.0f, 0.0f, 0.0f);
    const glm::vec3 t2 = glm::cross(vh, t1);
    // A point on the projected disk, warped to the visible half.
    const float r = std::sqrt(u1);
    const float phi = two_pi * u2;
    const float p1 = r * dm::cos(phi);
    float p2 = r * dm::sin(phi);
    const float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
    const glm::vec3 nh =
        t1 * p1 + t2 * p2 + vh * std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2));
    // Back to the ellipsoid configuration.
    glm::vec3 ne{alpha * nh.x, alpha * nh.y, std::max(0.0f, nh.z)};
    return ne / std::sqrt(glm::dot(ne, ne));
}

float ggx_pdf(glm::vec3 l, glm::vec3 v, float alpha) {
    if (!(l.z > 0.0f) || !(v.z > 0.0f)) return 0.0f;
    const glm::vec3 sum = l + v;
    const float length2 = glm::dot(sum, sum);
    if (!(length2 > tiny)) return 0.0f;
    const glm::vec3 h = sum / std::sqrt(length2);
    const float v_dot_h = glm::dot(v, h);
    if (!(v_dot_h > 0.0f)) return 0.0f;
    const float pdf_h = ggx_g1(v, alpha) * v_dot_h * ggx_d(h, alpha) / v.z;
    return pdf_h / (4.0f * v_dot_h);
}

}  // namespace fovref
