#include "tools/cli/commands/density.h"

#include <cstdio>
#include <filesystem>
#include <optional>

#include "ref/analysis/density.h"
#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/log_polar/params.h"
#include "ref/modes/modes.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/common/output_dir.h"
#include "tools/cli/report/svg_plot.h"

namespace fovref {

int run_density(const DensityOptions& o) {
    std::optional<OutputDirectory> out;  // checked before any work
    if (!o.out_dir.empty()) out.emplace("--out", o.out_dir);
    const FoveationPreset& preset = find_foveation_preset(o.mode);
    const GoldenCase run = command_case(o, "density");
    run.params.check_known(find_mode(o.mode).params, o.mode);
    RenderSettings settings;
    settings.width = o.width;
    settings.height = o.height;
    validate_settings(settings);
    const FoveatedParams params = parse_foveated_params(run.params, preset);
    const Scene scene = load_cli_scene(o.scene);
    const Camera camera = camera_at(scene, 0.0f);
    const LogPolarMap map = foveated_map(params, scene, camera, o.width, o.height, 0);
    RingSettings ring_settings;
    ring_settings.count = o.rings;
    ring_settings.max_range = o.max_range;
    const float d_px = display_distance_px(scene.display, o.width, o.height, camera.vfov_deg);
    const RingLayout layout = ring_layout(o.width, o.height, map.gaze, d_px, ring_settings);
    const std::vector<DensityRow> rows = ring_density(map, layout);

    std::printf(
        "fovref density: %s at %dx%d, gaze (%g, %g), d_px %.6g (scene %s), buffer %dx%d, "
        "K = %s, r_G %.6g px\n",
        o.mode.c_str(), o.width, o.height, static_cast<double>(map.gaze.x),
        static_cast<double>(map.gaze.y), static_cast<double>(d_px), o.scene.c_str(), map.width,
        map.height, kernel_text(map.kernel).c_str(), static_cast<double>(map.gaze_radius));
    std::printf(
        "rays per pixel along the radius and along the circle at each ring's middle "
        "(Lund's resolution is 1 / these); acuity relative to the fovea (Koskela)\n");
    std::printf("%5s %9s %9s %10s %10s %10s %8s\n", "ring", "e (deg)", "r (px)", "radial",
                "angular", "acuity", "");
    std::string csv =
        "ring,inner_deg,outer_deg,middle_deg,radius_px,in_gaze_buffer,radial_rays_per_px,"
        "angular_rays_per_px,relative_acuity\n";
    PlotSeries radial{"radial rays/px", {}, {}}, angular{"angular rays/px", {}, {}},
        acuity{"relative acuity", {}, {}};
    for (const DensityRow& r : rows) {
        std::printf("%5d %9.3f %9.2f %10.4f %10.4f %10.4f %8s\n", r.ring,
                    static_cast<double>(r.middle_deg), static_cast<double>(r.radius_px),
                    static_cast<double>(r.radial_rays_per_px),
                    static_cast<double>(r.angular_rays_per_px), static_cast<double>(r.acuity),
                    r.in_gaze_buffer ? "gaze buf" : "");
        char line[256];
        std::snprintf(line, sizeof line, "%d,%.9g,%.9g,%.9g,%.9g,%d,%.9g,%.9g,%.9g\n", r.ring,
                      static_cast<double>(r.inner_deg), static_cast<double>(r.outer_deg),
                      static_cast<double>(r.middle_deg), static_cast<double>(r.radius_px),
                      r.in_gaze_buffer ? 1 : 0, static_cast<double>(r.radial_rays_per_px),
                      static_cast<double>(r.angular_rays_per_px), static_cast<double>(r.acuity));
        csv += line;
        for (PlotSeries* s : {&radial, &angular, &acuity}) s->x.push_back(r.middle_deg);
        radial.y.push_back(r.radial_rays_per_px);
        angular.y.push_back(r.angular_rays_per_px);
        acuity.y.push_back(r.acuity);
    }
    if (out) {
        write_file_atomic(out->file("density.csv"), csv);
        PlotSpec spec;
        spec.title = o.mode + ": rays per pixel at each ring's middle (Lund mid_range_res)";
        spec.x_label = "eccentricity (deg)";
        spec.y_label = "rays per pixel";
        spec.series = {radial, angular, acuity};
        spec.width = 560;
        spec.height = 320;
        write_file_atomic(out->file("density.svg"), svg_line_plot(spec));
        out->commit();
        if (!o.quiet) std::printf("wrote %s/density.csv, density.svg\n", o.out_dir.c_str());
    }
    return 0;
}

}  // namespace fovref
