// `fovref probe` on a pixel of a render with frustum culling (docs/frustum.md): the pixel's
// tile, its frustum, its culled tree, and the path from the root to the leaf its primary ray hits,
// with each node's test (Lund's d and bias, kept or culled, and the exact test's verdict).
#pragma once

#include "ref/frustum/stages.h"
#include "ref/scene/scene.h"
#include "ref/stage/probe.h"

namespace fovref {

void explain_frustum_pixel(const ProbeContext& context, const FrustumSettings& settings,
                           ProbeReport& report);

}  // namespace fovref
