// Camera helpers (SPEC §1, §2): the deterministic quaternion slerp of camera paths.
#include <doctest/doctest.h>

#include <cmath>
#include <initializer_list>

#include "ref/scene/camera.h"

using namespace fovref;

namespace {

// Largest component difference, with q and -q (the same rotation) not identified: slerp must
// return the endpoints themselves, not their negatives.
float max_difference(glm::quat a, glm::quat b) {
    return std::fmax(std::fmax(std::fabs(a.x - b.x), std::fabs(a.y - b.y)),
                     std::fmax(std::fabs(a.z - b.z), std::fabs(a.w - b.w)));
}

// Rotation by `angle` radians about the unit `axis` (libm is fine in tests).
glm::quat rotation(float angle, glm::vec3 axis) {
    const double half = 0.5 * static_cast<double>(angle);
    const float s = static_cast<float>(std::sin(half));
    return glm::quat(static_cast<float>(std::cos(half)), s * axis.x, s * axis.y, s * axis.z);
}

}  // namespace

TEST_CASE("slerp_deterministic: endpoints, midpoint, nearly equal inputs") {
    const float pi_f = 3.14159265358979f;
    const glm::quat a = rotation(0.3f, glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f)));
    const glm::quat b = rotation(1.2f, glm::normalize(glm::vec3(-1.0f, 0.5f, 0.2f)));

    SUBCASE("t = 0 and t = 1 give the endpoints") {
        // 1e-7: the weights sin(θ)/sin(θ) and sin(0)/sin(θ) are exact, so only the final
        // normalisation of an already unit quaternion rounds (~1 ulp = 6e-8 on components < 1).
        CHECK(max_difference(slerp_deterministic(a, b, 0.0f), a) <= 1e-7f);
        CHECK(max_difference(slerp_deterministic(a, b, 1.0f), b) <= 1e-7f);
        // Shortest arc: -b is the same rotation as b; the path takes the short way and ends
        // at b, in a's hemisphere (a·b > 0 here).
        REQUIRE(glm::dot(a, b) > 0.0f);
        CHECK(max_difference(slerp_deterministic(a, -b, 1.0f), b) <= 1e-7f);
    }
    SUBCASE("the midpoint of a 90 degree rotation is the 45 degree rotation") {
        const glm::vec3 axis = glm::normalize(glm::vec3(0.0f, 1.0f, 1.0f));
        const glm::quat identity(1.0f, 0.0f, 0.0f, 0.0f);
        const glm::quat mid = slerp_deterministic(identity, rotation(pi_f / 2.0f, axis), 0.5f);
        // 1e-6: dm::sin/acos are within a few ulp in float, the weights carry ~1e-7 relative
        // error, the components are < 1.
        CHECK(max_difference(mid, rotation(pi_f / 4.0f, axis)) <= 1e-6f);
        // Quarter points along the same axis, through the slerp branch.
        CHECK(max_difference(slerp_deterministic(identity, rotation(pi_f / 2.0f, axis), 0.25f),
                             rotation(pi_f / 8.0f, axis)) <= 1e-6f);
    }
    SUBCASE("nearly identical quaternions give a finite unit result") {
        // Identical inputs, inputs one ulp apart, and a pair just on either side of the
        // normalised-lerp threshold a·b = 1 - 1e-6 (θ = 1.41e-3 rad).
        struct Case {
            glm::quat p, q;
            float angle;  // rotation angle from p to q about `axis` (0: p itself is expected)
        };
        const glm::quat a_ulp(std::nextafter(a.w, 2.0f), a.x, a.y, a.z);
        const glm::vec3 axis = glm::normalize(glm::vec3(0.3f, -0.2f, 0.9f));
        const glm::quat identity(1.0f, 0.0f, 0.0f, 0.0f);
        const Case cases[] = {{a, a, 0.0f},
                              {a, a_ulp, 0.0f},
                              {identity, rotation(2.8e-3f, axis), 2.8e-3f},
                              {identity, rotation(2.9e-3f, axis), 2.9e-3f}};
        for (const Case& c : cases) {
            for (float t : {0.0f, 0.3f, 0.5f, 1.0f}) {
                const glm::quat r = slerp_deterministic(c.p, c.q, t);
                INFO("t = " << t << ", a.b = " << glm::dot(c.p, c.q));
                REQUIRE((std::isfinite(r.x) && std::isfinite(r.y) && std::isfinite(r.z) &&
                         std::isfinite(r.w)));
                // 1e-6: |r|^2 after dividing by a float norm is 1 within a few ulp (~2e-7).
                CHECK(std::fabs(glm::dot(r, r) - 1.0f) <= 1e-6f);
                // On either side of the threshold the result is the rotation by t·angle
                // (nlerp's angle error there is < 5e-11 rad; 1e-6 allows for float rounding).
                const glm::quat expected = c.angle == 0.0f ? c.p : rotation(t * c.angle, axis);
                CHECK(max_difference(r, expected) <= 1e-6f);
            }
        }
    }
}
