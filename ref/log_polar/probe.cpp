#include "ref/log_polar/probe.h"

#include <cmath>
#include <cstring>
#include <set>
#include <utility>

#include "ref/bvh/bvh.h"
#include "ref/core/vec.h"
#include "ref/filters/gaussian_lerp.h"
#include "ref/filters/internal_aa.h"
#include "ref/filters/post_aa.h"
#include "ref/log_polar/deferred_sample.h"
#include "ref/log_polar/mip_resolve.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/stereo.h"
#include "ref/log_polar/trace.h"
#include "ref/trace/trace_probe.h"

namespace fovref {

namespace {

std::string point_text(glm::vec2 p) {
    return "(" + probe_float(p.x) + ", " + probe_float(p.y) + ")";
}

const char* status_text(TexelStatus s) {
    switch (s) {
        case TexelStatus::traced: return "on screen: traced";
        case TexelStatus::off_screen: return "off screen: not traced, no data";
        case TexelStatus::inside_gaze: return "inside the gaze circle: not traced (G = 1)";
    }
    return "?";
}

// The ray's closest hit and the surface there (the same ray the pass traced; its G-buffer values
// are checked separately).
void explain_hit(const ProbeContext& c, const Bvh& bvh, const Ray& ray, ProbeSection& section) {
    TraceStats stats;
    const Hit hit = trace_closest(bvh, ray, stats);
    section.add("traversal", std::to_string(stats.nodes_visited) + " nodes visited, " +
                                 std::to_string(stats.triangles_tested) + " triangles tested");
    if (!hit.hit()) {
        section.add("hit", "miss (background: ids -1, every other channel 0)");
        return;
    }
    section.add("hit", "t " + probe_float(hit.t) + ", primitive " + std::to_string(hit.primitive) +
                           ", barycentrics u " + probe_float(hit.u) + " v " + probe_float(hit.v) +
                           " (closest; ties: lowest primitive id)");
    explain_surface(*c.scene, surface_at(*c.scene, hit.primitive, hit.u, hit.v), section);
}

// [foveation] the map's constants for this frame.
void explain_map(const LogPolarMap& m, ProbeReport& report) {
    ProbeSection s{"foveation", "the log-polar map of this frame (docs/foveation.md)", {}};
    s.add("gaze", point_text(m.gaze));
    s.add("buffer", std::to_string(m.width) + "x" + std::to_string(m.height) +
                        " texels (u: columns, radial; v: rows, angular)");
    s.add("kernel", "K(x) = " + kernel_text(m.kernel));
    s.add("R, L", "R " + probe_float(m.radius_max) +
                      " px, L = ln(1 + R) = " + probe_float(m.log_radius_max));
    if (m.has_gaze_buffer())
        s.add("gaze buffer", "r_G " + probe_float(m.gaze_radius) +
                                 " px, G = K(ln(1 + r_G) / L) = " + probe_float(m.composite));
    else
        s.add("gaze buffer", "none (a_G = 0): G = 0");
    report.sections.push_back(s);
}

// Texel (i, j) as the buffer's pass makes it (lp_gbuffer_texel, or deferred_gbuffer_texel for
// kfr), into a scratch buffer, at the frame's TAA jitter: in the buffer before the inverse map,
// or (kfr) on the screen after it.
struct TexelRerun {
    MaskedGBuffer scratch;
    Image points;
    TexelStatus status = TexelStatus::off_screen;
};
TexelRerun rerun_texel(const ProbeContext& c, const FoveatedParams& params, const LogPolarMap& m,
                       const Bvh& bvh, int i, int j) {
    const FrameResult& f = *c.frame;
    TexelRerun r{MaskedGBuffer(m.width, m.height), Image(m.width, m.height, 2, 0.0f)};
    FoveatedTraceStats stats;
    const LpInverseTable table =
        params.deferred
            ? lp_inverse_table(m, Offset2{}, deferred_sample_offset(params.jitter_raster, c.jitter))
            : lp_inverse_table(m, c.jitter);
    if (params.deferred) {
        RasterSettings raster = params.raster;
        if (params.jitter_raster) raster.sample = c.jitter;
        const RasterizedScreen screen{
            *c.scene, f.find("gbuffer_primitive_id")->image,
            make_raster_frame(*c.scene, c.camera, m.screen_width, m.screen_height, raster),
            c.previous_camera, tan_half_vfov(c.previous_camera)};
        r.status = deferred_gbuffer_texel(r.scratch, r.points, m, table, screen, i, j, stats);
    } else {
        r.status = lp_gbuffer_texel(r.scratch, r.points, m, table,
                                    PrimaryView(*c.scene, bvh, c.camera, c.camera), i, j, stats);
    }
    return r;
}

// [lp_trace] (or [lp_sample]) of texel (i, j): the pass's own per-texel function, checked
// against the rendered buffer. Returns the texel's status.
TexelStatus explain_texel_trace(const ProbeContext& c, const FoveatedParams& params,
                                const LogPolarMap& m, const Bvh& bvh, int i, int j,
                                ProbeReport& report) {
    const std::string texel = "texel (" + std::to_string(i) + ", " + std::to_string(j) + ")";
    ProbeSection trace{
        params.deferred ? "lp_sample" : "lp_trace",
        texel + (params.deferred ? ": the rasterized G-buffer's pixel under its centre's "
                                   "inverse-mapped screen point (Meng's deferred variant)"
                                 : ": one ray through its centre's inverse-mapped screen point"),
        {}};
    const glm::vec2 uv = pixel_centre(i, j);
    trace.add("centre", "(u, v) = " + point_text(uv));
    const float t = m.composite + (1.0f - m.composite) * (uv.x / static_cast<float>(m.width));
    const float rho = kernel_inverse(m.kernel, t);
    trace.add("inverse", "rho = K^-1(G + (1 - G) u / w) = K^-1(" + probe_float(t) +
                             ") = " + probe_float(rho) + ", theta = 2 pi v / h");
    if (!(c.jitter == Offset2{}))
        trace.add("TAA jitter", "(" + probe_float(c.jitter.x) + ", " + probe_float(c.jitter.y) +
                                    (params.deferred ? ") in the pixel, after the inverse map"
                                                     : ") in the texel, before the inverse map"));
    const TexelRerun r = rerun_texel(c, params, m, bvh, i, j);
    const glm::vec2 p{r.points.at(i, j, 0), r.points.at(i, j, 1)};
    trace.add("screen point", point_text(p) + ", r = " + probe_float(gaze_distance(m.gaze, p)) +
                                  " px from the gaze: " + status_text(r.status));
    if (r.status == TexelStatus::traced && params.deferred) {
        const int sx = static_cast<int>(std::floor(p.x)), sy = static_cast<int>(std::floor(p.y));
        trace.add("sampled pixel", "(" + std::to_string(sx) + ", " + std::to_string(sy) +
                                       ") of the rasterized G-buffer, its channels made again "
                                       "from its primitive id (`fovref probe --pixel` explains "
                                       "its rasterization)");
        trace.add("primitive", probe_float(r.scratch.gbuffer.primitive_id.at(i, j)));
        const bool copy = probe_same_gbuffer(r.scratch.gbuffer, i, j, *c.frame, "gbuffer_", sx, sy);
        trace.add("G-buffer", std::string("texel: ") +
                                  (copy ? "bit-identical to the rasterized G-buffer's pixel"
                                        : "DIFFERS from the rasterized G-buffer's pixel"));
        if (!copy) report.consistent = false;
    } else if (r.status == TexelStatus::traced) {
        const Ray ray = primary_ray(c.camera, tan_half_vfov(c.camera), m.screen_width,
                                    m.screen_height, p.x, p.y);
        trace.add("primary ray",
                  "origin " + probe_vec3(ray.origin) + ", direction " + probe_vec3(ray.direction));
        explain_hit(c, bvh, ray, trace);
    }
    const FrameResult& f = *c.frame;
    const bool same = probe_same_gbuffer(r.scratch.gbuffer, f, "lp_gbuffer_", i, j) &&
                      r.scratch.valid.at(i, j) == f.find("lp_valid")->image.at(i, j);
    trace.add("check", std::string("texel: ") + (same ? "bit-identical to the rendered buffers"
                                                      : "DIFFERS from the rendered buffers"));
    if (!same) report.consistent = false;
    report.sections.push_back(trace);
    return r.status;
}

// [internal_aa] of texel (i, j): internal_aa_texel, checked against lp_color_aa.
void explain_internal_aa_texel(const ProbeContext& c, const LogPolarMap& m, int i, int j,
                               ProbeReport& report) {
    const FrameResult& f = *c.frame;
    ProbeSection aa{"internal_aa",
                    "texel (" + std::to_string(i) + ", " + std::to_string(j) +
                        "): Meng's internal anti-aliasing (docs/foveation.md)",
                    {}};
    Image out(m.width, m.height, 3, 0.0f);
    internal_aa_texel(f.find("lp_color")->image, f.find("lp_valid")->image, out, i, j);
    aa.add("applies", 2 * i < m.width ? "no: a texel of the inner half (2 i < w), unchanged"
                                      : "yes: the 3x3 Gaussian over its traced neighbours");
    const glm::vec3 mine{out.at(i, j, 0), out.at(i, j, 1), out.at(i, j, 2)};
    aa.add("value", probe_vec3(mine));
    probe_check(report, aa, "lp_color_aa", mine, probe_rgb(f, "lp_color_aa", i, j));
    report.sections.push_back(aa);
}

// [lp_trace], [lp_shade] and [internal_aa] of texel (i, j).
void explain_texel(const ProbeContext& c, const FoveatedParams& params, const LogPolarMap& m,
                   const Bvh& bvh, int i, int j, ProbeReport& report) {
    if (explain_texel_trace(c, params, m, bvh, i, j, report) != TexelStatus::traced) return;
    ProbeSection shade{"lp_shade",
                       "texel (" + std::to_string(i) + ", " + std::to_string(j) +
                           "): the basic ray tracer's shading (docs/trace.md)",
                       {}};
    explain_shade_at(c, bvh, "lp_gbuffer_", "lp_color", i, j, shade, report);
    report.sections.push_back(shade);
    if (params.internal_aa) explain_internal_aa_texel(c, m, i, j, report);
}

// [gaze_trace] and [gaze_shade] of screen pixel (x, y), inside the gaze circle.
void explain_gaze_pixel(const ProbeContext& c, const LogPolarMap& m, const Bvh& bvh,
                        ProbeReport& report) {
    ProbeSection trace{"gaze_trace", "one ray through the pixel centre (as basic)", {}};
    const ScreenWindow window = gaze_window(m);
    MaskedGBuffer scratch(window.width, window.height);
    FoveatedTraceStats stats;
    const float tan_half = tan_half_vfov(c.camera);
    gaze_gbuffer_pixel(scratch, window, m, PrimaryView(*c.scene, bvh, c.camera, c.camera), c.x, c.y,
                       stats, c.jitter);
    const int i = c.x - window.x0, j = c.y - window.y0;  // in the gaze buffer
    trace.add("gaze buffer", "covers screen pixels x " + std::to_string(window.x0) + ".." +
                                 std::to_string(window.x0 + window.width - 1) + ", y " +
                                 std::to_string(window.y0) + ".." +
                                 std::to_string(window.y0 + window.height - 1) + ": pixel (" +
                                 std::to_string(i) + ", " + std::to_string(j) + ") of it");
    const Ray ray =
        primary_ray(c.camera, tan_half, m.screen_width, m.screen_height,
                    static_cast<float>(c.x) + c.jitter.x, static_cast<float>(c.y) + c.jitter.y);
    trace.add("primary ray",
              "origin " + probe_vec3(ray.origin) + ", direction " + probe_vec3(ray.direction));
    explain_hit(c, bvh, ray, trace);
    const bool same = probe_same_gbuffer(scratch.gbuffer, *c.frame, "gaze_gbuffer_", i, j);
    trace.add("check", std::string("pixel: ") + (same ? "bit-identical to the rendered buffers"
                                                      : "DIFFERS from the rendered buffers"));
    if (!same) report.consistent = false;
    report.sections.push_back(trace);
    ProbeSection shade{"gaze_shade", "the basic ray tracer's shading (docs/trace.md)", {}};
    explain_shade_at(c, bvh, "gaze_gbuffer_", "gaze_color", i, j, shade, report, &window);
    report.sections.push_back(shade);
}

// [resolve]: pass 2 at the pixel; returns the taps' texels that were traced.
std::vector<std::pair<int, int>> explain_resolve(const ProbeContext& c,
                                                 const FoveatedParams& params, const LogPolarMap& m,
                                                 const std::string& output, ProbeReport& report) {
    const FrameResult& f = *c.frame;
    ProbeSection s{"resolve", "pass 2 (docs/foveation.md, \"Pass 2\")", {}};
    const glm::vec2 centre = pixel_centre(c.x, c.y);
    const float r = gaze_distance(m.gaze, centre);
    s.add("distance", "r = |centre - gaze| = " + probe_float(r) + " px");
    const GazeInput gaze =
        gaze_input(m, m.has_gaze_buffer() ? &f.find("gaze_color")->image : nullptr);
    const std::string color_name = resolve_color_name(params);
    const Image& color = f.find(color_name)->image;
    const Image& valid = f.find("lp_valid")->image;
    Image out(m.screen_width, m.screen_height, 3, 0.0f);
    ResolveStats stats;
    BilinearLookup l;
    float lambda = 0.0f;
    if (params.mip_resolve) {
        const std::vector<MipLevel> mips = build_lp_mips(color, valid);
        resolve_mip_pixel(m, mips, gaze, out, c.x, c.y, stats, &lambda);
        s.add("filter", "mip: a pyramid of " + std::to_string(mips.size()) +
                            " levels, level lambda = " + probe_float(lambda) +
                            " (log2 of the larger of the radial and angular texels per pixel)");
        if (lambda > 0.0f) {
            s.add("levels", "levels " + std::to_string(static_cast<int>(std::floor(lambda))) +
                                " and the next, lerped by " +
                                probe_float(lambda - std::floor(lambda)) +
                                "; texels of level 0 are listed only when lambda = 0");
            const glm::vec3 mine{out.at(c.x, c.y, 0), out.at(c.x, c.y, 1), out.at(c.x, c.y, 2)};
            s.add("value", probe_vec3(mine));
            probe_check(report, s, output, mine, probe_rgb(f, output, c.x, c.y));
            report.sections.push_back(s);
            return {};
        }
        sample_lp_bilinear(color, valid, lp_forward(m, centre), &out.at(c.x, c.y, 0), &l);
    } else {
        resolve_pixel(m, {color, valid, gaze}, out, c.x, c.y, stats, &l);
    }
    std::vector<std::pair<int, int>> taps;
    if (stats.pixels_from_gaze > 0) {
        s.add("source", "r < r_G = " + probe_float(m.gaze_radius) +
                            ": the gaze buffer's pixel, taken as it is");
    } else {
        const glm::vec2 uv = lp_forward(m, centre);
        s.add("forward map", "(u, v) = " + point_text(uv) +
                                 " (u = w (K(rho) - G) / (1 - G), v = " + "h theta / (2 pi))");
        s.add("lookup", "columns i0 " + std::to_string(l.i0) + ", i1 " + std::to_string(l.i1) +
                            ", fu " + probe_float(l.fu) + "; rows j0 " + std::to_string(l.j0) +
                            ", j1 " + std::to_string(l.j1) + ", fv " + probe_float(l.fv) +
                            " (v wraps, u clamps)");
        const int is[4] = {l.i0, l.i1, l.i0, l.i1}, js[4] = {l.j0, l.j0, l.j1, l.j1};
        for (int k = 0; k < 4; ++k) {
            const glm::vec3 value{color.at(is[k], js[k], 0), color.at(is[k], js[k], 1),
                                  color.at(is[k], js[k], 2)};
            s.add("  tap " + std::to_string(k),
                  "texel (" + std::to_string(is[k]) + ", " + std::to_string(js[k]) + ") " +
                      (l.traced[k] ? "traced, " + color_name + " " + probe_vec3(value)
                                   : std::string("not traced: left out")));
            if (l.traced[k] && (k == 0 || is[k] != is[k - 1] || js[k] != js[k - 1]))
                taps.emplace_back(is[k], js[k]);
        }
        s.add("rows", "weights W0 = (1 - fv) w(j0) = " + probe_float(l.row_weight[0]) +
                          ", W1 = fv w(j1) = " + probe_float(l.row_weight[1]) +
                          "; final lerp t = " + probe_float(l.t));
        if (stats.pixels_untraced_taps > 0)
            s.add("result", "no traced tap with a weight: black (screen_pixels_untraced_taps)");
    }
    const glm::vec3 mine{out.at(c.x, c.y, 0), out.at(c.x, c.y, 1), out.at(c.x, c.y, 2)};
    s.add("value", probe_vec3(mine));
    probe_check(report, s, output, mine, probe_rgb(f, output, c.x, c.y));
    report.sections.push_back(s);
    return taps;
}

}  // namespace

void explain_foveated(const ProbeContext& c, ProbeReport& report) {
    const FoveatedParams params =
        parse_foveated_params(c.settings->params, find_foveation_preset(report.mode));
    const LogPolarMap m = foveated_map(params, *c.scene, c.camera, c.settings->width,
                                       c.settings->height, c.frame->frame);
    const Bvh bvh = build_bvh(c.scene->positions);
    explain_map(m, report);
    if (c.texel) {
        if (c.eye >= 0)
            throw Error("--texel I,J,EYE: an eye applies to stereo-lp only (give --texel I,J)");
        const int i = c.texel->x, j = c.texel->y;
        if (i < 0 || j < 0 || i >= m.width || j >= m.height)
            throw Error("--texel " + std::to_string(i) + "," + std::to_string(j) +
                        ": outside the " + std::to_string(m.width) + "x" +
                        std::to_string(m.height) + " log-polar buffer");
        explain_texel(c, params, m, bvh, i, j, report);
        return;
    }
    // With TAA (a taa_age buffer) the chain has TAA's output after pass 2's (SPEC §6).
    const bool taa = c.frame->find("taa_age") != nullptr;
    const std::vector<std::string> chain = screen_chain(params, taa);
    const std::vector<std::pair<int, int>> taps = explain_resolve(c, params, m, chain[0], report);
    const glm::vec2 centre = pixel_centre(c.x, c.y);
    if (inside_gaze_circle(m, centre)) explain_gaze_pixel(c, m, bvh, report);
    for (const auto& [i, j] : taps) explain_texel(c, params, m, bvh, i, j, report);
    std::size_t link = taa ? 1 : 0;  // the TAA section comes from the modes' explainer
    if (params.gaussian_lerp) {
        ProbeSection s{"gaussian_lerp", "Lund's Gaussian lerp (docs/foveation.md)", {}};
        const Image& in = c.frame->find(chain[link])->image;
        const LerpRamp ramp = gaussian_lerp_ramp(in.width, in.height, m.gaze);
        const float t = gaussian_lerp_amount(ramp, m.gaze, centre);
        s.add("amount", "t = clamp((r - D/6) / (R_c - D/6), 0, 1) = " + probe_float(t));
        const glm::vec3 g{gaussian3x3_clamped(in, c.x, c.y, 0),
                          gaussian3x3_clamped(in, c.x, c.y, 1),
                          gaussian3x3_clamped(in, c.x, c.y, 2)};
        s.add("3x3 Gaussian", probe_vec3(g));
        Image out(in.width, in.height, 3, 0.0f);
        gaussian_lerp_pixel(in, m.gaze, ramp, out, c.x, c.y);
        const glm::vec3 mine{out.at(c.x, c.y, 0), out.at(c.x, c.y, 1), out.at(c.x, c.y, 2)};
        s.add("value", probe_vec3(mine) + (t == 0.0f ? " (t = 0: unchanged)" : ""));
        ++link;
        probe_check(report, s, chain[link], mine, probe_rgb(*c.frame, chain[link], c.x, c.y));
        report.sections.push_back(s);
    }
    if (params.post_aa) {
        ProbeSection s{"post_aa", "Meng's post anti-aliasing, eq. 2.14 (docs/foveation.md)", {}};
        const Image& in = c.frame->find(chain[link])->image;
        const float t = gaze_distance(m.gaze, centre) / m.radius_max;
        const int eta = post_aa_size(t);
        s.add("size", "t = r / R = " + probe_float(t) +
                          (eta == 0 ? ": t <= 0.10, unfiltered"
                                    : ": eta = 3 + 2 ceil((t - 0.10) / 0.05) = " +
                                          std::to_string(eta) + ", sigma = eta / 6"));
        std::vector<std::vector<float>> weights(static_cast<std::size_t>(std::max(eta, 0) + 1));
        if (eta > 0) weights[static_cast<std::size_t>(eta)] = post_aa_weights(eta);
        Image out(in.width, in.height, 3, 0.0f);
        post_aa_pixel(in, m.gaze, m.radius_max, weights, out, c.x, c.y);
        const glm::vec3 mine{out.at(c.x, c.y, 0), out.at(c.x, c.y, 1), out.at(c.x, c.y, 2)};
        s.add("value", probe_vec3(mine));
        probe_check(report, s, "final", mine, probe_rgb(*c.frame, "final", c.x, c.y));
        report.sections.push_back(s);
    }
}

namespace {

// [stereo] which eye and its camera.
void explain_eye(const StereoParams& params, const Camera& camera, int eye, ProbeReport& report) {
    ProbeSection s{"stereo", "Gupta's stereo pass: two eyes side by side (docs/foveation.md)", {}};
    s.add("eye", std::to_string(eye) + (eye == 0 ? " (left" : " (right") +
                     "): the frame's camera moved by " + (eye == 0 ? "-" : "+") +
                     "IPD/2 along its right axis, IPD " + probe_float(params.ipd));
    s.add("eye camera", "position " + probe_vec3(camera.position));
    report.sections.push_back(s);
}

// [stereo_trace] and [stereo_shade] of texel x (= e w + i), y of the side-by-side buffer.
void explain_stereo_texel(const ProbeContext& c, const std::array<LogPolarMap, 2>& maps,
                          const std::array<Camera, 2>& cameras, const Bvh& bvh, int x, int y,
                          ProbeReport& report) {
    const FrameResult& f = *c.frame;
    const int w = maps[0].width, eye = x / w, i = x - eye * w;
    const LogPolarMap& m = maps[static_cast<std::size_t>(eye)];
    const std::string texel = "texel (" + std::to_string(i) + ", " + std::to_string(y) +
                              ") of eye " + std::to_string(eye) + " = column " + std::to_string(x) +
                              " of the side-by-side buffer";
    ProbeSection trace{"stereo_trace",
                       texel +
                           ": one ray through its centre's inverse-mapped point, with the "
                           "eye's camera on its W/2 x H sub-screen",
                       {}};
    MaskedGBuffer scratch(2 * w, m.height);
    Image points(2 * w, m.height, 2, 0.0f);
    FoveatedTraceStats stats;
    // The frame's TAA jitter (the centre without TAA).
    const std::array<LpInverseTable, 2> tables = {lp_inverse_table(maps[0], c.jitter),
                                                  lp_inverse_table(maps[1], c.jitter)};
    // The probe explains the frame as rendered: the previous cameras only change the motion
    // vectors, which the check below leaves out.
    const TexelStatus status = stereo_gbuffer_texel(
        scratch, points, maps, tables, eye_views(*c.scene, bvh, cameras, cameras), x, y, stats);
    const glm::vec2 full{points.at(x, y, 0), points.at(x, y, 1)};
    const glm::vec2 p{full.x - static_cast<float>(eye * m.screen_width), full.y};
    trace.add("screen point", point_text(p) + " in the eye, " + point_text(full) +
                                  " on the screen; r = " + probe_float(gaze_distance(m.gaze, p)) +
                                  " px from the eye's gaze: " + status_text(status));
    const Camera& camera = cameras[static_cast<std::size_t>(eye)];
    if (status == TexelStatus::traced) {
        const Ray ray =
            primary_ray(camera, tan_half_vfov(camera), m.screen_width, m.screen_height, p.x, p.y);
        trace.add("primary ray",
                  "origin " + probe_vec3(ray.origin) + ", direction " + probe_vec3(ray.direction));
        explain_hit(c, bvh, ray, trace);
    }
    const bool same = probe_same_gbuffer(scratch.gbuffer, f, "lp_gbuffer_", x, y) &&
                      scratch.valid.at(x, y) == f.find("lp_valid")->image.at(x, y);
    trace.add("check", std::string("texel: ") + (same ? "bit-identical to the rendered buffers"
                                                      : "DIFFERS from the rendered buffers"));
    if (!same) report.consistent = false;
    report.sections.push_back(trace);
    if (status != TexelStatus::traced) return;
    ProbeSection shade{"stereo_shade",
                       "column " + std::to_string(x) + ", row " + std::to_string(y) +
                           ": the basic ray tracer's shading with eye " + std::to_string(eye) +
                           "'s camera (docs/trace.md)",
                       {}};
    ProbeContext eye_context = c;
    eye_context.camera = camera;
    explain_shade_at(eye_context, bvh, "lp_gbuffer_", "lp_color", x, y, shade, report);
    report.sections.push_back(shade);
}

// [resolve] of screen pixel (x, y): the eye, the (barrel) source, the bilinear lookup in the
// eye's half; returns the traced taps as columns of the side-by-side buffer.
std::vector<std::pair<int, int>> explain_stereo_resolve(const ProbeContext& c,
                                                        const StereoParams& params,
                                                        const std::array<LogPolarMap, 2>& maps,
                                                        ProbeReport& report) {
    const FrameResult& f = *c.frame;
    const int eye_width = maps[0].screen_width, eye = c.x / eye_width, w = maps[0].width;
    const LogPolarMap& m = maps[static_cast<std::size_t>(eye)];
    ProbeSection s{"resolve", "pass 2 in the eye's half of the buffer (docs/foveation.md)", {}};
    const glm::vec2 local = pixel_centre(c.x - eye * eye_width, c.y);
    s.add("eye", std::to_string(eye) + ": eye-local centre " + point_text(local));
    glm::vec2 uv{0.0f};
    const bool in_lens = stereo_lookup(params, maps, c.x, c.y, uv);
    if (params.barrel) {
        const glm::vec2 source =
            barrel_source(local, eye_width, m.screen_height, params.k1, params.k2);
        s.add("barrel",
              "source s = centre + (W/4) q (1 + k1 |q|^2 + k2 |q|^4) = " + point_text(source) +
                  (in_lens ? "" : ": outside the eye's image, black (counted)"));
    }
    const std::array<Image, 2> colors = {eye_half(f.find("lp_color")->image, 0),
                                         eye_half(f.find("lp_color")->image, 1)};
    const std::array<Image, 2> masks = {eye_half(f.find("lp_valid")->image, 0),
                                        eye_half(f.find("lp_valid")->image, 1)};
    Image out(2 * eye_width, m.screen_height, 3, 0.0f);
    StereoResolveStats stats;
    resolve_stereo_pixel(params, maps, colors, masks, out, c.x, c.y, stats);
    std::vector<std::pair<int, int>> taps;
    if (in_lens) {
        BilinearLookup l;
        float scratch[4];
        const auto e = static_cast<std::size_t>(eye);
        sample_lp_bilinear(colors[e], masks[e], uv, scratch, &l);
        s.add("forward map", "(u, v) = " + point_text(uv) + " in eye " + std::to_string(eye) +
                                 "'s " + std::to_string(w) + "x" + std::to_string(m.height) +
                                 " half");
        const int is[4] = {l.i0, l.i1, l.i0, l.i1}, js[4] = {l.j0, l.j0, l.j1, l.j1};
        for (int k = 0; k < 4; ++k) {
            const int column = eye * w + is[k];
            s.add(
                "  tap " + std::to_string(k),
                "texel (" + std::to_string(is[k]) + ", " + std::to_string(js[k]) + "), column " +
                    std::to_string(column) + ": " +
                    (l.traced[k] ? "traced, lp_color " + probe_vec3({colors[e].at(is[k], js[k], 0),
                                                                     colors[e].at(is[k], js[k], 1),
                                                                     colors[e].at(is[k], js[k], 2)})
                                 : std::string("not traced: left out")));
            if (l.traced[k] && (k == 0 || is[k] != is[k - 1] || js[k] != js[k - 1]))
                taps.emplace_back(column, js[k]);
        }
        s.add("rows", "weights W0 = " + probe_float(l.row_weight[0]) + ", W1 = " +
                          probe_float(l.row_weight[1]) + "; final lerp t = " + probe_float(l.t));
        if (stats.resolve.pixels_untraced_taps > 0)
            s.add("result", "no traced tap with a weight: black (screen_pixels_untraced_taps)");
    }
    const glm::vec3 mine{out.at(c.x, c.y, 0), out.at(c.x, c.y, 1), out.at(c.x, c.y, 2)};
    s.add("value", probe_vec3(mine));
    // With TAA pass 2 writes "resolved" (TAA then writes "final").
    const std::string output = f.find("resolved") ? "resolved" : "final";
    probe_check(report, s, output, mine, probe_rgb(f, output, c.x, c.y));
    report.sections.push_back(s);
    return taps;
}

}  // namespace

void explain_stereo(const ProbeContext& c, ProbeReport& report) {
    const StereoParams params = parse_stereo_params(c.settings->params);
    const std::array<LogPolarMap, 2> maps = stereo_maps(
        params, *c.scene, c.camera, c.settings->width, c.settings->height, c.frame->frame);
    const std::array<Camera, 2> cameras = {eye_camera(c.camera, 0, params.ipd),
                                           eye_camera(c.camera, 1, params.ipd)};
    const Bvh bvh = build_bvh(c.scene->positions);
    const int w = maps[0].width, h = maps[0].height;
    if (c.texel) {
        const int i = c.texel->x, j = c.texel->y, eye = c.eye;
        if (eye < 0)
            throw Error("--texel " + std::to_string(i) + "," + std::to_string(j) +
                        ": stereo-lp needs the eye too, --texel I,J,EYE (EYE 0 left, 1 right)");
        if (i < 0 || j < 0 || i >= w || j >= h)
            throw Error("--texel " + std::to_string(i) + "," + std::to_string(j) + "," +
                        std::to_string(eye) + ": outside eye " + std::to_string(eye) + "'s " +
                        std::to_string(w) + "x" + std::to_string(h) + " log-polar buffer");
        explain_eye(params, cameras[static_cast<std::size_t>(eye)], eye, report);
        explain_map(maps[static_cast<std::size_t>(eye)], report);
        report.buffer_texel = glm::ivec2(eye * w + i, j);
        explain_stereo_texel(c, maps, cameras, bvh, eye * w + i, j, report);
        return;
    }
    const int eye = c.x / maps[0].screen_width;
    explain_eye(params, cameras[static_cast<std::size_t>(eye)], eye, report);
    explain_map(maps[static_cast<std::size_t>(eye)], report);
    for (const auto& [x, y] : explain_stereo_resolve(c, params, maps, report))
        explain_stereo_texel(c, maps, cameras, bvh, x, y, report);
}

}  // namespace fovref
