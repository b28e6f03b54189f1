// Theoretical gain of foveated rendering for a display (SPEC §5.6; Koskela et al. 2016, "Foveated
// Path Tracing: A Literature Review and a Performance Gain Analysis", the thesis's P1, §4): the
// share of the details a display can show that the eye cannot resolve while it looks at the
// centre of the field of view: the work that foveation with perfect eye tracking could leave
// out (the thesis's "upper bound" of the saving).
// clang-format off
//
//   V(e)   = peak_cpd                       for e <= e_f        (P1 eq. 2: 60 c/deg, e_f = 5.79 deg)
//          = A / (s e + 1)^2                for e >  e_f        (A = 449.4 c/deg, s = 0.3 /deg)
//   Vc(e)  = min(V(e), V_max)               V_max = the display's maximum c/deg (the clamp)
//   gain   = 1 - (integral of Vc(e) dA over the FOV) / (V_max * area)
//
// e is the distance in degrees from the FOV centre: P1 puts the gaze there, where the most detail
// is needed, so the figure is the least gain over gaze positions. Degrees are treated as planar
// coordinates: the FOV is a disc or an ellipse in a plane of degrees, area in deg^2. Sample
// density is taken proportional to V (c/deg), not to V^2 (samples per deg^2), as in the sources.
//
// Integration, all binary64 (docs/gain.md):
//   F(R) = integral_0^R Vc(e) e de in closed form, piece by piece: the fovea, the clamped
//          periphery (Vc = V_max), and the falloff, whose antiderivative is
//          A/s^2 (ln(s e + 1) + 1/(s e + 1)), evaluated as ln(u1/u0) + 1/u1 - 1/u0 (dm::log_d).
//   disc of radius R:        integral = 2 pi F(R), exact but for rounding.
//   ellipse, semi-axes a, b: polar integral over the boundary, parametrised by the ellipse's own
//          angle t (boundary point (a cos t, b sin t), r(t)^2 = a^2 cos^2 t + b^2 sin^2 t,
//          d(polar angle)/dt = a b / r^2):
//            integral = 4 * integral_0^{pi/2} F(r(t)) a b / r(t)^2 dt
//                     ~ (2 pi a b / N) * sum_{k=0}^{N-1} F(r(t_k)) / r(t_k)^2,  t_k = (k + 1/2) (pi/2) / N
//          the midpoint rule, summed in increasing k. The integrand is smooth and periodic, so
//          the rule converges faster than any power of N, except where the boundary crosses e_f
//          or the clamp radius (a kink: O(N^-2)); N = 4096 puts the error below 1e-9 for every
//          shape tried. cos t_k and sin t_k come from Taylor series (+ - * / only, SPEC §0).
// clang-format on
#pragma once

#include <string>
#include <vector>

namespace fovref {

enum class FovShape { disc, ellipse };

/// "disc" or "ellipse".
const char* fov_shape_name(FovShape shape);

/// Bounds of the accepted parameters: anything beyond them is a typo, not a display.
inline constexpr double gain_max_fov_deg = 360.0;     ///< full width or height of the FOV
inline constexpr double gain_max_cpd = 10000.0;       ///< any c/deg parameter
inline constexpr int gain_max_angle_steps = 1 << 20;  ///< N

/// The FOV, the display and the acuity model. Defaults: P1's "perfect HMD" (an oval FOV of
/// 160 deg x 135 deg at 60 c/deg) with P1 eq. 2's constants.
struct GainParams {
    FovShape shape = FovShape::ellipse;
    double width_deg = 160.0;    ///< full horizontal extent (disc: the diameter)
    double height_deg = 135.0;   ///< full vertical extent (ellipse only; a disc ignores it)
    double display_cpd = 60.0;   ///< V_max: the display's maximum c/deg, the clamp of V
    double peak_cpd = 60.0;      ///< V inside the fovea (P1 eq. 2)
    double fovea_deg = 5.79;     ///< e_f: the fovea's radius (P1 eq. 2)
    double falloff_cpd = 449.4;  ///< A in A / (s e + 1)^2 (P1 eq. 2)
    double falloff_slope = 0.3;  ///< s, per degree (P1 eq. 2)
    int angle_steps = 4096;      ///< N, midpoint nodes per quadrant (ellipse only)
};

struct GainResult {
    double gain = 0.0;                  ///< 1 - acuity_integral / uniform_integral, in [0, 1]
    double acuity_integral = 0.0;       ///< integral of Vc dA over the FOV, c/deg * deg^2
    double uniform_integral = 0.0;      ///< V_max * area: the display's full rate everywhere
    double area_deg2 = 0.0;             ///< pi a b (disc: pi R^2)
    double v_max_cpd = 0.0;             ///< the display maximum the gain is measured against
    double full_rate_radius_deg = 0.0;  ///< Vc = V_max for every e up to this (0: nowhere)
};

/// Throws fovref::Error naming the parameter ("gain: width_deg must be ...") unless every
/// parameter is finite and within its bounds: widths in (0, 360], c/deg values in (0, 10000],
/// fovea_deg in [0, 360], falloff_slope in (0, 100], angle_steps in 1..2^20.
void validate_gain_params(const GainParams& params);

/// Vc(e): P1 eq. 2 clamped to the display's maximum. e >= 0 in degrees.
double acuity_cpd(double eccentricity_deg, const GainParams& params);

/// F(R) = integral_0^R Vc(e) e de in closed form (c/deg * deg^2 per radian of polar angle).
double acuity_radial_integral(double radius_deg, const GainParams& params);

/// The largest e with Vc = V_max on all of [0, e]: max(e_f, clamp radius) when peak_cpd >= V_max,
/// else 0. The clamp radius (sqrt(A / V_max) - 1) / s is where the falloff meets V_max.
double full_rate_radius_deg(const GainParams& params);

/// The gain and its parts (validates the parameters first).
GainResult theoretical_gain(const GainParams& params);

/// One of P1's headline cases, with the figure the sources quote for it.
struct GainCase {
    std::string name;         ///< e.g. "perfect-hmd-oval"
    std::string description;  ///< the case in words
    GainParams params;
    double quoted_percent = 0.0;  ///< the sources' figure, in percent
    std::string quoted;           ///< how the sources put it
};

/// P1's three headline cases (SPEC §5.6): the oval 160 x 135 deg at 60 c/deg (P1: "94%"); a disc
/// of 110 deg diameter clamped to 15.3 c/deg, the HTC Vive (P1: "at least 70%"); a disc of
/// radius 80 deg at 60 c/deg (the thesis's summary of P1: "95%").
std::vector<GainCase> p1_gain_cases();

}  // namespace fovref
