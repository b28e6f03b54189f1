// Theoretical gain (SPEC §5.6, Koskela P1 §4): P1's three figures, closed forms computed here
// independently with libm, an independent 2-D quadrature, convergence of the ellipse rule,
// symmetries and parameter checks.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "ref/analysis/gain.h"
#include "ref/core/error.h"

using namespace fovref;

namespace {

constexpr double pi = 3.14159265358979323846;

GainParams disc(double diameter_deg, double display_cpd) {
    GainParams p;
    p.shape = FovShape::disc;
    p.width_deg = diameter_deg;
    p.display_cpd = display_cpd;
    return p;
}

GainParams ellipse(double width_deg, double height_deg, double display_cpd) {
    GainParams p;
    p.shape = FovShape::ellipse;
    p.width_deg = width_deg;
    p.height_deg = height_deg;
    p.display_cpd = display_cpd;
    return p;
}

// P1 eq. 2 clamped to c, written out again (not acuity_cpd) for the independent quadrature.
double acuity_here(double e, double c) {
    const double v = e <= 5.79 ? 60.0 : 449.4 / ((0.3 * e + 1.0) * (0.3 * e + 1.0));
    return v < c ? v : c;
}

// The gain of an ellipse by a different method: the true polar angle phi (not the ellipse's own
// angle), libm's cos and sin, and a numeric radial midpoint rule instead of the closed form.
// Midpoint in phi: spectral (smooth periodic integrand); radial midpoint: O(h^2) with kinks at
// 5.79 deg and the clamp radius, about 1e-7 of the gain at these resolutions.
double gain_by_2d_quadrature(double a, double b, double c, int angles, int radii) {
    double sum = 0.0;
    for (int j = 0; j < angles; ++j) {
        const double phi = (j + 0.5) * (pi / 2.0) / angles;
        const double x = std::cos(phi) / a, y = std::sin(phi) / b;
        const double boundary = 1.0 / std::sqrt(x * x + y * y);
        const double h = boundary / radii;
        double radial = 0.0;
        for (int i = 0; i < radii; ++i) {
            const double e = (i + 0.5) * h;
            radial += acuity_here(e, c) * e;
        }
        sum += radial * h;
    }
    const double integral = 4.0 * (pi / 2.0) / angles * sum;
    return 1.0 - integral / (c * pi * a * b);
}

}  // namespace

TEST_CASE("gain: P1's three figures (SPEC §5.6) to 0.05 percentage points") {
    // SPEC §5.6 gives the figures to 0.1 pp; the sources round them to whole percents.
    const auto cases = p1_gain_cases();
    REQUIRE(cases.size() == 3);
    const double expected_percent[3] = {93.8, 70.3, 94.6};
    for (int k = 0; k < 3; ++k) {
        CAPTURE(cases[k].name);
        const GainResult r = theoretical_gain(cases[k].params);
        CHECK(std::abs(100.0 * r.gain - expected_percent[k]) < 0.05);
        // The sources' whole percents ("94%", "at least 70%", "95%") are our figures rounded.
        CHECK(std::round(100.0 * r.gain) == cases[k].quoted_percent);
    }
    // The readings that do not reproduce P1: the oval's 160 x 135 as semi-axes (98.0%), and the
    // Vive's 110 deg as the disc's radius, as P1's text words it (89.1%).
    CHECK(100.0 * theoretical_gain(ellipse(320.0, 270.0, 60.0)).gain > 97.9);
    CHECK(std::abs(100.0 * theoretical_gain(disc(220.0, 15.3)).gain - 89.1) < 0.05);
}

TEST_CASE("gain: a disc has the closed form, computed here with libm") {
    // integral = 2 pi [min(peak, c) e_f^2/2 + c (r_c^2 - e_f^2)/2
    //                  + A/s^2 (ln(u_R/u_c) + 1/u_R - 1/u_c)],  u = 0.3 e + 1,
    // r_c = max(e_f, clamp radius); relative agreement 1e-13 (rounding of a few terms).
    for (const std::pair<double, double>& radius_cpd :
         {std::pair{40.0, 60.0}, std::pair{80.0, 60.0}, std::pair{55.0, 15.3},
          std::pair{20.0, 30.0}}) {
        const double radius = radius_cpd.first, c = radius_cpd.second;
        CAPTURE(radius);
        CAPTURE(c);
        const double e_f = 5.79, clamp = (std::sqrt(449.4 / c) - 1.0) / 0.3;
        const double r_c = clamp > e_f ? clamp : e_f;
        const double u_c = 0.3 * r_c + 1.0, u_r = 0.3 * radius + 1.0;
        const double integral =
            2.0 * pi *
            (std::min(60.0, c) * e_f * e_f / 2.0 + c * (r_c * r_c - e_f * e_f) / 2.0 +
             449.4 / 0.09 * (std::log(u_r / u_c) + 1.0 / u_r - 1.0 / u_c));
        const GainResult r = theoretical_gain(disc(2.0 * radius, c));
        CHECK(std::abs(r.acuity_integral / integral - 1.0) < 1e-13);
        CHECK(std::abs(r.area_deg2 / (pi * radius * radius) - 1.0) < 1e-15);
        CHECK(std::abs(r.gain - (1.0 - integral / (c * pi * radius * radius))) < 1e-13);
    }
}

