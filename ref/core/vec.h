// Small helpers on glm vectors shared across stages.
#pragma once

#include <cmath>

#include <glm/glm.hpp>

namespace fovref {

/// True when every component is finite (neither NaN nor infinite).
inline bool is_finite(glm::vec3 v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

}  // namespace fovref
