// `fovref probe` explanations of the basic and ground-truth ray tracers (ModeInfo::explain): the
// values come from the passes' own per-pixel functions (raster_fragment, depth_test,
// raycast_gbuffer_pixel, gbuffer_surface, shade_basic_pixel, ground_truth_pixel), and every value
// the pass also wrote is checked against the rendered buffer bit for bit.
#pragma once

#include <string>

#include "ref/bvh/bvh.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/surface.h"
#include "ref/stage/probe.h"

namespace fovref {

void explain_basic(const ProbeContext& context, ProbeReport& report);

// Pieces the foveated modes' explanations reuse.

/// Channels 0..2 of buffer `name` of `frame` at (x, y); NaN when it is missing.
glm::vec3 probe_rgb(const FrameResult& frame, const std::string& name, int x, int y);
/// The surface's attributes, material and texture lookup (the sampler's own record).
void explain_surface(const Scene& scene, const SurfacePoint& surface, ProbeSection& section);
/// "check: <what>: bit-identical to the rendered buffer" or "DIFFERS ..." (then the report is
/// marked inconsistent).
void probe_check(ProbeReport& report, ProbeSection& section, const std::string& what,
                 glm::vec3 mine, glm::vec3 rendered);
/// True when every G-buffer channel but motion of `mine` at (x, y) has the bits of the rendered
/// buffer named prefix + channel ("gbuffer_view_depth", ...).
bool probe_same_gbuffer(const GBuffer& mine, const FrameResult& frame, const std::string& prefix,
                        int x, int y);
/// The same for `mine` at (x, y) against the rendered buffers at (rx, ry) (a texel against the
/// screen pixel it was sampled from).
bool probe_same_gbuffer(const GBuffer& mine, int x, int y, const FrameResult& frame,
                        const std::string& prefix, int rx, int ry);
/// The shading pass's own per-pixel function (shade_basic_pixel) at (x, y) of the rendered
/// G-buffer named prefix + "world_position", ... (its light samples and random numbers), checked
/// against buffer `color` at (x, y). `window`: where that buffer lies on the screen (null: it is
/// its own screen), as the pass was given it.
void explain_shade_at(const ProbeContext& context, const Bvh& bvh, const std::string& prefix,
                      const std::string& color, int x, int y, ProbeSection& section,
                      ProbeReport& report, const ScreenWindow* window = nullptr);
void explain_ground_truth(const ProbeContext& context, ProbeReport& report);

}  // namespace fovref
