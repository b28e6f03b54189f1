#include "ref/visual_polar/params.h"

#include <cmath>

#include "ref/core/block_offsets.h"
#include "ref/core/error.h"
#include "ref/core/limits.h"
#include "ref/visual_polar/map.h"

namespace fovref {

std::vector<ParamSpec> sparse_param_specs(const std::string& mode) {
    std::vector<ParamSpec> specs = gaze_param_specs();
    if (mode == "visual-polar" || mode == "visual-polar-basic") {
        specs.push_back({"buffer_width", "0",
                         "Visual-Polar buffer columns w (rho); 0: round(W / 1.5) (P5's preset)"});
        specs.push_back({"buffer_height", "0",
                         "Visual-Polar buffer rows h (phi); 0: round(H / 1.5) (P5's preset)"});
        specs.push_back({"resolve", "mip",
                         "pass 2: 'mip' (per-column phi mips, trilinear; P5 §3.4) or 'bilinear'"});
        specs.push_back({"blur", "on", "the P5 blur ramp after pass 2: 'on' or 'off'"});
        if (mode == "visual-polar")
            specs.push_back(
                {"vp_clip", "staircase",
                 "the fovea's clip under BMFR: 'staircase' (P5 Fig. 4b: every column of a BMFR "
                 "block column has the rows of its last, and the steps move with the block "
                 "offsets) or 'triangle' (each column its own rows, as without BMFR); "
                 "docs/visual-polar.md"});
        specs.push_back({"blur_sigma_deg", "0.564",
                         "blur ramp: sigma (model degrees) from blur_full_deg on (P5 §3.5)"});
        specs.push_back({"blur_full_deg", "30",
                         "blur ramp: eccentricity (model degrees) where sigma reaches "
                         "blur_sigma_deg; 0 at the fovea edge P(u0) = 5.79"});
    }
    if (mode == "linear-falloff") {
        specs.push_back({"falloff_fovea_deg", "10",
                         "f_l: every pixel is sampled up to this eccentricity (degrees)"});
        specs.push_back({"falloff_periphery_deg", "20",
                         "p_l: the probability reaches falloff_min at this eccentricity"});
        specs.push_back({"falloff_min", "0.2", "P_p: the sampling probability beyond p_l"});
        specs.push_back({"blur", "off",
                         "the P5 blur ramp on the final image: 'on' (P5's linear fall-off with "
                         "blur, its geometry the Visual-Polar preset's for this screen and gaze) "
                         "or 'off'"});
        specs.push_back({"blur_sigma_deg", "0.564", "blur ramp: as in visual-polar"});
        specs.push_back({"blur_full_deg", "30", "blur ramp: as in visual-polar"});
        specs.push_back(
            {"fill", "push-pull", "unsampled pixels: 'push-pull' (Koskela §4.4.3) or 'black'"});
    }
    if (mode == "linear-falloff" || mode == "acuity")
        specs.push_back({"eccentricity", "exact",
                         "screen distance to degrees: 'exact' (atan(r / d_px), the display "
                         "model) or 'linear' (r / pixels per degree at the gaze); "
                         "docs/visual-polar.md"});
    if (mode == "acuity") {
        specs.push_back({"samples", "0", "samples per frame; 0: 10% of W x H"});
        specs.push_back({"progressive", "on",
                         "'on': each pixel shows the mean of every sample so far (P3); 'off': "
                         "this frame's samples only"});
        specs.push_back({"fill", "black", "pixels without a sample: 'black' (P3) or 'push-pull'"});
    }
    return specs;
}

namespace {

bool parse_fill(const Params& params, const std::vector<ParamSpec>& specs) {
    return params.get_choice(specs, "fill", {"push-pull", "black"}) == 0;
}

}  // namespace

SparseParams parse_sparse_params(const Params& params, const std::string& mode) {
    const std::vector<ParamSpec> specs = sparse_param_specs(mode);
    SparseParams p;
    parse_gaze_params(params, specs, p.gaze, p.gaze_track);
    if (mode == "visual-polar" || mode == "visual-polar-basic") {
        p.buffer_width = params.get_int(specs, "buffer_width", 0, 16384);
        p.buffer_height = params.get_int(specs, "buffer_height", 0, 16384);
        p.mip_resolve = params.get_choice(specs, "resolve", {"mip", "bilinear"}) == 0;
        p.blur = params.get_bool(specs, "blur");
        if (mode == "visual-polar") {
            const bool staircase =
                params.get_choice(specs, "vp_clip", {"staircase", "triangle"}) == 0;
            // BMFR's own parameters (denoise, bmfr_block) are validated by the BMFR stages;
            // the clip follows the blocks only when BMFR runs
            const auto raw = [&params](const char* key, const char* fallback) {
                return params.given(key) ? params.values().at(key) : std::string(fallback);
            };
            if (staircase && raw("denoise", "bmfr") == "bmfr")
                p.staircase_block = raw("bmfr_block", "32") == "64" ? 64 : 32;
        }
        p.ramp.sigma_deg = params.get_float(specs, "blur_sigma_deg", 0.0f, 10.0f);
        p.ramp.full_deg = params.get_float(specs, "blur_full_deg", 6.0f, 1000.0f);
    }
    if (mode == "linear-falloff") {
        p.falloff.fovea_deg = params.get_float(specs, "falloff_fovea_deg", 0.0f, 180.0f);
        p.falloff.periphery_deg = params.get_float(specs, "falloff_periphery_deg", 0.0f, 180.0f);
        p.falloff.periphery_probability = params.get_float(specs, "falloff_min", 0.0f, 1.0f);
        p.blur = params.get_bool(specs, "blur");
        p.ramp.sigma_deg = params.get_float(specs, "blur_sigma_deg", 0.0f, 10.0f);
        p.ramp.full_deg = params.get_float(specs, "blur_full_deg", 6.0f, 1000.0f);
        if (!(p.falloff.periphery_deg > p.falloff.fovea_deg))
            throw Error(
                "parameters 'falloff_periphery_deg' and 'falloff_fovea_deg': p_l must be "
                "greater than f_l");
        p.fill = parse_fill(params, specs);
    }
    if (mode == "linear-falloff" || mode == "acuity") {
        p.exact_eccentricity = params.get_choice(specs, "eccentricity", {"exact", "linear"}) == 0;
    }
    if (mode == "acuity") {
        p.samples = params.get_int(specs, "samples", 0, 1 << 28);
        p.progressive = params.get_bool(specs, "progressive");
        p.fill = parse_fill(params, specs);
    }
    return p;
}

glm::vec2 sparse_gaze(const SparseParams& params, int width, int height, int frame) {
    return gaze_of_frame(params.gaze, params.gaze_track, width, height, frame);
}

VisualPolarMap sparse_vp_map(const SparseParams& params, int width, int height, int frame) {
    const glm::ivec2 preset = visual_polar_buffer_size(width, height);
    const int w = params.buffer_width > 0 ? params.buffer_width : preset.x;
    const int h = params.buffer_height > 0 ? params.buffer_height : preset.y;
    check_limit("parameters 'buffer_width' x 'buffer_height': the Visual-Polar buffer",
                static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h),
                input_limits().max_image_pixels, "texels", "FOVREF_MAX_IMAGE_PIXELS");
    VisualPolarMap map =
        make_visual_polar_map(width, height, sparse_gaze(params, width, height, frame), w, h);
    if (params.staircase_block > 0) {
        map.staircase_block = params.staircase_block;
        map.staircase_offset = block_grid_offsets()[static_cast<std::size_t>(frame % 16)].x *
                               (params.staircase_block / 32);
    }
    return map;
}

float sparse_pixels_per_degree(const Scene& scene, const Camera& camera, int width, int height) {
    const float d_px = display_distance_px(scene.display, width, height, camera.vfov_deg);
    return d_px * 3.14159265358979323846f / 180.0f;
}

EccentricityModel sparse_eccentricity(const SparseParams& params, const Scene& scene,
                                      const Camera& camera, int width, int height) {
    return {params.exact_eccentricity,
            display_distance_px(scene.display, width, height, camera.vfov_deg)};
}

int acuity_samples_per_frame(const SparseParams& params, int width, int height) {
    if (params.samples > 0) {
        check_limit("parameter 'samples'", static_cast<std::uint64_t>(params.samples),
                    input_limits().max_image_pixels, "samples (texels of the sample G-buffer)",
                    "FOVREF_MAX_IMAGE_PIXELS");
        return params.samples;
    }
    const long long pixels = static_cast<long long>(width) * height;
    return static_cast<int>(std::max(1LL, (pixels + 5) / 10));
}

}  // namespace fovref
