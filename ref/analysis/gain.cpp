// Theoretical gain (SPEC §5.6, Koskela P1 §4): gain = 1 - integral of min(V(e), V_max) dA /
// (V_max * area), V from P1 eq. 2, e the distance in degrees from the FOV centre (planar). The
// radial integral is closed-form; an ellipse adds a midpoint rule over its own angle t, N nodes
// per quadrant, summed in increasing t in binary64 (gain.h has the equations, docs/gain.md the
// error). No libm transcendental: the logarithm is dm::log_d, cos/sin of t a Taylor series.
#include "ref/analysis/gain.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "ref/core/dmath.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

// "gain: NAME must be WHAT, got VALUE" unless lo < value <= hi (lo <= value with `closed_low`).
void check_range(const char* name, double value, double lo, double hi, bool closed_low,
                 const char* what) {
    const bool low_ok = closed_low ? value >= lo : value > lo;
    if (!(std::isfinite(value) && low_ok && value <= hi))
        throw Error(std::string("gain: ") + name + " must be " + what + ", got " +
                    check_value_text(value));
}

// cos t and sin t for t in [0, pi/2], binary64, + - * / only: the Taylor series to t^26 and t^27
// in Horner form. The first omitted terms are below 1e-21 at t = pi/2, so the error is rounding
// (a few 1e-16), far below what the quadrature needs.
struct CosSin {
    double c = 1.0, s = 0.0;
};

CosSin cos_sin_quadrant(double t) {
    const double t2 = t * t;
    double c = 1.0, s = 1.0;
    for (int n = 13; n >= 1; --n) {
        const double k = 2.0 * n;
        c = 1.0 - t2 / ((k - 1.0) * k) * c;
        s = 1.0 - t2 / (k * (k + 1.0)) * s;
    }
    return {c, t * s};
}

// Where the falloff A / (s e + 1)^2 equals V_max (may be negative: the falloff is below V_max
// everywhere).
double clamp_radius_deg(const GainParams& p) {
    return (std::sqrt(p.falloff_cpd / p.display_cpd) - 1.0) / p.falloff_slope;
}

// Ellipse of semi-axes a, b: (2 pi a b / N) * sum_k F(r_k) / r_k^2 (gain.h).
double ellipse_integral(double a, double b, const GainParams& p) {
    const int n = p.angle_steps;
    const double step = (dm::pi_d / 2.0) / static_cast<double>(n);
    double sum = 0.0;
    for (int k = 0; k < n; ++k) {
        const CosSin cs = cos_sin_quadrant((static_cast<double>(k) + 0.5) * step);
        const double ac = a * cs.c, bs = b * cs.s;
        const double r2 = ac * ac + bs * bs;
        sum += acuity_radial_integral(std::sqrt(r2), p) / r2;
    }
    return 2.0 * dm::pi_d * a * b / static_cast<double>(n) * sum;
}

}  // namespace

const char* fov_shape_name(FovShape shape) { return shape == FovShape::disc ? "disc" : "ellipse"; }

void validate_gain_params(const GainParams& p) {
    if (p.shape != FovShape::disc && p.shape != FovShape::ellipse)
        throw Error("gain: shape must be disc or ellipse, got " + check_value_text(p.shape));
    check_range("width_deg", p.width_deg, 0.0, gain_max_fov_deg, false, "finite and in (0, 360]");
    if (p.shape == FovShape::ellipse)
        check_range("height_deg", p.height_deg, 0.0, gain_max_fov_deg, false,
                    "finite and in (0, 360]");
    check_range("display_cpd", p.display_cpd, 0.0, gain_max_cpd, false,
                "finite and in (0, 10000] c/deg");
    check_range("peak_cpd", p.peak_cpd, 0.0, gain_max_cpd, false, "finite and in (0, 10000] c/deg");
    check_range("fovea_deg", p.fovea_deg, 0.0, gain_max_fov_deg, true, "finite and in [0, 360]");
    check_range("falloff_cpd", p.falloff_cpd, 0.0, gain_max_cpd, false,
                "finite and in (0, 10000] c/deg");
    check_range("falloff_slope", p.falloff_slope, 0.0, 100.0, false,
                "finite and in (0, 100] per degree");
    if (p.angle_steps < 1 || p.angle_steps > gain_max_angle_steps)
        throw Error("gain: angle_steps must be 1..1048576, got " + std::to_string(p.angle_steps));
}

