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
/// `denoise_default`: the mode's default ("none"; "bmfr" for visual-polar).
std::vector<ParamSpec> bmfr_param_specs(const char* denoise_default = "none");
/// Throws fovref::Error naming the parameter; a bmfr_* parameter without denoise=bmfr is an
/// error (it would change nothing).
BmfrSettings parse_bmfr_params(const Params& params, const char* denoise_default = "none");

}  // namespace fovref
