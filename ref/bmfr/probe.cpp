#include "ref/bmfr/probe.h"

#include <cstring>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/bmfr_params.h"
#include "ref/core/error.h"
#include "ref/trace/trace_probe.h"

namespace fovref {

void explain_bmfr_block(const ProbeContext& c, const VisualPolarMap& m, int i, int j,
                        ProbeReport& report) {
    ProbeSection b{"bmfr_fit", "the BMFR block of this texel (staircase grid, rows wrap)", {}};
    const BmfrGrid g = bmfr_grid(m.width, m.height, c.frame->frame, &m,
                                 parse_bmfr_params(c.settings->params, "bmfr").params.block_size);
    const glm::ivec2 cell = g.cell_of(i, j);
    const glm::ivec2 o = g.origin(cell.x, cell.y);
    b.add("cell", "(" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + ") of " +
                      std::to_string(g.cells_x) + " block columns");
    b.add("block column",
          "phi height H = " + std::to_string(g.cell_rows[static_cast<std::size_t>(cell.x)]) +
              " rows, " + std::to_string(g.cells_in_column(cell.x)) + " blocks");
    b.add("origin", "(" + std::to_string(o.x) + ", " + std::to_string(o.y) +
                        "): columns clamped to [0, w - 1], rows modulo H; offset (" +
                        std::to_string(g.offset.x) + ", " + std::to_string(g.offset.y) + ")");
    const Image& w = c.frame->find("bmfr_weights")->image;
    std::string red;
    for (int k = 0; k < bmfr_feature_count; ++k)
        red += (k ? ", " : "") + probe_float(w.at(cell.x, cell.y, k));
    b.add("red weights", red);
    report.sections.push_back(b);
}

namespace {

const Image& image_of(const FrameResult& f, const std::string& name) {
    const Buffer* b = f.find(name);
    FOVREF_CHECK(b != nullptr, "probe: the frame has no buffer '" + name + "'");
    return b->image;
}

glm::vec3 rgb(const Image& image, int x, int y) {
    return {image.at(x, y, 0), image.at(x, y, 1), image.at(x, y, 2)};
}

std::string point(glm::vec2 p) { return "(" + probe_float(p.x) + ", " + probe_float(p.y) + ")"; }

// A scalar of the recomputation against the rendered buffer, bit for bit.
void check_scalar(ProbeReport& report, ProbeSection& s, const std::string& what, float mine,
                  float rendered) {
    const bool same = std::memcmp(&mine, &rendered, sizeof mine) == 0;
    s.add("check", what + ": " +
                       (same ? "bit-identical to the rendered buffer"
                             : "DIFFERS from the rendered buffer " + probe_float(rendered)));
    if (!same) report.consistent = false;
}

// What frame f's phases read from frame f - 1: its camera, G-buffer and accumulations (the
// stages hand on the same images; none for frame 0).
BmfrHistory previous_history(const ProbeContext& c) {
    BmfrHistory h;
    if (!c.previous_frame || !c.previous_frame->camera) return h;
    const FrameResult& p = *c.previous_frame;
    h.valid = true;
    h.view_projection = view_projection(*p.camera, c.settings->width, c.settings->height);
    h.world_position = image_of(p, "gbuffer_world_position");
    h.normal = image_of(p, "gbuffer_shading_normal");
    h.accumulated_noisy = image_of(p, "bmfr_accumulated_noisy");
    h.spp = image_of(p, "bmfr_spp");
    h.accumulated_filtered = image_of(p, "bmfr_accumulated_filtered");
    h.taa = image_of(p, "bmfr_taa");
    return h;
}

std::string vec(glm::vec3 v) { return probe_vec3(v); }

// [bmfr_accumulate_noisy]: the reprojection, the four taps with their accept bits, the blend.
void explain_phase_one(const ProbeContext& c, const BmfrParams& params, const BmfrHistory& h,
                       BmfrAccumulation& out, ProbeReport& report) {
    const FrameResult& f = *c.frame;
    const int x = c.x, y = c.y, width = c.settings->width, height = c.settings->height;
    const Image& world = image_of(f, "gbuffer_world_position");
    const Image& normal = image_of(f, "gbuffer_shading_normal");
    ProbeSection s{"bmfr_accumulate_noisy",
                   "phase I: the noisy illumination blended with its reprojected history "
                   "(SPEC §9 item 2, docs/bmfr.md)",
                   {}};
    s.add("illumination", vec(rgb(image_of(f, "bmfr_illumination"), x, y)) +
                              " = radiance / max(albedo, " + probe_float(params.albedo_floor) +
                              ") (bmfr_illumination)");
    BmfrStats stats;
    out = BmfrAccumulation{Image(width, height, 3), Image(width, height, 1),
                           Image(width, height, 1), Image(width, height, 2), Image()};
    bmfr_accumulate_noisy_pixel(params, image_of(f, "bmfr_illumination"), world, normal, h, h.valid,
                                {}, out, x, y, stats);
    const glm::vec2 q{out.previous_pixel.at(x, y, 0), out.previous_pixel.at(x, y, 1)};
    if (!h.valid) {
        s.add("history", "none (frame 0): out = c, spp = 1");
    } else {
        s.add("reprojected", "q = " + point(q) + " (the world position " + vec(rgb(world, x, y)) +
                                 " through the previous camera)");
        const BmfrTaps taps = bmfr_taps(q);
        const auto bits = static_cast<unsigned>(out.accept.at(x, y));
        for (int k = 0; k < 4; ++k) {
            std::string text = "(" + std::to_string(taps.x[k]) + ", " + std::to_string(taps.y[k]) +
                               "), weight " + probe_float(taps.w[k]);
            if (taps.x[k] >= 0 && taps.y[k] >= 0 && taps.x[k] < width && taps.y[k] < height) {
                const glm::vec3 dp = rgb(h.world_position, taps.x[k], taps.y[k]) - rgb(world, x, y);
                const glm::vec3 dn = rgb(h.normal, taps.x[k], taps.y[k]) - rgb(normal, x, y);
                text += ": |P_k - P|^2 = " + probe_float(glm::dot(dp, dp)) + " (limit " +
                        probe_float(params.position_limit_squared) +
                        "), |n_k - n|^2 = " + probe_float(glm::dot(dn, dn)) + " (limit " +
                        probe_float(params.normal_limit_squared) + ")";
            } else {
                text += ": outside the image";
            }
            s.add("tap " + std::to_string(k),
                  text + ((bits >> k) & 1u ? ": accepted" : ": rejected"));
        }
        s.add("history spp", probe_float(out.spp.at(x, y)) +
                                 " after this frame (max 255); "
                                 "alpha = max(1 / (spp_h + 1), " +
                                 probe_float(params.noisy_alpha_min) + ")");
    }
    s.add("accumulated", vec(rgb(out.accumulated, x, y)));
    probe_check(report, s, "bmfr_accumulated_noisy", rgb(out.accumulated, x, y),
                rgb(image_of(f, "bmfr_accumulated_noisy"), x, y));
    check_scalar(report, s, "bmfr_spp", out.spp.at(x, y), image_of(f, "bmfr_spp").at(x, y));
    check_scalar(report, s, "bmfr_accept", out.accept.at(x, y),
                 image_of(f, "bmfr_accept").at(x, y));
    report.sections.push_back(s);
}

// [bmfr_fit] and [bmfr_weighted_sum]: the pixel's block, its features scaled with the block's
// ranges, the fitted weights and the pixel's fitted value.
void explain_fit(const ProbeContext& c, ProbeReport& report) {
    const FrameResult& f = *c.frame;
    const int x = c.x, y = c.y;
    BmfrFit fit;
    fit.grid = bmfr_grid(c.settings->width, c.settings->height, f.frame, nullptr,
                         parse_bmfr_params(c.settings->params).params.block_size);
    fit.weights = image_of(f, "bmfr_weights");
    fit.feature_range = image_of(f, "bmfr_feature_range");
    const glm::ivec2 cell = fit.grid.cell_of(x, y);
    const glm::ivec2 o = fit.grid.origin(cell.x, cell.y);
    ProbeSection b{"bmfr_fit", "phase II: the block this pixel belongs to, and its fit", {}};
    b.add("block", "cell (" + std::to_string(cell.x) + ", " + std::to_string(cell.y) + ") of " +
                       std::to_string(fit.grid.cells_x) + " x " + std::to_string(fit.grid.cells_y) +
                       ", pixels (" + std::to_string(o.x) + ".." +
                       std::to_string(o.x + fit.grid.block - 1) + ", " + std::to_string(o.y) +
                       ".." + std::to_string(o.y + fit.grid.block - 1) +
                       ") mirrored at the borders");
    b.add("offset", "(" + std::to_string(fit.grid.offset.x) + ", " +
                        std::to_string(fit.grid.offset.y) + "): the authors' offset " +
                        std::to_string(f.frame % 16) + " of 16 for frame " +
                        std::to_string(f.frame));
    float t[bmfr_feature_count];
    bmfr_features(rgb(image_of(f, "gbuffer_shading_normal"), x, y),
                  rgb(image_of(f, "gbuffer_world_position"), x, y), t);
    std::string raw, scaled;
    for (int k = 0; k < bmfr_feature_count; ++k) raw += (k ? ", " : "") + probe_float(t[k]);
    b.add("features", "T_0..9 = " + raw + " (1, n, w, w^2)");
    for (int k = 0; k < bmfr_scaled_count; ++k) {
        const float lo = fit.feature_range.at(cell.x, cell.y, k);
        const float hi = fit.feature_range.at(cell.x, cell.y, bmfr_scaled_count + k);
        scaled += (k ? ", " : "") +
                  probe_float(bmfr_scale_feature(t[bmfr_scaled_first + k], lo, hi)) + " [" +
                  probe_float(lo) + ", " + probe_float(hi) + "]";
    }
    b.add("scaled T_4..9", scaled + " ((v - min) / (max - min) when max - min > 1, else v - min)");
    for (int ch = 0; ch < 3; ++ch) {
        std::string w;
        for (int k = 0; k < bmfr_feature_count; ++k)
            w += (k ? ", " : "") +
                 probe_float(fit.weights.at(cell.x, cell.y, ch * bmfr_feature_count + k));
        b.add(std::string("weights ") + "rgb"[ch], w);
    }
    report.sections.push_back(b);

    ProbeSection s{
        "bmfr_weighted_sum", "the fit at this pixel: max(0, sum_i w_i T_i) per channel", {}};
    BmfrStats stats;
    Image out(c.settings->width, c.settings->height, 3);
    bmfr_weighted_sum_pixel(fit, image_of(f, "gbuffer_world_position"),
                            image_of(f, "gbuffer_shading_normal"), out, x, y, stats);
    s.add("fitted", vec(rgb(out, x, y)));
    probe_check(report, s, "bmfr_fitted", rgb(out, x, y), rgb(image_of(f, "bmfr_fitted"), x, y));
    report.sections.push_back(s);
}

// [bmfr_accumulate_filtered], [bmfr_remodulate], [bmfr_taa]: phase III, remodulation, the
// authors' TAA in YCoCg.
void explain_display(const ProbeContext& c, const BmfrParams& params, const BmfrHistory& h,
                     const BmfrAccumulation& phase_one, ProbeReport& report) {
    const FrameResult& f = *c.frame;
    const int x = c.x, y = c.y, width = c.settings->width, height = c.settings->height;
    ProbeSection p{"bmfr_accumulate_filtered",
                   "phase III: the fit blended with its history through phase I's accepted taps",
                   {}};
    Image filtered(width, height, 3);
    bmfr_accumulate_filtered_pixel(params, image_of(f, "bmfr_fitted"), phase_one.spp,
                                   phase_one.accept, phase_one.previous_pixel,
                                   h.valid ? h.accumulated_filtered : Image(), {}, filtered, x, y);
    p.add("alpha",
          "max(1 / spp, " + probe_float(params.filtered_alpha_min) + ") = " +
              probe_float(std::max(1.0f / phase_one.spp.at(x, y), params.filtered_alpha_min)) +
              (h.valid && phase_one.accept.at(x, y) != 0.0f
                   ? ""
                   : " (unused: no accepted tap, out = the fit)"));
    p.add("filtered", vec(rgb(filtered, x, y)));
    probe_check(report, p, "bmfr_accumulated_filtered", rgb(filtered, x, y),
                rgb(image_of(f, "bmfr_accumulated_filtered"), x, y));
    report.sections.push_back(p);

    ProbeSection r{"bmfr_remodulate",
                   "display = clamp((max(albedo, floor) max(0, x) + e)^g, 0, 1), g = bmfr_gamma, "
                   "floor = " +
                       probe_float(params.remodulation_floor) + " (bmfr_remodulate)",
                   {}};
    Image one(1, 1, 3), albedo(1, 1, 3), emission;
    for (int ch = 0; ch < 3; ++ch) {
        one.at(0, 0, ch) = image_of(f, "bmfr_accumulated_filtered").at(x, y, ch);
        albedo.at(0, 0, ch) = image_of(f, "gbuffer_albedo").at(x, y, ch);
    }
    if (params.separate_emission && f.find("emission")) {
        emission = Image(1, 1, 3);
        for (int ch = 0; ch < 3; ++ch) emission.at(0, 0, ch) = image_of(f, "emission").at(x, y, ch);
        r.add("emission", vec(rgb(emission, 0, 0)) + " (added back: bmfr_emission=separate)");
    }
    r.add("albedo", vec(rgb(albedo, 0, 0)));
    const Image display = bmfr_remodulate(params, one, albedo, emission);
    r.add("display", vec(rgb(display, 0, 0)));
    probe_check(report, r, "bmfr_display", rgb(display, 0, 0),
                rgb(image_of(f, "bmfr_display"), x, y));
    report.sections.push_back(r);

    ProbeSection t{"bmfr_taa",
                   "the authors' TAA: 3x3 YCoCg box, history at q clamped, 0.2 new + 0.8 history",
                   {}};
    const Image& shown = image_of(f, "bmfr_display");
    const glm::vec3 current = rgb(shown, x, y);
    t.add("new (YCoCg)", vec(glm::vec3(current.x + 2.0f * current.y + current.z,
                                       2.0f * current.x - 2.0f * current.z,
                                       -current.x + 2.0f * current.y - current.z)) +
                             " (Y = R + 2G + B, Co = 2R - 2B, Cg = -R + 2G - B, unnormalised)");
    Image out(width, height, 3);
    const Image history = h.valid ? h.taa : Image();
    const bool used = bmfr_taa_pixel(params, shown, history.empty() ? Image() : bmfr_ycocg(shown),
                                     phase_one.previous_pixel, history, {}, out, x, y);
    t.add("history", used ? "blended (q = " +
                                point({phase_one.previous_pixel.at(x, y, 0),
                                       phase_one.previous_pixel.at(x, y, 1)}) +
                                ")"
                          : "none used: the new colour alone");
    t.add("taa", vec(rgb(out, x, y)));
    probe_check(report, t, "bmfr_taa", rgb(out, x, y), rgb(image_of(f, "bmfr_taa"), x, y));
    Image linear_in(1, 1, 3);
    for (int ch = 0; ch < 3; ++ch) linear_in.at(0, 0, ch) = out.at(x, y, ch);
    const Image linear = bmfr_linearize(linear_in);
    t.add("output", vec(rgb(linear, 0, 0)) + " = taa^2.2 (linear)");
    if (const Buffer* final_buffer = f.find("final"))
        probe_check(report, t, "final", rgb(linear, 0, 0), rgb(final_buffer->image, x, y));
    report.sections.push_back(t);
}

}  // namespace

void explain_bmfr_pixel(const ProbeContext& c, ProbeReport& report) {
    if (c.texel || !c.frame->find("bmfr_weights") || !c.frame->find("gbuffer_world_position"))
        return;
    const BmfrParams params = parse_bmfr_params(c.settings->params).params;
    const BmfrHistory h = previous_history(c);
    BmfrAccumulation phase_one;
    explain_phase_one(c, params, h, phase_one, report);
    explain_fit(c, report);
    explain_display(c, params, h, phase_one, report);
}

}  // namespace fovref