double acuity_cpd(double e, const GainParams& p) {
    const double s_e = p.falloff_slope * e + 1.0;
    const double v = e <= p.fovea_deg ? p.peak_cpd : p.falloff_cpd / (s_e * s_e);
    return std::min(v, p.display_cpd);
}

double acuity_radial_integral(double radius, const GainParams& p) {
    const double e_f = p.fovea_deg;
    // Fovea, 0 <= e <= e_f: Vc = min(peak, V_max).
    const double r_fovea = std::min(radius, e_f);
    double f = std::min(p.peak_cpd, p.display_cpd) * r_fovea * r_fovea / 2.0;
    if (radius <= e_f) return f;
    // Clamped periphery, e_f < e <= clamp radius: Vc = V_max.
    const double r_clamp = std::min(radius, std::max(e_f, clamp_radius_deg(p)));
    f += p.display_cpd * (r_clamp - e_f) * (r_clamp + e_f) / 2.0;
    if (radius <= r_clamp) return f;
    // Falloff, r_clamp < e <= radius: A/s^2 [ln u + 1/u] between u0 = s r_clamp + 1, u1 = s R + 1.
    const double s = p.falloff_slope;
    const double u0 = s * r_clamp + 1.0, u1 = s * radius + 1.0;
    f += p.falloff_cpd / (s * s) * (dm::log_d(u1 / u0) + 1.0 / u1 - 1.0 / u0);
    return f;
}

double full_rate_radius_deg(const GainParams& p) {
    if (p.peak_cpd < p.display_cpd) return 0.0;
    return std::max(p.fovea_deg, clamp_radius_deg(p));
}

GainResult theoretical_gain(const GainParams& p) {
    validate_gain_params(p);
    const double a = p.width_deg / 2.0;
    const double b = p.shape == FovShape::disc ? a : p.height_deg / 2.0;
    GainResult r;
    r.v_max_cpd = p.display_cpd;
    r.area_deg2 = dm::pi_d * a * b;
    r.acuity_integral = p.shape == FovShape::disc ? 2.0 * dm::pi_d * acuity_radial_integral(a, p)
                                                  : ellipse_integral(a, b, p);
    r.uniform_integral = p.display_cpd * r.area_deg2;
    // Vc <= V_max everywhere, so the gain is in [0, 1]; rounding may leave it a few ulp below 0.
    r.gain = std::max(0.0, 1.0 - r.acuity_integral / r.uniform_integral);
    r.full_rate_radius_deg = full_rate_radius_deg(p);
    return r;
}

std::vector<GainCase> p1_gain_cases() {
    std::vector<GainCase> cases(3);
    cases[0].name = "perfect-hmd-oval";
    cases[0].description = "oval FOV 160 x 135 deg (full axes) at 60 c/deg: a perfect HMD";
    cases[0].params.shape = FovShape::ellipse;
    cases[0].params.width_deg = 160.0;
    cases[0].params.height_deg = 135.0;
    cases[0].params.display_cpd = 60.0;
    cases[0].quoted_percent = 94.0;
    cases[0].quoted = "94% (P1 §4)";

    cases[1].name = "htc-vive";
    cases[1].description = "disc FOV of 110 deg diameter clamped to 15.3 c/deg: the HTC Vive";
    cases[1].params.shape = FovShape::disc;
    cases[1].params.width_deg = 110.0;
    cases[1].params.display_cpd = 15.3;
    cases[1].quoted_percent = 70.0;
    cases[1].quoted = "at least 70% (P1 §4)";

    cases[2].name = "perfect-hmd-disc";
    cases[2].description = "disc FOV of radius 80 deg (160 deg diameter) at 60 c/deg";
    cases[2].params.shape = FovShape::disc;
    cases[2].params.width_deg = 160.0;
    cases[2].params.display_cpd = 60.0;
    cases[2].quoted_percent = 95.0;
    cases[2].quoted = "95% (the thesis's summary of P1)";
    return cases;
}

}  // namespace fovref