TEST_CASE("gain: zero where the display's maximum is rendered everywhere") {
    // Inside the fovea V = 60 = V_max: nothing to save. The ellipse's quadrature must then sum
    // to the exact area pi a b too, which checks its angles (relative 1e-13).
    for (const GainParams& p : {disc(10.0, 60.0), ellipse(11.0, 4.0, 60.0)}) {
        const GainResult r = theoretical_gain(p);
        CHECK(std::abs(r.acuity_integral / r.uniform_integral - 1.0) < 1e-13);
        CHECK(r.gain < 1e-13);
        CHECK(r.full_rate_radius_deg == 5.79);
    }
    // Clamped everywhere: V >= 5 c/deg out to (sqrt(449.4 / 5) - 1) / 0.3 = 28.27 deg.
    for (const GainParams& p :
         {disc(56.0, 5.0), ellipse(56.0, 3.0, 5.0), ellipse(2.0, 56.0, 5.0)}) {
        const GainResult r = theoretical_gain(p);
        CHECK(std::abs(r.acuity_integral / r.uniform_integral - 1.0) < 1e-13);
        CHECK(r.gain < 1e-13);
        CHECK(r.full_rate_radius_deg == doctest::Approx((std::sqrt(449.4 / 5.0) - 1.0) / 0.3));
    }
    // A display finer than the eye: inside the fovea the eye takes half of 120 c/deg.
    const GainResult half = theoretical_gain(disc(8.0, 120.0));
    CHECK(std::abs(half.gain - 0.5) < 1e-15);
    CHECK(half.full_rate_radius_deg == 0.0);
}

TEST_CASE("gain: the ellipse agrees with an independent 2-D quadrature") {
    // Tolerance 2e-6: the reference's radial midpoint rule is good to about 1e-7 here.
    for (const GainParams& p : {ellipse(160.0, 135.0, 60.0), ellipse(110.0, 90.0, 15.3),
                                ellipse(20.0, 8.0, 60.0), ellipse(40.0, 11.58, 15.3)}) {
        CAPTURE(p.width_deg);
        CAPTURE(p.height_deg);
        const double reference =
            gain_by_2d_quadrature(p.width_deg / 2.0, p.height_deg / 2.0, p.display_cpd, 512, 4000);
        CHECK(std::abs(theoretical_gain(p).gain - reference) < 2e-6);
    }
}

TEST_CASE("gain: the ellipse rule has converged at the default resolution") {
    // Doubling N changes the gain by less than 1e-9 (measured at most 4.5e-10, for the 360 x 1
    // ellipse, whose boundary crosses both kinks); docs/gain.md promises 1e-6. The oval's
    // boundary crosses neither kink, so the rule is spectral: N = 64 agrees with N = 4096 to 1e-12.
    for (const GainParams& base :
         {ellipse(160.0, 135.0, 60.0), ellipse(20.0, 8.0, 60.0), ellipse(40.0, 11.58, 15.3),
          ellipse(30.0, 5.0, 60.0), ellipse(360.0, 1.0, 60.0), ellipse(360.0, 0.01, 60.0)}) {
        CAPTURE(base.width_deg);
        CAPTURE(base.height_deg);
        GainParams fine = base;
        fine.angle_steps = 2 * base.angle_steps;
        CHECK(base.angle_steps == 4096);
        CHECK(std::abs(theoretical_gain(base).gain - theoretical_gain(fine).gain) < 1e-9);
    }
    GainParams coarse = ellipse(160.0, 135.0, 60.0);
    coarse.angle_steps = 64;
    CHECK(std::abs(theoretical_gain(coarse).gain -
                   theoretical_gain(ellipse(160.0, 135.0, 60.0)).gain) < 1e-12);
}

TEST_CASE("gain: an ellipse with equal axes is the disc, swapping the axes changes nothing") {
    for (const std::pair<double, double>& size_cpd :
         {std::pair{110.0, 15.3}, std::pair{160.0, 60.0}, std::pair{9.0, 60.0},
          std::pair{30.0, 100.0}}) {
        const double size = size_cpd.first, c = size_cpd.second;
        CAPTURE(size);
        const GainResult d = theoretical_gain(disc(size, c));
        const GainResult e = theoretical_gain(ellipse(size, size, c));
        CHECK(std::abs(d.gain - e.gain) < 1e-13);
        CHECK(std::abs(d.acuity_integral / e.acuity_integral - 1.0) < 1e-13);
        // A disc ignores height_deg.
        GainParams odd = disc(size, c);
        odd.height_deg = std::numeric_limits<double>::quiet_NaN();
        CHECK(theoretical_gain(odd).gain == d.gain);
    }
    // V depends on the distance only, so which axis is horizontal does not matter.
    CHECK(std::abs(theoretical_gain(ellipse(160.0, 135.0, 60.0)).gain -
                   theoretical_gain(ellipse(135.0, 160.0, 60.0)).gain) < 1e-13);
}

