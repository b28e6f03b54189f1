#include "ref/visual_polar/probe.h"

#include <cmath>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/filters/blur_ramp.h"
#include "ref/trace/trace_probe.h"
#include "ref/visual_polar/params.h"
#include "ref/visual_polar/resolve.h"

namespace fovref {

namespace {

void explain_map(const VisualPolarMap& m, ProbeReport& report) {
    ProbeSection s{"map", "the Visual-Polar map (docs/visual-polar.md)", {}};
    s.add("screen", std::to_string(m.screen_width) + "x" + std::to_string(m.screen_height) +
                        ", gaze (" + probe_float(m.gaze.x) + ", " + probe_float(m.gaze.y) + ")");
    s.add("buffer", std::to_string(m.width) + "x" + std::to_string(m.height) +
                        " (w columns: rho, h rows: phi)");
    s.add("fovea", "columns i < i_f = " + std::to_string(m.fovea_columns) +
                       ", radius s P(u0) = " + probe_float(m.fovea_radius) + " px");
    s.add("scale", "s = R / P(1) = " + probe_float(m.scale) + " px per model degree");
    report.sections.push_back(s);
}

void explain_texel(const ProbeContext& c, const VisualPolarMap& m, int i, int j,
                   ProbeReport& report) {
    ProbeSection s{"vp_trace", "texel (" + std::to_string(i) + ", " + std::to_string(j) + ")", {}};
    const int rows = vp_column_rows(m, i);
    const bool fovea = i < m.fovea_columns;
    s.add("column", std::string(fovea ? "fovea" : "periphery") + ", n_i = " + std::to_string(rows) +
                        " rows with data");
    if (fovea) {
        s.add("radius",
              "r = s P(u0) (i + 1/2) / i_f = " + probe_float(vp_column_radius(m, i)) + " px");
    } else {
        const float rho = (static_cast<float>(i) + 0.5f) / static_cast<float>(m.width);
        const float rho_f = static_cast<float>(m.fovea_columns) / static_cast<float>(m.width);
        const float u = vp_u0 + (rho - rho_f) * (1.0f - vp_u0) / (1.0f - rho_f);
        s.add("U", "u0 + (rho - rho_f)(1 - u0) / (1 - rho_f) = " + probe_float(u));
        s.add("radius", "r = s P(U) = " + probe_float(vp_column_radius(m, i)) + " px (" +
                            probe_float(vp_column_radius(m, i) / m.scale) + " model degrees)");
    }
    glm::vec2 p{0.0f};
    const VpTexel status = vp_texel_status(m, i, j, p);
    if (status == VpTexel::clipped) {
        s.add("clipped", "yes: j >= n_i (the triangular clip): never traced, no data");
        report.sections.push_back(s);
        return;
    }
    const float theta =
        6.28318530717958647692f * (static_cast<float>(j) + 0.5f) / static_cast<float>(rows);
    s.add("clipped", "no");
    s.add("theta", "2 pi (j + 1/2) / n_i = " + probe_float(theta) + " rad");
    s.add("screen point", "(" + probe_float(p.x) + ", " + probe_float(p.y) + ")");
    s.add("traced",
          status == VpTexel::traced ? "yes" : "no: the point is off screen (never traced)");
    const Buffer* valid = c.frame->find("vp_valid");
    if (valid) s.add("vp_valid", probe_float(valid->image.at(i, j)));
    report.sections.push_back(s);
    report.buffer_texel = glm::ivec2(i, j);
}

}  // namespace

void explain_visual_polar(const ProbeContext& c, ProbeReport& report) {
    const SparseParams params = parse_sparse_params(c.settings->params, report.mode);
    const VisualPolarMap m =
        sparse_vp_map(params, c.settings->width, c.settings->height, c.frame->frame);
    explain_map(m, report);
    if (c.texel) {
        if (c.eye >= 0) throw Error("--texel I,J,EYE: an eye applies to stereo-lp only");
        const int i = c.texel->x, j = c.texel->y;
        if (i < 0 || j < 0 || i >= m.width || j >= m.height)
            throw Error("--texel " + std::to_string(i) + "," + std::to_string(j) +
                        ": outside the " + std::to_string(m.width) + "x" +
                        std::to_string(m.height) + " Visual-Polar buffer");
        explain_texel(c, m, i, j, report);
        return;
    }
    // [resolve]
    ProbeSection s{"resolve", "pass 2 (docs/visual-polar.md, \"Resolve\")", {}};
    const glm::vec2 centre = pixel_centre(c.x, c.y);
    const float r = gaze_distance(m.gaze, centre);
    const glm::vec2 ut = vp_forward_angle(m, centre);
    s.add("distance", "r = " + probe_float(r) + " px, e = r / s = " + probe_float(r / m.scale) +
                          " model degrees");
    s.add("region", r < m.fovea_radius ? "fovea (r < s P(u0)): linear columns"
                                       : "periphery: U = P^-1(r / s) by bisection");
    s.add("u", probe_float(ut.x) + " (texel centres at + 1/2)");
    s.add("angle", "theta / 2 pi = " + probe_float(ut.y));
    const float sx = std::clamp(ut.x, 0.5f, static_cast<float>(m.width) - 0.5f) - 0.5f;
    const int i0 = static_cast<int>(std::floor(sx));
    for (int col : {i0, std::min(i0 + 1, m.width - 1)}) {
        const int n = vp_column_rows(m, col);
        s.add("column " + std::to_string(col),
              "n = " + std::to_string(n) + ", v = n theta / 2 pi = " +
                  probe_float(static_cast<float>(n) * ut.y) + ", phi-mip level " +
                  (params.mip_resolve ? probe_float(vp_mip_level(n, r))
                                      : std::string("0 (bilinear)")));
    }
    s.add("fx", probe_float(sx - static_cast<float>(i0)));
    const std::string output = params.blur ? "resolved" : "final";
    if (const Buffer* color = c.frame->find("vp_color")) {
        const VpMips mips = build_vp_mips(m, color->image, c.frame->find("vp_valid")->image);
        Image out(m.screen_width, m.screen_height, 3, 0.0f);
        ResolveStats stats;
        float lambda = 0.0f;
        resolve_vp_pixel(m, mips, out, c.x, c.y, stats, &lambda, params.mip_resolve);
        const glm::vec3 mine{out.at(c.x, c.y, 0), out.at(c.x, c.y, 1), out.at(c.x, c.y, 2)};
        s.add("value",
              probe_vec3(mine) + (stats.pixels_untraced_taps ? " (no traced tap: black)" : ""));
        probe_check(report, s, output, mine, probe_rgb(*c.frame, output, c.x, c.y));
    }
    report.sections.push_back(s);
    if (params.blur) {
        ProbeSection b{"blur_horizontal", "the P5 blur ramp (two separable passes)", {}};
        const float sigma = blur_ramp_sigma_px(params.ramp, blur_ramp_geometry(m), centre);
        b.add("sigma", probe_float(sigma) + " px = " + probe_float(sigma / m.scale) +
                           " model degrees (0 up to the fovea edge e_f = " +
                           probe_float(vp_inverse_cdf(vp_u0)) + ", rising to " +
                           probe_float(params.ramp.sigma_deg) + " at " +
                           probe_float(params.ramp.full_deg) + " model degrees, constant beyond)");
        b.add("radius", std::to_string(blur_ramp_radius(sigma)) + " px");
        report.sections.push_back(b);
    }
}

}  // namespace fovref
