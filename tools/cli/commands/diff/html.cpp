// The HTML report of `fovref diff`: one self-contained file (images as PNG data: URIs, plots as
// inline SVG, no script needed to read it), which opens in any browser without a server.
// Layout: a summary (pass/fail, the first failing stage highlighted and linked, the probe
// command), a table of every buffer in pipeline order, then a section per compared buffer with
// golden / candidate / error heatmap side by side, the figures, the worst pixels and the
// ring-error plots. A small script only counts the images that decoded and checks the plots'
// layout (for the headless-browser tests).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "ref/metrics/heatmap.h"
#include "ref/stage/frame.h"
#include "tools/cli/commands/diff/report.h"
#include "tools/cli/common/number_text.h"
#include "tools/cli/report/svg_plot.h"

namespace fs = std::filesystem;

namespace fovref {

namespace {

std::string base64(const std::string& bytes) {
    static const char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    std::string out;
    out.reserve((bytes.size() + 2) / 3 * 4);
    for (std::size_t i = 0; i < bytes.size(); i += 3) {
        const auto b0 = static_cast<unsigned char>(bytes[i]);
        const auto b1 = i + 1 < bytes.size() ? static_cast<unsigned char>(bytes[i + 1]) : 0u;
        const auto b2 = i + 2 < bytes.size() ? static_cast<unsigned char>(bytes[i + 2]) : 0u;
        const unsigned v = (b0 << 16) | (b1 << 8) | b2;
        out += table[(v >> 18) & 63];
        out += table[(v >> 12) & 63];
        out += i + 1 < bytes.size() ? table[(v >> 6) & 63] : '=';
        out += i + 2 < bytes.size() ? table[v & 63] : '=';
    }
    return out;
}

BufferKind kind_from_name(const std::string& kind) {
    for (const BufferKind k : {BufferKind::color, BufferKind::depth, BufferKind::id,
                               BufferKind::vector, BufferKind::scalar})
        if (kind == buffer_kind_name(k)) return k;
    return BufferKind::scalar;
}

// Images larger than this are shown box-downscaled by an integer factor (the report stays small).
constexpr std::size_t max_preview_pixels = 1u << 20;

Image downscale(const Image& image) {
    std::size_t factor = 1;
    while (image.pixel_count() / (factor * factor) > max_preview_pixels) ++factor;
    if (factor == 1) return image;
    // ceil(W / f) x ceil(H / f): a side shorter than f keeps one pixel (a 1048577 x 1 image
    // used to round to 0 rows); edge boxes average the pixels they have.
    const auto f = static_cast<int>(factor);
    Image out((image.width + f - 1) / f, (image.height + f - 1) / f, image.channels);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < image.channels; ++c) {
                double sum = 0;
                int count = 0;
                for (int j = y * f; j < std::min(image.height, (y + 1) * f); ++j)
                    for (int i = x * f; i < std::min(image.width, (x + 1) * f); ++i) {
                        sum += image.at(i, j, c);
                        ++count;
                    }
                out.at(x, y, c) = static_cast<float>(sum / count);
            }
    return out;
}

std::string img_tag(const Image& image, const std::string& alt) {
    return "<img class=\"shot\" alt=\"" + html_escape(alt) + "\" src=\"data:image/png;base64," +
           base64(encode_png(downscale(image))) + "\">";
}

std::string preview_tag(const Image& image, const std::string& kind, const std::string& alt) {
    Buffer b;
    b.kind = kind_from_name(kind);
    b.image = image;
    return img_tag(preview_image(b), alt);
}

std::string fmt(double v, const char* format = "%.4g") { return number_text(v, format, "&ndash;"); }

std::string values_text(const std::vector<float>& values) {
    std::string out;
    for (std::size_t i = 0; i < values.size(); ++i)
        out += (i ? ", " : "") + fmt(static_cast<double>(values[i]), "%.9g");
    return out;
}

std::string anchor(std::size_t k) { return "b" + std::to_string(k); }

std::string status_class(const DiffItem& item) {
    return !item.compared ? (item.required ? "status-fail" : "status-missing")
           : item.pass    ? "status-pass"
                          : "status-fail";
}

std::string colour_css(glm::vec3 c) {
    char text[32];
    std::snprintf(text, sizeof text, "rgb(%d,%d,%d)", static_cast<int>(c.x * 255.0f + 0.5f),
                  static_cast<int>(c.y * 255.0f + 0.5f), static_cast<int>(c.z * 255.0f + 0.5f));
    return text;
}

std::string percent(std::int64_t part, std::int64_t whole) {
    return fmt(whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0,
               "%.3g%%");
}

std::string ring_plots(const BufferComparison& r) {
    PlotSeries psnr{"PSNR (dB)", {}, {}}, ssim{"SSIM", {}, {}}, rmse{"RMSE", {}, {}},
        sd{"SD of squared error", {}, {}};
    for (const RingStats& s : r.rings) {
        const double mid = 0.5 * (static_cast<double>(s.inner_deg) + s.outer_deg);
        for (PlotSeries* p : {&psnr, &ssim, &rmse, &sd}) p->x.push_back(mid);
        psnr.y.push_back(s.psnr);
        ssim.y.push_back(s.ssim);
        rmse.y.push_back(s.rmse);
        sd.y.push_back(s.sd);
    }
    std::string out = "<div class=\"plots\">";
    out += svg_line_plot({"PSNR per ring", "eccentricity (degrees)", "dB", {psnr}});
    out += svg_line_plot({"SSIM per ring", "eccentricity (degrees)", "SSIM", {ssim}});
    out += svg_line_plot({"RMSE and SD per ring", "eccentricity (degrees)", "", {rmse, sd}});
    return out + "</div>";
}

// A buffer-space image's errors along its axes: per column (u: a log-polar or Visual-Polar
// buffer's radius) and per row (v: its angle), where screen images get rings.
std::string axis_plots(const BufferComparison& r) {
    PlotSeries columns{"RMSE", {}, r.column_rmse}, rows{"RMSE", {}, r.row_rmse};
    for (std::size_t k = 0; k < r.column_rmse.size(); ++k)
        columns.x.push_back(static_cast<double>(k));
    for (std::size_t k = 0; k < r.row_rmse.size(); ++k) rows.x.push_back(static_cast<double>(k));
    std::string out = "<div class=\"plots\">";
    out += svg_line_plot({"RMSE per column (along u)", "column u (buffer space)", "", {columns}});
    out += svg_line_plot({"RMSE per row (along v)", "row v (buffer space)", "", {rows}});
    return out + "</div>";
}

// An id buffer: both previews, the mismatch map with markers, the counts and the mismatches.
std::string id_section(const DiffItem& item) {
    const IdComparison& r = item.ids;
    std::string h =
        "<p>files: golden <code>" + html_escape(item.golden_file) + "</code>, candidate <code>" +
        html_escape(item.candidate_file) + "</code>; " + std::to_string(r.width) + "&times;" +
        std::to_string(r.height) + "; compared as integers; tolerance: " +
        std::to_string(r.tolerance.max_interior_mismatches) + " interior mismatches, " +
        fmt(100.0 * r.tolerance.max_edge_mismatch_share) + "% of the edge pixels" +
        (r.tolerance.reason.empty() ? "" : " (" + html_escape(r.tolerance.reason) + ")") + "</p>\n";
    h += "<p>" + std::to_string(r.interior_mismatches) + " interior mismatches, " +
         std::to_string(r.edge_mismatches) + " edge mismatches (" +
         percent(r.edge_mismatches, r.edge_pixels) + " of " +
         count_text(r.edge_pixels, "edge pixel") + ", " +
         std::to_string(r.allowed_edge_mismatches) +
         " allowed). An edge pixel has another id in the golden's 3&times;3 neighbourhood.</p>\n";
    h += "<div class=\"shots\"><figure>" +
         preview_tag(item.golden, item.kind, "golden " + item.name) +
         "<figcaption>golden</figcaption></figure><figure>" +
         preview_tag(item.candidate, item.kind, "candidate " + item.name) +
         "<figcaption>candidate</figcaption></figure>";
    if (r.edge_mismatches + r.interior_mismatches > 0) {
        Buffer b;
        b.kind = BufferKind::id;
        b.image = item.golden;
        h += "<figure>" +
             img_tag(id_mismatch_image(preview_image(b), r.mismatch_map),
                     "id mismatches " + item.name) +
             "<figcaption>mismatches marked: <span class=\"key\" style=\"background:" +
             colour_css(interior_marker_colour) +
             "\"></span>interior <span class=\"key\" style=\"background:" +
             colour_css(edge_marker_colour) + "\"></span>edge</figcaption></figure>";
    }
    h += "</div>\n";
    if (!r.mismatches.empty()) {
        h += "<table><tr><th>mismatch</th><th>x</th><th>y</th><th class=\"l\">kind</th>"
             "<th class=\"l\">golden</th><th class=\"l\">candidate</th></tr>\n";
        for (std::size_t i = 0; i < r.mismatches.size(); ++i) {
            const IdMismatch& m = r.mismatches[i];
            h += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + std::to_string(m.x) +
                 "</td><td>" + std::to_string(m.y) + "</td><td class=\"l\">" +
                 (m.edge ? "edge" : "interior") + "</td><td class=\"l\">" + values_text(m.golden) +
                 "</td><td class=\"l\">" + values_text(m.candidate) + "</td></tr>\n";
        }
        h += "</table>\n";
    }
    return h;
}

const char* style = R"(
body{font-family:sans-serif;margin:1.5em;color:#222}
table{border-collapse:collapse;margin:.5em 0}
td,th{border:1px solid #ccc;padding:2px 6px;text-align:right;font-size:13px}
td.l,th.l{text-align:left}
tr.fail td{background:#fde2e1} tr.first td{background:#f8b4b0;font-weight:bold}
tr.missing td{color:#777;font-style:italic}
.status-pass{color:#137333;font-weight:bold} .status-fail{color:#b3261e;font-weight:bold}
.status-missing{color:#8a6d00;font-weight:bold;font-style:italic}
.key{display:inline-block;width:10px;height:10px;border:1px solid #555;margin:0 3px}
section{border:1px solid #ddd;border-radius:6px;padding:.6em 1em;margin:1em 0}
section.first-failing{border:3px solid #b3261e}
summary{font-size:1.25em;font-weight:bold;cursor:pointer;padding:.3em 0}
.shots{display:flex;gap:12px;flex-wrap:wrap;align-items:flex-start}
.shots figure{margin:0} .shots figcaption{font-size:12px;color:#555}
img.shot{image-rendering:pixelated;max-width:640px;min-width:360px;border:1px solid #999}
.plots{display:flex;gap:8px;flex-wrap:wrap}
code{background:#f3f3f3;padding:1px 4px}
)";

// Summary: the paths, the case, the result and the first failing stage with its probe command.
std::string summary_html(const DiffReport& report) {
    std::string h =
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>"
        "fovref diff: " +
        html_escape(report.case_name.empty() ? report.golden : report.case_name) +
        "</title>\n<style>" + style + "</style></head>\n<body>\n";
    h += "<h1>fovref diff</h1>\n<p>golden <code>" + html_escape(report.golden) + "</code>";
    if (!report.case_name.empty())
        h += " (case <b>" + html_escape(report.case_name) + "</b>, mode " +
             html_escape(report.mode) +
             (report.scene.empty() ? "" : ", scene " + html_escape(report.scene)) + ")";
    h += "<br>candidate <code>" + html_escape(report.candidate) + "</code></p>\n";
    h += std::string("<p id=\"result\" class=\"") + (report.pass ? "status-pass" : "status-fail") +
         "\">RESULT: " + (report.pass ? "PASS" : "FAIL") + " &mdash; " +
         html_escape(result_counts(report)) + "</p>\n";
    if (report.first_failing >= 0) {
        const auto k = static_cast<std::size_t>(report.first_failing);
        const DiffItem& f = report.items[k];
        h += "<p id=\"first-failing\">First failing stage: <a href=\"#" + anchor(k) + "\"><b>" +
             html_escape(f.stage) + "</b>, buffer <b>" + html_escape(f.name) + "</b>, frame " +
             std::to_string(f.frame) + "</a> (later stages inherit its error).</p>\n";
        if (!report.probe_command.empty())
            h += "<p>Explain the pixel it points at (its first interior id mismatch, else its "
                 "worst pixel): <code>" +
                 html_escape(report.probe_command) + "</code></p>\n";
    }
    return h;
}

// Item k's row of the table of all buffers.
std::string table_row(const DiffReport& report, std::size_t k) {
    const DiffItem& item = report.items[k];
    const bool first = static_cast<int>(k) == report.first_failing;
    const std::string cls = !item.compared && !item.required ? "missing"
                            : first                          ? "first"
                            : !item.pass                     ? "fail"
                                                             : "";
    std::string h = "<tr class=\"" + cls + "\"><td>" + std::to_string(item.frame) +
                    "</td><td class=\"l\">" + html_escape(item.stage) +
                    "</td><td class=\"l\"><a href=\"#" + anchor(k) + "\">" +
                    html_escape(item.name) + "</a></td><td class=\"" + status_class(item) + "\">" +
                    item.status() + "</td>";
    if (!item.compared || item.hash_only)
        return h + "<td class=\"l\" colspan=\"8\">" + html_escape(item.note) + "</td></tr>\n";
    if (item.is_id) {
        const IdComparison& r = item.ids;
        return h + "<td class=\"l\" colspan=\"8\">compared as ids: " +
               std::to_string(r.interior_mismatches) + " interior mismatches (" +
               std::to_string(r.tolerance.max_interior_mismatches) + " allowed), " +
               std::to_string(r.edge_mismatches) +
               " edge mismatches = " + percent(r.edge_mismatches, r.edge_pixels) + " of " +
               count_text(r.edge_pixels, "edge pixel") + " (" +
               std::to_string(r.allowed_edge_mismatches) + " allowed)</td></tr>\n";
    }
    const BufferComparison& r = item.result;
    const std::int64_t compared_pixels =
        static_cast<std::int64_t>(r.width) * r.height - r.masked_pixels;
    const bool nonfinite = r.nonfinite_mismatches > 0;
    return h + "<td>" + (nonfinite ? std::string("convention?") : fmt(r.max_abs)) + "</td><td>" +
           fmt(r.max_rel) + "</td><td>" + std::to_string(r.max_ulp) + "</td><td>" +
           std::to_string(r.failing_pixels) + "</td><td>" +
           percent(r.pixels_over_threshold, compared_pixels) + "</td><td>" +
           (nonfinite ? "&ndash;" : fmt(r.rmse)) + "</td><td>" +
           (nonfinite ? "&ndash;" : fmt(r.psnr)) + "</td><td>" +
           (r.ssim ? fmt(*r.ssim, "%.6f") : "&ndash;") + "</td></tr>\n";
}

// The table of all buffers in comparison order, what "out of tolerance" means, and the
// candidate files that were ignored.
std::string table_html(const DiffReport& report) {
    std::string h =
        "<table><tr><th>frame</th><th class=\"l\">stage</th><th class=\"l\">buffer</th>"
        "<th>result</th><th>max abs</th><th>max rel</th><th>max ulp</th><th>failing px</th>"
        "<th>out of tolerance</th><th>RMSE</th><th>PSNR</th><th>SSIM</th></tr>\n";
    for (std::size_t k = 0; k < report.items.size(); ++k) h += table_row(report, k);
    h += "</table>\n";
    h += "<p>&ldquo;out of tolerance&rdquo;: share of the compared pixels outside the buffer's "
         "own tolerance (of the pixels over <code>--threshold</code> when one is given). Id "
         "buffers are compared as integers; the other buffers of a frame only where its ids "
         "agree.</p>\n";
    for (std::size_t k = 0; k < report.ignored.size(); ++k)
        h += "<p class=\"status-missing\">ignored: <code>" + html_escape(report.ignored[k]) +
             "</code> matches no golden buffer" +
             (report.ignored_hint[k].empty()
                  ? std::string()
                  : "; did you mean <code>" + html_escape(report.ignored_hint[k]) + "</code>?") +
             "</p>\n";
    return h;
}

// Golden, candidate and (where they differ) the error heatmap side by side.
std::string pictures_html(const DiffItem& item) {
    const BufferComparison& r = item.result;
    const bool differs = r.max_abs > 0.0 || r.nonfinite_mismatches > 0;
    HeatmapSettings hs;
    hs.rings = item.rings ? &*item.rings : nullptr;
    std::string h = "<div class=\"shots\"><figure>" +
                    preview_tag(item.golden, item.kind, "golden " + item.name) +
                    "<figcaption>golden</figcaption></figure><figure>" +
                    preview_tag(item.candidate, item.kind, "candidate " + item.name) +
                    "<figcaption>candidate</figcaption></figure>";
    if (differs) {
        // A few failing pixels are marked (a single wrong value is one pixel of the map)
        Image map = heatmap(r.abs_error, hs);
        const bool isolated =
            r.failing_pixels > 0 &&
            r.failing_pixels <= static_cast<std::int64_t>(r.failing_listed.size());
        if (isolated) mark_pixels(map, r.width, r.height, r.failing_listed, interior_marker_colour);
        h += "<figure>" + img_tag(map, "error heatmap " + item.name) +
             "<figcaption>|candidate &minus; golden| (largest channel), scale 0 .. " +
             fmt(heatmap_scale(r.abs_error, hs)) + (hs.rings ? ", ring boundaries lighter" : "") +
             (isolated
                  ? ", the " + count_text(r.failing_pixels, "pixel") + " out of tolerance ringed"
                  : "") +
             "</figcaption></figure>";
    }
    h += "</div>\n";
    return h;
}

// The error figures of a value buffer, its LDR-FLIP (--flip) and its worst pixels.
std::string figures_html(const DiffItem& item) {
    const BufferComparison& r = item.result;
    std::string h;
    if (r.nonfinite_mismatches > 0)
        h += "<p class=\"status-fail\">convention mismatch: " +
             std::to_string(r.nonfinite_mismatches) +
             " value(s) are non-finite on one side only (e.g. a depth cleared to +inf where "
             "fovref writes 0); no error figure is defined for them and the figures below "
             "cover the values finite on both sides.</p>\n";
    h += "<p>max abs " + fmt(r.max_abs) + ", max rel " + fmt(r.max_rel) + ", max ulp " +
         std::to_string(r.max_ulp) + ", non-finite mismatches " +
         std::to_string(r.nonfinite_mismatches) + ", mean abs " + fmt(r.mean_abs) + ", RMSE " +
         fmt(r.rmse) + ", PSNR " + fmt(r.psnr) + " dB, SSIM " +
         (r.ssim ? fmt(*r.ssim, "%.6f") : "&ndash;") + ", " +
         (r.threshold >= 0.0 ? "pixels over " + fmt(r.threshold)
                             : std::string("pixels out of tolerance")) +
         ": " + std::to_string(r.pixels_over_threshold) + "</p>\n";
    if (item.flip)
        h += "<p>LDR-FLIP (display space): mean " + fmt(item.flip->mean, "%.6f") +
             ", weighted median " + fmt(item.flip->weighted_median, "%.6f") + ", quartiles " +
             fmt(item.flip->first_quartile, "%.6f") + " / " +
             fmt(item.flip->third_quartile, "%.6f") + ", max " + fmt(item.flip->max, "%.6f") +
             "; " + fmt(item.flip_ppd, "%.4g") + " pixels per degree (" +
             html_escape(item.flip_observer) + ")</p>\n<div class=\"shots\"><figure>" +
             img_tag(heatmap(item.flip->error_map, HeatmapSettings{1.0f, true, nullptr}),
                     "FLIP map " + item.name) +
             "<figcaption>FLIP error map (scale 0 .. 1)</figcaption></figure></div>\n";
    if (!r.worst.empty()) {
        h += "<table><tr><th>worst pixels</th><th>x</th><th>y</th><th>|error|</th>"
             "<th class=\"l\">golden</th><th class=\"l\">candidate</th></tr>\n";
        for (std::size_t i = 0; i < r.worst.size(); ++i)
            h += "<tr><td>" + std::to_string(i + 1) + "</td><td>" + std::to_string(r.worst[i].x) +
                 "</td><td>" + std::to_string(r.worst[i].y) + "</td><td>" +
                 fmt(r.worst[i].abs_error) + "</td><td class=\"l\">" +
                 values_text(r.worst[i].golden) + "</td><td class=\"l\">" +
                 values_text(r.worst[i].candidate) + "</td></tr>\n";
        h += "</table>\n";
    }
    return h;
}

// Item k's section: failing buffers open, the others folded away under their title.
std::string section_html(const DiffReport& report, std::size_t k) {
    const DiffItem& item = report.items[k];
    const bool first = static_cast<int>(k) == report.first_failing;
    const bool open = !item.pass || first;
    std::string h = "<section id=\"" + anchor(k) + "\"" +
                    (first ? " class=\"first-failing\"" : "") + "><details" +
                    (open ? " open" : "") + "><summary>frame " + std::to_string(item.frame) +
                    " &middot; " + html_escape(item.stage) + " &middot; " + html_escape(item.name) +
                    " <span class=\"" + status_class(item) + "\">" + item.status() + "</span>" +
                    (first ? " &larr; first failing stage" : "") + "</summary>\n";
    if (!item.note.empty()) h += "<p>" + html_escape(item.note) + "</p>\n";
    if (!item.compared || item.hash_only) return h + "</details></section>\n";
    if (item.is_id) return h + id_section(item) + "</details></section>\n";
    const BufferComparison& r = item.result;
    h += "<p>files: golden <code>" + html_escape(item.golden_file) + "</code>, candidate <code>" +
         html_escape(item.candidate_file) + "</code>; " + std::to_string(r.width) + "&times;" +
         std::to_string(r.height) + "&times;" + std::to_string(r.channels) + "; tolerance abs " +
         fmt(r.tolerance.abs) + ", rel " + fmt(r.tolerance.rel) + ", ulp " +
         std::to_string(r.tolerance.ulp) + ", " +
         count_text(r.tolerance.max_failing_pixels, "failing pixel") + " allowed" +
         (r.tolerance.reason.empty() ? "" : " (" + html_escape(r.tolerance.reason) + ")") +
         "</p>\n";
    if (!item.masked_by.empty()) {
        std::string names;
        for (const std::string& n : item.masked_by) names += (names.empty() ? "" : ", ") + n;
        h += "<p>compared where <code>" + html_escape(names) +
             "</code> agree: " + count_text(r.masked_pixels - item.margin_pixels, "pixel") +
             " left out.</p>\n";
    }
    if (item.margin_pixels > 0)
        h += "<p>--margin: " + count_text(item.margin_pixels, "pixel") +
             " of the border band left out.</p>\n";
    // Pictures: every failing buffer and every colour buffer.
    if (!item.pass || item.kind == "color") h += pictures_html(item);
    h += figures_html(item);
    if (!r.rings.empty() && r.max_abs > 0.0) h += ring_plots(r);
    if (!r.column_rmse.empty() && r.max_abs > 0.0) h += axis_plots(r);
    h += "</details></section>\n";
    return h;
}

// A small script (not needed to read the report) counts the images that decoded and checks the
// layout of every plot (sections opened for the measurement, then folded back): labels inside
// their plot, tick labels distinct. The headless-browser tests read both lines.
const char* const check_script =
    "<p id=\"images-status\">images: <span id=\"images-loaded\">not counted (scripts off)"
    "</span>; plots: <span id=\"plot-check\">not checked (scripts off)</span></p>\n"
    "<script>addEventListener('load',function(){var i=document.images,n=0;"
    "for(var k=0;k<i.length;++k)if(i[k].complete&&i[k].naturalWidth>0)++n;"
    "document.getElementById('images-loaded').textContent=n+' of '+i.length+' decoded';"
    "var d=document.querySelectorAll('details'),was=[];for(var k=0;k<d.length;++k)"
    "{was.push(d[k].open);d[k].open=true;}"
    "var s=document.querySelectorAll('svg.plot'),labels=0,clipped=0,repeated=0;"
    "for(var k=0;k<s.length;++k){var r=s[k].getBoundingClientRect();"
    "var t=s[k].querySelectorAll('text');"
    "for(var j=0;j<t.length;++j){var b=t[j].getBoundingClientRect();++labels;"
    "if(b.left<r.left-0.5||b.right>r.right+0.5||b.top<r.top-0.5||b.bottom>r.bottom+0.5)"
    "++clipped;}['tick-x','tick-y'].forEach(function(c){var seen={},u=s[k]."
    "querySelectorAll('text.'+c);for(var j=0;j<u.length;++j){if(seen[u[j].textContent])"
    "++repeated;seen[u[j].textContent]=1;}});}"
    "for(var k=0;k<d.length;++k)d[k].open=was[k];"
    "document.getElementById('plot-check').textContent=s.length+' plots, '+labels+"
    "' labels, '+clipped+' clipped, '+repeated+' repeated ticks';});"
    "</script>\n</body></html>\n";

}  // namespace

void write_diff_html(const DiffReport& report, const std::string& directory) {
    std::string h = summary_html(report);
    h += table_html(report);
    for (std::size_t k = 0; k < report.items.size(); ++k) h += section_html(report, k);
    h += check_script;

    std::error_code ec;
    fs::create_directories(directory, ec);
    if (ec) throw Error(directory + ": cannot create the report directory: " + ec.message());
    write_file_atomic((fs::path(directory) / "index.html").string(), h);
}

}  // namespace fovref
