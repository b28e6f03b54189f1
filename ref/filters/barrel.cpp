#include "ref/filters/barrel.h"

namespace fovref {

glm::vec2 barrel_source(glm::vec2 c, int eye_width, int height, float k1, float k2) {
    const float half = static_cast<float>(eye_width) * 0.5f;
    const glm::vec2 centre{half, static_cast<float>(height) * 0.5f};
    const glm::vec2 q = (c - centre) / half;
    const float q2 = q.x * q.x + q.y * q.y;
    const float scale = 1.0f + k1 * q2 + k2 * (q2 * q2);
    return centre + half * (q * scale);
}

}  // namespace fovref
