// The parameters of the foveated ray tracers (Lund Table 5.1, Meng ch. 3-4; SPEC §12), typed and
// validated once per render: the pipeline (ref/modes) and the probe read the same struct. Each
// mode is a preset whose values are the parameters' defaults; `--param` overrides any of them.
//
//   preset  sigma  alpha  a_G (rad)  lp_aspect  L         primary  resolve   filters
//   fov     0.75   1      0          1.2        diagonal  ray      bilinear  -
//   kfov    1.0    3      0          0.70       diagonal  ray      bilinear  -
//   cfov    1.4    1      0.20       0.33       diagonal  ray      bilinear  -
//   ckfov   1.3    2      0.15       0.35       diagonal  ray      bilinear  -
//   kfr     1.8    4      0          0 (off)    corners   raster   mip       internal_aa,post_aa
// (kfr's TAA comes with the temporal stages.)
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ref/gaze/gaze_track.h"
#include "ref/log_polar/map.h"
#include "ref/raster/rasterizer.h"
#include "ref/scene/scene.h"
#include "ref/stage/params.h"

namespace fovref {

struct FoveationPreset {
    std::string name;    ///< the mode's name
    std::string source;  ///< e.g. "Lund Table 5.1"
    LogPolarParams map;
    std::string primary = "ray";       ///< default of `primary`
    std::string resolve = "bilinear";  ///< default of `resolve`
    std::string filters;               ///< default of `filters`
};

/// The log-polar presets fov, kfov, cfov, ckfov (Lund Table 5.1) and kfr (Meng), in that order.
const std::vector<FoveationPreset>& foveation_presets();
/// Throws fovref::Error for an unknown name.
const FoveationPreset& find_foveation_preset(const std::string& name);

struct FoveatedParams {
    LogPolarParams map;
    /// The gaze point in screen pixels (`gaze=X,Y`, any finite point); empty: the screen centre.
    std::optional<glm::vec2> gaze;
    /// A recorded gaze path (`gaze_track=FILE`, ref/gaze/gaze_track.h); empty: none.
    std::vector<GazeSample> gaze_track;
    /// How the log-polar buffer's G-buffer is made: a ray per texel (`primary=ray`), or Meng's
    /// deferred sampling of the full-resolution rasterized G-buffer (`primary=raster`).
    bool deferred = false;
    RasterSettings raster;  ///< the rasterizer's fill rule (`fill_rule`, primary=raster)
    /// primary=raster with TAA jitter (`raster_jitter`): true (`raster`, default) jitters the
    /// rasterizer's samples and each texel copies the pixel whose jittered sample is nearest
    /// its point, so a static camera supersamples; false (`lookup`) leaves the rasterizer at the
    /// pixel centres and shifts the texels' points by the jitter (whole pixels change, no
    /// supersampling; what fovref did before). docs/foveation.md
    bool jitter_raster = true;
    bool mip_resolve = false;  ///< pass 2 with the mip pyramid (`resolve=mip`), else bilinear
    // Filters (`filters=a,b`): buffer space before pass 2, then screen space in this order.
    bool internal_aa = false;    ///< Meng's internal AA on the buffer's peripheral half
    bool gaussian_lerp = false;  ///< Lund §3.5's Gaussian lerp (off in Lund's error tests)
    bool post_aa = false;        ///< Meng's post-AA (eq. 2.14)
};

/// The parameter list of a foveated mode, with the preset's values as defaults.
std::vector<ParamSpec> foveated_param_specs(const FoveationPreset& preset);

/// Parses and validates; throws fovref::Error naming the parameter.
FoveatedParams parse_foveated_params(const Params& params, const FoveationPreset& preset);

/// The gaze of frame `frame` on a W x H screen: the gaze track's, else the given point, else the
/// centre (W/2, H/2).
glm::vec2 gaze_point(const FoveatedParams& params, int width, int height, int frame);

/// The buffer pass 2 reads: "lp_color", or "lp_color_aa" after the internal anti-aliasing.
std::string resolve_color_name(const FoveatedParams& params);

/// The screen-space buffers from pass 2 on, in pipeline order: pass 2's output ("resolved"),
/// with `taa` the TAA stage's ("taa_color", SPEC §6: TAA comes before the screen filters), then
/// each screen filter's ("lerp_filtered", "post_aa_filtered"); the last is renamed "final"
/// (pass 2 writes "final" itself when nothing follows).
std::vector<std::string> screen_chain(const FoveatedParams& params, bool taa = false);

/// The log-polar map of a W x H frame: the parameters' map, the gaze point and the viewing
/// distance of the scene's display model for the camera (docs/foveation.md).
LogPolarMap foveated_map(const FoveatedParams& params, const Scene& scene, const Camera& camera,
                         int width, int height, int frame);

}  // namespace fovref
