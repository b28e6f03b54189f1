// Gupta's barrel distortion (Gupta 2019 §3; SPEC §6 "Barrel distortion"): an option of the stereo
// pass 2 that pre-distorts each eye's image for an HMD lens. Per eye, a point c of the eye's
// W/2 x H image is resolved from its source
//   q = (c - eye centre) / (W/4)            (the eye's half-width is 1)
//   s = eye centre + (W/4) q (1 + k1 |q|^2 + k2 |q|^4)
// binary32 in that order (|q|^2 = q.x q.x + q.y q.y, |q|^4 = |q|^2 |q|^2); defaults k1 = 0.22,
// k2 = 0.24 (choice). A source outside the eye's image is black (the caller's test).
#pragma once

#include <glm/glm.hpp>

namespace fovref {

/// The barrel distortion's source point for eye-local point c of a W/2 x H eye.
glm::vec2 barrel_source(glm::vec2 c, int eye_width, int height, float k1, float k2);

}  // namespace fovref
