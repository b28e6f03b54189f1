// Sampling density (ref/analysis/density.h, Lund §5.2 mid_range_res): the analytic texels per
// pixel of the classic map, the gaze buffer's rows, the acuity model, and Lund's observations on
// his presets (Fig. 5.2): fov and cfov match radially and angularly, cfov leaves the gaze buffer
// at about one ray per pixel, the kernel presets differ near the gaze and match further out.
#include <doctest/doctest.h>

#include <cmath>

#include "ref/analysis/density.h"
#include "ref/log_polar/params.h"

using namespace fovref;

namespace {

std::vector<DensityRow> preset_density(const std::string& name, int rings) {
    const float d_px = static_cast<float>(360.0 / std::tan(20.0 * M_PI / 180.0));  // cornell
    const LogPolarMap map =
        make_log_polar_map(find_foveation_preset(name).map, 1280, 720, {640, 360}, d_px);
    RingSettings settings;
    settings.count = rings;
    return ring_density(map, ring_layout(1280, 720, map.gaze, d_px, settings));
}

}  // namespace

TEST_CASE("density: the classic map's texels per pixel, analytically") {
    LogPolarParams params;
    params.lp_aspect = 1.0f;
    const LogPolarMap map = make_log_polar_map(params, 400, 300, {200, 150}, 300.0f);
    for (const float r : {1.0f, 10.0f, 100.0f, 240.0f}) {
        const TexelsPerPixel s = texels_per_pixel(map, r);
        CHECK(s.radial ==
              doctest::Approx(map.width / ((1.0 + r) * std::log1p(500.0))).epsilon(2e-6));
        CHECK(s.angular == doctest::Approx(map.height / (2 * M_PI * r)).epsilon(2e-6));
    }
    CHECK(relative_acuity(5.79f) == 1.0f);
    CHECK(relative_acuity(10.0f) == doctest::Approx(7.49 / 16.0).epsilon(1e-6));
}

TEST_CASE("density: Lund's presets behave as his Fig. 5.2 describes") {
    const std::vector<DensityRow> fov = preset_density("fov", 10);
    for (const DensityRow& r : fov)  // lp_aspect 1.2: square cells, matched axes
        CHECK(r.radial_rays_per_px == doctest::Approx(r.angular_rays_per_px).epsilon(0.05));
    const std::vector<DensityRow> cfov = preset_density("cfov", 20);
    std::size_t first_outside = 0;
    while (cfov[first_outside].in_gaze_buffer) {
        CHECK(cfov[first_outside].radial_rays_per_px == 1.0f);
        ++first_outside;
    }
    REQUIRE(first_outside > 0);
    // Leaving the gaze buffer: close to one ray per pixel on both axes (within 15%).
    CHECK(cfov[first_outside].radial_rays_per_px == doctest::Approx(1.0).epsilon(0.15));
    CHECK(cfov[first_outside].angular_rays_per_px == doctest::Approx(1.0).epsilon(0.15));
    // kfov: the kernel lowers the radial density near the gaze; the axes meet further out.
    const std::vector<DensityRow> kfov = preset_density("kfov", 10);
    CHECK(kfov[0].radial_rays_per_px < 0.5f * kfov[0].angular_rays_per_px);
    CHECK(kfov[3].radial_rays_per_px == doctest::Approx(kfov[3].angular_rays_per_px).epsilon(0.05));
    // Outside the gaze buffer density falls with eccentricity on every preset; ckfov oversamples
    // where it leaves the gaze buffer (1.25 angular rays per pixel), the effect Lund's Fig. 5.1
    // (right) shows.
    for (const std::string name : {"fov", "kfov", "cfov", "ckfov"}) {
        const std::vector<DensityRow> rows = preset_density(name, 10);
        for (std::size_t k = 1; k < rows.size(); ++k)
            if (!rows[k - 1].in_gaze_buffer)
                CHECK(rows[k].angular_rays_per_px <= rows[k - 1].angular_rays_per_px);
    }
    const std::vector<DensityRow> ckfov = preset_density("ckfov", 10);
    CHECK(ckfov[1].in_gaze_buffer);
    CHECK_FALSE(ckfov[2].in_gaze_buffer);
    CHECK(ckfov[2].angular_rays_per_px > 1.2f);
}

TEST_CASE(
    "density: mid_range_res from the Jacobian agrees with Lund's count of the pixels two "
    "adjacent rays span") {
    // Lund measures the resolution as the screen distance between the rays of two adjacent
    // texels; the density uses the map's analytic Jacobian. For every column pair (i, i + 1) of
    // row 0 (any row: the map is radial), the rays' screen points are d pixels apart at the
    // mean radius r, so 1/d rays per pixel; texels_per_pixel(r).radial must agree (central
    // difference: error O(h^2)). Measured at 1280x720, wherever a column spans at least 1/8
    // pixel: fov 0.034%, kfov 0.76% (x^3 bends fastest, near the gaze), cfov 0.015%, ckfov
    // 0.017%; the stated tolerance is 1%.
    const float d_px = static_cast<float>(360.0 / std::tan(20.0 * M_PI / 180.0));
    for (const FoveationPreset& preset : foveation_presets()) {
        const LogPolarMap map = make_log_polar_map(preset.map, 1280, 720, {640, 360}, d_px);
        double worst = 0.0;
        int compared = 0;
        for (int i = 0; i + 1 < map.width; ++i) {
            const glm::vec2 a = lp_inverse(map, {static_cast<float>(i) + 0.5f, 0.5f});
            const glm::vec2 b = lp_inverse(map, {static_cast<float>(i) + 1.5f, 0.5f});
            const double ra = std::hypot(a.x - 640.0, a.y - 360.0);
            const double rb = std::hypot(b.x - 640.0, b.y - 360.0);
            const double spacing = rb - ra;
            if (spacing < 0.125 || (map.has_gaze_buffer() && ra < map.gaze_radius)) continue;
            const double analytic =
                texels_per_pixel(map, static_cast<float>(0.5 * (ra + rb))).radial;
            worst = std::max(worst, std::fabs(analytic * spacing - 1.0));
            ++compared;
        }
        INFO(preset.name, ": worst relative difference ", worst, " over ", compared, " columns");
        CHECK(compared > 100);
        CHECK(worst < 0.01);
    }
}
