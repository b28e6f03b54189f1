// Small helpers on glm vectors shared across stages.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace fovref {

/// True when every component is finite (neither NaN nor infinite).
inline bool is_finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// The centre of pixel (x, y) (SPEC §1: pixel (i, j) covers [i, i+1) x [j, j+1)), or of texel
/// (i, j) of a buffer (SPEC §5: centres at (i + 1/2, j + 1/2)): (x + 1/2, y + 1/2) in binary32.
inline glm::vec2 pixel_centre(int x, int y) {
    return {static_cast<float>(x) + 0.5f, static_cast<float>(y) + 0.5f};
}

/// The distance r = |p - g| from the gaze point g in binary32: sqrt(x' x' + y' y'). The one
/// distance every foveated pass uses (the gaze circle's test, the forward map, the filters' ramps).
inline float gaze_distance(glm::vec2 gaze, glm::vec2 p) {
    const float dx = p.x - gaze.x, dy = p.y - gaze.y;
    return std::sqrt(dx * dx + dy * dy);
}

}  // namespace fovref
