// `fovref probe` explanations of the basic and ground-truth ray tracers (ModeInfo::explain): the
// values come from the passes' own per-pixel functions (raster_fragment, depth_test,
// raycast_gbuffer_pixel, gbuffer_surface, shade_basic_pixel, ground_truth_pixel), and every value
// the pass also wrote is checked against the rendered buffer bit for bit.
#pragma once

#include "ref/stage/probe.h"

namespace fovref {

void explain_basic(const ProbeContext& context, ProbeReport& report);
void explain_ground_truth(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
