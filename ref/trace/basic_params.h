// The parameters of the basic ray tracer (Lund §3.1), typed and validated once per render: the
// pipeline (ref/modes) and the probe's explanation read the same struct.
#pragma once

#include <vector>

#include "ref/raster/rasterizer.h"
#include "ref/stage/params.h"

namespace fovref {

/// How `basic` finds the surface at each pixel centre.
enum class PrimaryVisibility {
    ray,     ///< one ray per pixel centre through the BVH (ref/trace/raycast_gbuffer.h)
    raster,  ///< the rasterizer (ref/raster/rasterizer.h)
};

struct BasicParams {
    PrimaryVisibility primary = PrimaryVisibility::ray;  ///< --param primary=ray|raster
    RasterSettings raster;                               ///< --param fill_rule=d3d|gl
};

/// The parameter list of `basic`, with defaults and documentation (`fovref render --help`).
std::vector<ParamSpec> basic_param_specs();

/// Parses and validates basic's parameters; throws fovref::Error naming the parameter (an unknown
/// primary visibility; fill_rule given with primary=ray, where no rasterizer runs).
BasicParams parse_basic_params(const Params& params);

}  // namespace fovref
