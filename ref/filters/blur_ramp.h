// The P5 blur ramp (Koskela P5 §3.5; SPEC §6 "P5 blur ramp"): a screen-space Gaussian blur
// whose width grows with eccentricity, to hide the Visual-Polar resolve's aliasing in the
// periphery. Two separable passes, horizontal then vertical, with a per-pixel sigma.
//
// Sigma (blur_ramp_sigma_px), binary32, at a screen point p (a pixel centre (x + 1/2, y + 1/2)):
//   e = sqrt(dx^2 + dy^2) / s, (dx, dy) = p - g, s = geometry.scale (pixels per model degree);
//   e_f = geometry.fovea_deg (the Visual-Polar map's P(u0) = 5.79 model degrees: the fovea
//   edge; blur_ramp_geometry in ref/visual_polar/map.h);
//   sigma(e) = 0 for e <= e_f;
//            = sigma_deg * (e - e_f) / (full_deg - e_f) for e_f < e < full_deg;
//            = sigma_deg for e >= full_deg (choice: constant beyond, SPEC);
//   sigma_px = sigma(e) * s. Defaults sigma_deg = 0.564, full_deg = 30 (P5: 6.8 px at
//   12.05 px/degree).
// Radius (blur_ramp_radius): R = min(ceil(3 sigma_px), blur_ramp_max_radius = 64) (choice: the cap
//   bounds the work; it binds only where sigma_px > 21.3, i.e. s > 37.8 px/degree with the
//   defaults; the taps kept are still normalised). sigma_px <= 0 (R = 0): the pixel is copied.
// One pass (blur_ramp_horizontal; blur_ramp_vertical is the same along y), output pixel (x, y):
//   sigma_px at the output pixel's centre (the same value in both passes);
//   taps d = -R .. R in that order, source pixel clamp(x + d, 0, W - 1) (clamp to edge);
//   weights w_d = a^(d^2) for d = 0 .. R, a = dm::exp(-1 / (2 sigma_px^2)) (one exp per pixel;
//     2 sigma_px^2 rounded as (2 sigma_px) sigma_px), by the recurrence w_0 = 1,
//     w_d = w_(d-1) g_d with g_1 = a, g_(d+1) = g_d (a a) (relative error below 1e-5 for
//     R <= 64); w_-d = w_d bit for bit;
//   normalised: W = sum of w_d over d = -R .. R in that order, each w_d times 1 / W;
//   out = sum over d = -R .. R (in that order) of w_d c_d, binary32, per channel (a constant
//     comes back within a few ulps).
// blur_ramp = blur_ramp_vertical(blur_ramp_horizontal(image)). Any channel count.
#pragma once

#include <memory>

#include <glm/glm.hpp>

#include "ref/image/image.h"

namespace fovref {

/// The ramp's parameters (SPEC §6): sigma in model degrees, reached at `full_deg` and kept.
struct BlurRamp {
    float sigma_deg = 0.564f;  ///< sigma beyond full_deg, model degrees
    float full_deg = 30.0f;    ///< eccentricity where the ramp reaches sigma_deg, model degrees
    bool operator==(const BlurRamp&) const = default;
};

/// Where the ramp is measured from, on a W x H screen: the gaze, the screen's pixels per model
/// degree and the fovea edge in model degrees (the Visual-Polar map's, blur_ramp_geometry).
struct BlurRampGeometry {
    int screen_width = 0, screen_height = 0;
    glm::vec2 gaze{0.0f};
    float scale = 1.0f;      ///< s, pixels per model degree
    float fovea_deg = 0.0f;  ///< e_f, model degrees
    bool operator==(const BlurRampGeometry&) const = default;
};

struct BlurRampPlan;  // blur_ramp.cpp

/// Each pixel's sigma_px and a = dm::exp(-1 / (2 sigma_px^2)) (0 where the radius is 0) for one
/// ramp and geometry, which the blur stages keep while both stay the same (a static gaze): the
/// AVX passes then read them instead of computing an exp per pixel, the same bits. A table kept
/// for more than one frame can also hold the AVX passes' plan (add_blur_ramp_plan): each
/// group's decision (copied, summed alike, summed lane by lane, with its radii) and the weights
/// it uses, made once, which both passes then replay (the same bits as deciding and making them
/// again, group by group, which a pass does without a plan).
struct BlurRampTable {
    BlurRamp ramp;
    BlurRampGeometry geometry;
    Image sigma_a;                             ///< W x H x 2: sigma_px, a
    std::shared_ptr<const BlurRampPlan> plan;  ///< the AVX passes' plan, or null
    bool made_for(const BlurRamp& ramp, const BlurRampGeometry& geometry) const;
};
BlurRampTable blur_ramp_table(const BlurRamp& ramp, const BlurRampGeometry& geometry);
/// Adds the AVX passes' plan to `table` where the CPU has AVX2 and simd_allowed() (else, or when
/// it has one, nothing). Worth it for a table used by more passes than the two of one frame (a
/// static gaze): making the plan costs about what the decisions of one pass do.
void add_blur_ramp_plan(BlurRampTable& table);

inline constexpr int blur_ramp_max_radius = 64;  ///< cap on the kernel radius, pixels

/// sigma_px at screen point p (see above); 0 inside the fovea.
float blur_ramp_sigma_px(const BlurRamp& ramp, const BlurRampGeometry& geometry, glm::vec2 p);

/// The kernel radius for sigma_px: min(ceil(3 sigma_px), blur_ramp_max_radius); 0 when
/// sigma_px <= 0.
int blur_ramp_radius(float sigma_px);

/// The normalised weights w_0 .. w_R of sigma_px and R = blur_ramp_radius(sigma_px) >= 1 (see
/// above), written to weights[0 .. R].
void blur_ramp_weights(float sigma_px, int radius, float* weights);

/// Per-pixel work of a pass (along y when `vertical`, else x): pixel (x, y) of `out`, which holds
/// a copy of `image` (a pixel whose radius is 0 keeps it).
void blur_ramp_pixel(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                     bool vertical, Image& out, int x, int y);

/// The horizontal pass on a W x H image (the geometry's screen size), any channel count. With
/// `simd` (the default), a CPU with AVX2 and three channels, eight pixels at a time on the
/// interleaved floats, each float's lane doing its pixel's blur_ramp_pixel operations in their
/// order: the same bits as `simd` false (and as other channel counts, which always run it), which
/// runs blur_ramp_pixel pixel by pixel (the readable reference). `table` (optional, made for this
/// ramp and geometry) gives the AVX groups each pixel's sigma and exp. `storage`: an image the
/// output is written into when it has the image's shape (a stage recycles an earlier frame's);
/// every value is written, none of its own is read; otherwise the output is made anew.
Image blur_ramp_horizontal(const BlurRamp& ramp, const BlurRampGeometry& geometry,
                           const Image& image, bool simd = true,
                           const BlurRampTable* table = nullptr, Image storage = {});
/// The vertical pass on a W x H image (the geometry's screen size), any channel count (`simd`,
/// `table`, `storage`: as blur_ramp_horizontal).
Image blur_ramp_vertical(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                         bool simd = true, const BlurRampTable* table = nullptr,
                         Image storage = {});
/// Both passes: horizontal, then vertical.
Image blur_ramp(const BlurRamp& ramp, const BlurRampGeometry& geometry, const Image& image,
                bool simd = true);

}  // namespace fovref
