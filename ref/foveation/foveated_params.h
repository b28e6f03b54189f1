// The parameters of the foveated ray tracers (Lund Table 5.1; SPEC §12), typed and validated once
// per render: the pipeline (ref/modes) and the probe read the same struct. Each mode is a preset
// whose values are the parameters' defaults; `--param` overrides any of them.
//
//   preset  sigma  alpha  gaze_angle (a_G, rad)  lp_aspect  L
//   fov     0.75   1      0                      1.2        diagonal
//   kfov    1.0    3      0                      0.70       diagonal
//   cfov    1.4    1      0.20                   0.33       diagonal
//   ckfov   1.3    2      0.15                   0.35       diagonal
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ref/foveation/gaze_track.h"
#include "ref/foveation/log_polar.h"
#include "ref/scene/scene.h"
#include "ref/stage/params.h"

namespace fovref {

struct FoveationPreset {
    std::string name;    ///< the mode's name
    std::string source;  ///< e.g. "Lund Table 5.1"
    LogPolarParams map;
};

/// The log-polar presets fov, kfov, cfov, ckfov (Lund Table 5.1), in that order.
const std::vector<FoveationPreset>& foveation_presets();
/// Throws fovref::Error for an unknown name.
const FoveationPreset& find_foveation_preset(const std::string& name);

struct FoveatedParams {
    LogPolarParams map;
    /// The gaze point in screen pixels (`gaze=X,Y`, any finite point); empty: the screen centre.
    std::optional<glm::vec2> gaze;
    /// A recorded gaze path (`gaze_track=FILE`, ref/foveation/gaze_track.h); empty: none.
    std::vector<GazeSample> gaze_track;
    /// Lund §3.5's Gaussian lerp after pass 2 (`filters=lerp`); off by default, as in Lund's
    /// error measurements (§5.3.4).
    bool gaussian_lerp = false;
};

/// The parameter list of a foveated mode, with the preset's values as defaults.
std::vector<ParamSpec> foveated_param_specs(const FoveationPreset& preset);

/// Parses and validates; throws fovref::Error naming the parameter.
FoveatedParams parse_foveated_params(const Params& params, const FoveationPreset& preset);

/// The gaze of frame `frame` on a W x H screen: the gaze track's, else the given point, else the
/// centre (W/2, H/2).
glm::vec2 gaze_point(const FoveatedParams& params, int width, int height, int frame);

/// The log-polar map of a W x H frame: the parameters' map, the gaze point and the viewing
/// distance of the scene's display model for the camera (docs/foveation.md).
LogPolarMap foveated_map(const FoveatedParams& params, const Scene& scene, const Camera& camera,
                         int width, int height, int frame);

}  // namespace fovref