TEST_CASE("gain: the acuity model and its radial integral") {
    const GainParams p;  // 60 c/deg display
    CHECK(acuity_cpd(0.0, p) == 60.0);
    CHECK(acuity_cpd(5.79, p) == 60.0);
    // Beyond the fovea, exactly the expression of P1 eq. 2.
    const auto falloff = [](double e) { return 449.4 / ((0.3 * e + 1.0) * (0.3 * e + 1.0)); };
    CHECK(acuity_cpd(10.0, p) == falloff(10.0));
    CHECK(acuity_cpd(100.0, p) == falloff(100.0));
    CHECK(falloff(5.79) < 60.0);  // 59.99: the model steps down by 0.01 c/deg at the fovea's edge
    GainParams vive = p;
    vive.display_cpd = 15.3;
    CHECK(acuity_cpd(3.0, vive) == 15.3);
    CHECK(acuity_cpd(14.0, vive) == 15.3);  // falloff 16.3 > 15.3
    CHECK(acuity_cpd(16.0, vive) == falloff(16.0));
    CHECK(full_rate_radius_deg(vive) == (std::sqrt(449.4 / 15.3) - 1.0) / 0.3);  // 14.73 deg
    CHECK(full_rate_radius_deg(p) == 5.79);  // the falloff is 59.99 c/deg at 5.79 deg
    // F(R) against a fine midpoint rule of Vc(e) e (relative 1e-9: O(h^2) with two kinks).
    for (const double radius : {3.0, 5.79, 10.0, 14.0, 15.0, 80.0}) {
        CAPTURE(radius);
        const int n = 200000;
        double sum = 0.0;
        for (int i = 0; i < n; ++i) {
            const double e = (i + 0.5) * radius / n;
            sum += acuity_cpd(e, vive) * e;
        }
        CHECK(std::abs(acuity_radial_integral(radius, vive) / (sum * radius / n) - 1.0) < 1e-9);
    }
    // The gain grows with the FOV beyond the clamp radius.
    double previous = 0.0;
    for (const double diameter : {40.0, 80.0, 120.0, 200.0, 360.0}) {
        const double g = theoretical_gain(disc(diameter, 15.3)).gain;
        CHECK(g > previous);
        previous = g;
    }
}

TEST_CASE("gain: bad parameters are refused with the parameter named") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    const auto refused = [](const GainParams& p, const char* name) {
        CAPTURE(name);
        CHECK_THROWS_WITH_AS(theoretical_gain(p), doctest::Contains(name), Error);
    };
    for (const double bad : {nan, inf, -inf, 0.0, -10.0, 360.5, 1e300}) {
        CAPTURE(bad);
        GainParams p;
        p.width_deg = bad;
        refused(p, "width_deg");
        p = GainParams{};
        p.height_deg = bad;
        refused(p, "height_deg");
        p = GainParams{};
        p.display_cpd = bad == 360.5 ? 10000.5 : bad;
        refused(p, "display_cpd");
        p = GainParams{};
        p.peak_cpd = bad == 360.5 ? 10000.5 : bad;
        refused(p, "peak_cpd");
        p = GainParams{};
        p.falloff_cpd = bad == 360.5 ? 10000.5 : bad;
        refused(p, "falloff_cpd");
        p = GainParams{};
        p.falloff_slope = bad == 360.5 ? 100.5 : bad;
        refused(p, "falloff_slope");
        if (bad != 0.0) {  // a fovea of radius 0 is allowed: the falloff from the centre
            p = GainParams{};
            p.fovea_deg = bad;
            refused(p, "fovea_deg");
        }
    }
    GainParams steps;
    steps.angle_steps = 0;
    refused(steps, "angle_steps");
    steps.angle_steps = gain_max_angle_steps + 1;
    refused(steps, "angle_steps");
    GainParams shape;
    shape.shape = static_cast<FovShape>(7);
    refused(shape, "shape");
    CHECK_THROWS_WITH_AS(theoretical_gain(disc(400.0, 60.0)),
                         "gain: width_deg must be finite and in (0, 360], got 400", Error);
    // The limits themselves are accepted; the fovea may be 0.
    GainParams edge = ellipse(360.0, 360.0, 10000.0);
    edge.fovea_deg = 0.0;
    CHECK_NOTHROW(theoretical_gain(edge));
}
