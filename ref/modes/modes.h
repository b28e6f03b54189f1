// The registry of render modes: the one place that knows every mode, a plain list of the modes
// each family file describes (ray_tracing.h, log_polar.h, visual_polar.h, building_blocks.h:
// its stages, parameters, presets and buffer spaces). Each mode is a pipeline of stages wired
// from the stage folders below (ref/raster, ref/trace, ref/log_polar, ref/visual_polar,
// ref/filters, ref/temporal, ref/bmfr, ref/building_blocks); the stage framework (ref/stage)
// knows none of them.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "ref/golden/bundle.h"
#include "ref/stage/pipeline.h"
#include "ref/stage/probe.h"

namespace fovref {

/// Every render mode, in the order `fovref render --help` lists them.
const std::vector<ModeInfo>& render_modes();
/// Throws fovref::Error listing the valid names.
const ModeInfo& find_mode(const std::string& name);

/// True when frame f of `mode` with these parameters depends on frame f - 1 (a stateful mode, or
/// TAA or BMFR turned on), so it renders alone only with the previous frame's dump (--resume).
bool carries_state(const ModeInfo& mode, const Params& params);

/// render_each / render / probe_pixel of ref/stage for the mode named `mode`.
std::vector<std::string> render_each(const Scene* scene, const std::string& mode,
                                     const RenderSettings& settings,
                                     const std::function<void(FrameResult&)>& on_frame);
std::vector<FrameResult> render(const Scene* scene, const std::string& mode,
                                const RenderSettings& settings);
ProbeReport probe_pixel(const Scene* scene, const std::string& mode, const RenderSettings& settings,
                        int frame, int x, int y, std::optional<glm::ivec2> texel = std::nullopt,
                        int eye = -1);

/// Renders a golden case (ref/golden/bundle.h), keeping every frame.
std::vector<FrameResult> render_golden_case(const GoldenCase& golden_case, const Scene* scene,
                                            const std::vector<std::string>& requested,
                                            const std::function<void(double)>& progress = {});

}  // namespace fovref
