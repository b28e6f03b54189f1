// The parameters of the Visual-Polar and screen-space sparse modes (Koskela P3-P5; SPEC §5.3-5.5,
// §6, §12; docs/visual-polar.md), typed and validated once per render. Each mode's defaults are
// its preset's:
//
//   mode                buffer                 sampling                      after
//   visual-polar        round(W/1.5) x         every traced texel, path      BMFR on the buffer,
//                       round(H/1.5)           traced                        phi-mip resolve, blur
//   visual-polar-basic  as visual-polar        every traced texel, basic     phi-mip resolve, blur
//   linear-falloff      the screen             pixel p with L(e): 10, 20,    push-pull fill
//                                              0.2 (path traced)             (BMFR optional)
//   acuity              the screen             N = 10% of W x H samples per  progressive mean,
//                                              frame at P(r2) (path traced)  unsampled black
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "ref/filters/blur_ramp.h"
#include "ref/gaze/gaze_track.h"
#include "ref/scene/scene.h"
#include "ref/stage/params.h"
#include "ref/visual_polar/map.h"
#include "ref/visual_polar/sparse_sampling.h"

namespace fovref {

struct SparseParams {
    /// The gaze point (`gaze=X,Y`); empty: the screen centre.
    std::optional<glm::vec2> gaze;
    std::vector<GazeSample> gaze_track;  ///< `gaze_track=FILE`
    // Visual-Polar
    int buffer_width = 0, buffer_height = 0;  ///< 0: the preset, round(W/1.5), round(H/1.5)
    bool mip_resolve = true;                  ///< `resolve=mip` (phi mips), else `bilinear`
    /// `blur=on`: the P5 blur ramp after pass 2 (Visual-Polar, default on) or on the final
    /// image (linear fall-off, default off)
    bool blur = true;
    /// BMFR's staircase clip (`vp_clip=staircase` with `denoise=bmfr`, P5 Fig. 4b): the BMFR
    /// block edge (`bmfr_block`, 32 or 64) the fovea's row counts follow; 0: the triangular clip
    int staircase_block = 0;
    BlurRamp ramp;  ///< `blur_sigma_deg`, `blur_full_deg`
    // linear fall-off
    LinearFalloff falloff;  ///< `falloff_fovea_deg`, `falloff_periphery_deg`, `falloff_min`
    // acuity
    int samples = 0;          ///< `samples` per frame; 0: 10% of W x H
    bool progressive = true;  ///< `progressive=on`: accumulate over frames
    bool fill = false;        ///< `fill=push-pull` (linear-falloff default), `black` (acuity)
    /// `eccentricity=exact` (default, both sparse modes) or `linear` (EccentricityModel)
    bool exact_eccentricity = true;
};

/// The parameters of mode `mode` (visual-polar, visual-polar-basic, linear-falloff, acuity).
std::vector<ParamSpec> sparse_param_specs(const std::string& mode);
/// Parses and validates; throws fovref::Error naming the parameter.
SparseParams parse_sparse_params(const Params& params, const std::string& mode);

/// The gaze of frame `frame` on a W x H screen: the track's, else the point, else the centre.
glm::vec2 sparse_gaze(const SparseParams& params, int width, int height, int frame);

/// The Visual-Polar map of a frame (the buffer size of the parameters or the preset).
VisualPolarMap sparse_vp_map(const SparseParams& params, int width, int height, int frame);

/// The display model's pixels per degree at the gaze: d_px pi / 180 (SPEC §1, §5.5).
float sparse_pixels_per_degree(const Scene& scene, const Camera& camera, int width, int height);
/// The sparse modes' eccentricity model of a frame: the parameter's choice with the display
/// model's d_px.
EccentricityModel sparse_eccentricity(const SparseParams& params, const Scene& scene,
                                      const Camera& camera, int width, int height);

/// Samples per frame of the acuity mode: `samples`, or 10% of W x H (at least 1).
int acuity_samples_per_frame(const SparseParams& params, int width, int height);

}  // namespace fovref
