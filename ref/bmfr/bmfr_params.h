// The parameters of the modes that can denoise with BMFR (`pathtrace`; SPEC §9, docs/bmfr.md):
// `--param denoise=none|bmfr`, `bmfr_storage=half|float` and the reprojection limits.
#pragma once

#include <vector>

#include "ref/bmfr/bmfr.h"
#include "ref/stage/params.h"

namespace fovref {

struct BmfrSettings {
    bool enabled = false;  ///< denoise=bmfr
    BmfrParams params;
};

/// denoise, bmfr_storage, bmfr_position_limit_squared, bmfr_normal_limit_squared,
/// bmfr_emission.
std::vector<ParamSpec> bmfr_param_specs();
/// Throws fovref::Error naming the parameter; a bmfr_* parameter without denoise=bmfr is an
/// error (it would change nothing).
BmfrSettings parse_bmfr_params(const Params& params);

}  // namespace fovref
