// `fovref sweep report OUT --html DIR` (docs/sweeps.md, "Report"): the merged results of a sweep
// as one self-contained HTML page. Per scene, screen and gaze: the Pareto front of time per frame
// and of rays traced per frame against the chosen error metric (every configuration a point, the
// front joined and enlarged), the ring-error curves of the configurations (Lund Fig. 5.6-5.7
// style), the table of configurations with the front they are on or the one that dominates them,
// and the work each one skipped. Every plot is also written as DIR/plots/NAME.svg and, where
// rsvg-convert (Debian librsvg2-bin) is installed, as NAME.png for slides.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include <spawn.h>
#include <sys/wait.h>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/image/image_io.h"
#include "tools/cli/commands/sweep.h"
#include "tools/cli/common/number_text.h"
#include "tools/cli/report/svg_plot.h"

extern char** environ;

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace fovref {

namespace {

/// One configuration of the results, with what the report plots.
struct Point {
    std::string id, label;
    double ms = NAN, rays = NAN, metric = NAN;  ///< ms: per frame
    const json* row = nullptr;
    bool time_front = false, rays_front = false;
    std::string dominated_by;  ///< on time: the label of a configuration that dominates it
};

struct Metric {
    const char* key;    ///< in results.json
    const char* label;  ///< on the axis
    bool higher_is_better;
};

Metric metric_of(const std::string& name) {
    if (name == "psnr") return {"psnr", "PSNR (dB, higher is better)", true};
    if (name == "ssim") return {"ssim", "SSIM (higher is better)", true};
    if (name == "flip") return {"flip_mean", "LDR-FLIP mean (lower is better)", false};
    return {"temporal_error", "temporal error (lower is better)", false};
}

double number_or_nan(const json& row, const char* key) {
    return row.contains(key) && row[key].is_number() ? row[key].get<double>() : NAN;
}

/// a dominates b: no worse in cost and in the metric, better in one of them.
bool dominates(double cost_a, double metric_a, double cost_b, double metric_b, bool higher) {
    const bool metric_no_worse = higher ? metric_a >= metric_b : metric_a <= metric_b;
    const bool metric_better = higher ? metric_a > metric_b : metric_a < metric_b;
    return cost_a <= cost_b && metric_no_worse && (cost_a < cost_b || metric_better);
}

/// Marks the non-dominated points on (cost, metric); returns them sorted by cost. Points whose
/// cost or metric is not finite are on no front.
std::vector<const Point*> pareto_front(std::vector<Point>& points, double Point::*cost,
                                       bool Point::*front, bool higher, bool record) {
    std::vector<const Point*> on_front;
    for (Point& p : points) {
        p.*front = false;
        if (!std::isfinite(p.*cost) || !std::isfinite(p.metric)) continue;
        const Point* by = nullptr;
        for (const Point& q : points)
            if (&q != &p && std::isfinite(q.*cost) && std::isfinite(q.metric) &&
                dominates(q.*cost, q.metric, p.*cost, p.metric, higher)) {
                by = &q;
                break;
            }
        p.*front = by == nullptr;
        if (record && by) p.dominated_by = by->label;
        if (!by) on_front.push_back(&p);
    }
    std::sort(on_front.begin(), on_front.end(), [&](const Point* a, const Point* b) {
        return a->*cost < b->*cost || (a->*cost == b->*cost && a->label < b->label);
    });
    return on_front;
}

std::string fmt(double v, const char* format = "%.4g") { return number_text(v, format, "&ndash;"); }

/// The plot inline, as DIR/plots/NAME.svg, and as NAME.png when rsvg-convert is available.
struct PlotWriter {
    fs::path dir;
    bool png = false;
    int written = 0, converted = 0;

    std::string operator()(const std::string& name, const PlotSpec& spec) {
        const std::string svg = svg_line_plot(spec);
        const fs::path svg_file = dir / "plots" / (name + ".svg");
        write_file_atomic(svg_file.string(), svg);
        ++written;
        std::string links = "<a href=\"plots/" + name + ".svg\">SVG</a>";
        if (png && to_png(svg_file, dir / "plots" / (name + ".png"))) {
            links += " &middot; <a href=\"plots/" + name + ".png\">PNG</a>";
            ++converted;
        }
        return "<figure>" + svg + "<figcaption>" + links + "</figcaption></figure>\n";
    }

    /// rsvg-convert -z 2 (twice the SVG's size, for slides) into a temporary file, renamed.
    static bool to_png(const fs::path& svg, const fs::path& png) {
        const std::string temporary = png.string() + ".tmp";
        std::vector<std::string> args = {"rsvg-convert", "-z", "2",       "-b",
                                         "white",        "-o", temporary, svg.string()};
        std::vector<char*> argv;
        for (std::string& a : args) argv.push_back(a.data());
        argv.push_back(nullptr);
        pid_t pid = 0;
        if (posix_spawnp(&pid, "rsvg-convert", nullptr, nullptr, argv.data(), environ) != 0)
            return false;
        int status = 0;
        if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
            std::error_code ignored;
            fs::remove(temporary, ignored);
            return false;
        }
        fs::rename(temporary, png);
        return true;
    }
};

bool have_rsvg_convert() {
    const char* path = std::getenv("PATH");
    std::string paths = path ? path : "/usr/bin:/bin";
    std::size_t start = 0;
    while (start <= paths.size()) {
        const std::size_t end = std::min(paths.find(':', start), paths.size());
        if (fs::exists(fs::path(paths.substr(start, end - start)) / "rsvg-convert")) return true;
        start = end + 1;
    }
    return false;
}

std::string slug(const std::string& text) {
    std::string s;
    for (char c : text) s += std::isalnum(static_cast<unsigned char>(c)) ? c : '-';
    return s;
}

/// The counters that say what a configuration skipped (or did), when present.
const char* const skip_counters[] = {"texels_traced",         "texels_off_screen",
                                     "texels_clipped",        "rays_shadow",
                                     "pixels_shaded",         "screen_pixels_untraced_taps",
                                     "bmfr_history_rejected", "taa_history_rejected"};

const char* const page_style =
    "body{font-family:sans-serif;margin:1.5em;max-width:1400px}table{border-collapse:collapse;"
    "margin:.6em 0}td,th{border:1px solid #ccc;padding:2px 6px;text-align:right;font-size:13px}"
    "td.l,th.l{text-align:left}tr.front td{background:#eef6ee}figure{display:inline-block;"
    "margin:.4em}figcaption{font-size:12px;text-align:center}h2{margin-top:1.6em}";

// The finished results by group (scene, screen and gaze), the groups in the order of the plan.
struct Groups {
    std::map<std::string, std::vector<Point>> points;
    std::vector<std::string> order;
    int missing = 0;  ///< jobs without a result
};

Groups read_groups(const json& results, const Metric& metric) {
    Groups g;
    for (const json& row : results["results"]) {
        if (row["status"] != "done") {
            ++g.missing;
            continue;
        }
        const std::string group =
            row["scene"].get<std::string>() + ", " + std::to_string(row["width"].get<int>()) + "x" +
            std::to_string(row["height"].get<int>()) + ", gaze " + row["gaze"].get<std::string>();
        if (!g.points.count(group)) g.order.push_back(group);
        Point p;
        p.id = row["id"].get<std::string>();
        p.label = row["mode"].get<std::string>();
        for (const auto& [key, value] : row["params"].items())
            p.label += " " + key + "=" + value.get<std::string>();
        p.ms = 1e3 * number_or_nan(row, "seconds_per_frame");
        p.rays = number_or_nan(row, "rays_traced_per_frame");
        p.metric = number_or_nan(row, metric.key);
        p.row = &row;
        g.points[group].push_back(p);
    }
    return g;
}

// A Pareto plot: every configuration as a dot, the front joined.
PlotSpec pareto_plot(const std::vector<Point>& points, const Metric& metric, const char* title,
                     const char* x_label, double Point::*cost,
                     const std::vector<const Point*>& front) {
    PlotSeries all{"configurations", {}, {}, false, 3.0, {}};
    PlotSeries joined{"Pareto front", {}, {}, true, 4.5, {}};
    for (const Point& p : points) {
        all.x.push_back(p.*cost);
        all.y.push_back(p.metric);
        all.tips.push_back(p.label + ": " + fmt(p.*cost) + ", " + fmt(p.metric));
    }
    for (const Point* p : front) {
        joined.x.push_back(p->*cost);
        joined.y.push_back(p->metric);
        joined.tips.push_back(p->label);
    }
    PlotSpec spec{title, x_label, metric.label, {all, joined}, 460, 300};
    spec.x_scale = PlotScale::automatic;
    return spec;
}

// Ring-error curves: every configuration (the front's only, when there are more than 8).
PlotSpec ring_plot(const std::vector<Point>& points) {
    PlotSpec rings{"PSNR per error ring", "eccentricity (degrees)", "dB", {}, 460, 300};
    for (const Point& p : points) {
        if (points.size() > 8 && !p.time_front) continue;
        PlotSeries s{p.label, {}, {}, true, 2.0, {}};
        const json& deg = (*p.row)["ring_outer_deg"];
        const json& psnr = (*p.row)["ring_psnr"];
        for (std::size_t k = 0; k < deg.size() && k < psnr.size(); ++k) {
            s.x.push_back(deg[k].get<double>());
            s.y.push_back(psnr[k].is_number() ? psnr[k].get<double>() : NAN);
        }
        rings.series.push_back(s);
    }
    return rings;
}

// The table: every configuration, fastest first.
std::string configurations_table(const std::vector<const Point*>& sorted) {
    std::string body =
        "<table class=\"configurations\"><tr><th class=\"l\">configuration</th>"
        "<th>ms per frame</th><th>rays per frame</th><th>PSNR</th><th>SSIM</th>"
        "<th>FLIP</th><th>temporal</th><th>front (time)</th><th>front (rays)</th>"
        "<th class=\"l\">dominated by (time)</th></tr>\n";
    for (const Point* p : sorted) {
        const json& r = *p->row;
        body += std::string("<tr") + (p->time_front ? " class=\"front\"" : "") +
                "><td class=\"l\" title=\"" + html_escape(p->id) + "\">" + html_escape(p->label) +
                "</td><td>" + fmt(p->ms) + "</td><td>" + fmt(p->rays, "%.0f") + "</td><td>" +
                fmt(number_or_nan(r, "psnr")) + "</td><td>" + fmt(number_or_nan(r, "ssim")) +
                "</td><td>" + fmt(number_or_nan(r, "flip_mean")) + "</td><td>" +
                fmt(number_or_nan(r, "temporal_error")) + "</td><td>" +
                (p->time_front ? "yes" : "") + "</td><td>" + (p->rays_front ? "yes" : "") +
                "</td><td class=\"l\">" + html_escape(p->dominated_by) + "</td></tr>\n";
    }
    return body + "</table>\n";
}

// The work skipped (and done), per frame, from the modes' counters.
std::string work_table(const std::vector<Point>& points, const std::vector<const Point*>& sorted) {
    std::string body = "<table class=\"skipped\"><tr><th class=\"l\">work per frame</th>";
    std::vector<std::string> shown;
    for (const char* c : skip_counters)
        for (const Point& p : points)
            if ((*p.row).contains("counters_per_frame") &&
                (*p.row)["counters_per_frame"].contains(c)) {
                shown.push_back(c);
                break;
            }
    for (const std::string& c : shown) body += "<th>" + html_escape(c) + "</th>";
    body += "</tr>\n";
    for (const Point* p : sorted) {
        body += "<tr><td class=\"l\">" + html_escape(p->label) + "</td>";
        const json& counters = (*p->row).value("counters_per_frame", json::object());
        for (const std::string& c : shown)
            body += "<td>" +
                    (counters.contains(c) ? fmt(counters[c].get<double>(), "%.0f")
                                          : std::string("&ndash;")) +
                    "</td>";
        body += "</tr>\n";
    }
    return body + "</table>\n";
}

// One group's section: its fronts and plots, the table of configurations and the work table.
std::string group_section(const std::string& title, const std::string& name,
                          std::vector<Point>& points, const Metric& metric, PlotWriter& plot,
                          int& front_total) {
    const std::vector<const Point*> time_front =
        pareto_front(points, &Point::ms, &Point::time_front, metric.higher_is_better, true);
    const std::vector<const Point*> rays_front =
        pareto_front(points, &Point::rays, &Point::rays_front, metric.higher_is_better, false);
    front_total += static_cast<int>(time_front.size());
    std::string body = "<h2>" + html_escape(title) + "</h2>\n<div class=\"plots\">\n";
    body +=
        plot(name + "-time", pareto_plot(points, metric, "time against error",
                                         "ms per frame (single thread)", &Point::ms, time_front));
    body += plot(name + "-rays", pareto_plot(points, metric, "rays traced against error",
                                             "rays per frame", &Point::rays, rays_front));
    body += plot(name + "-rings", ring_plot(points));
    body += "</div>\n";
    std::vector<const Point*> sorted;
    for (const Point& p : points) sorted.push_back(&p);
    std::sort(sorted.begin(), sorted.end(), [](const Point* a, const Point* b) {
        return a->ms < b->ms || (a->ms == b->ms && a->label < b->label);
    });
    return body + configurations_table(sorted) + work_table(points, sorted);
}

}  // namespace

int run_sweep_report(const SweepOptions& o) {
    const fs::path results_file = fs::path(o.out) / "results.json";
    if (!fs::exists(results_file))
        throw Error(results_file.string() + ": no such file (run `fovref sweep merge " + o.out +
                    "` first)");
    const json results =
        parse_json_document<json>(read_file(results_file.string()), results_file.string());
    const Metric metric = metric_of(o.metric);
    Groups groups = read_groups(results, metric);
    if (groups.points.empty())
        throw Error(results_file.string() + ": no finished job to report (" +
                    std::to_string(groups.missing) + " missing)");

    fs::create_directories(fs::path(o.html) / "plots");
    PlotWriter plot{fs::path(o.html), have_rsvg_convert()};
    std::string body;
    int front_total = 0, points_total = 0;
    for (std::size_t g = 0; g < groups.order.size(); ++g) {
        std::vector<Point>& points = groups.points[groups.order[g]];
        points_total += static_cast<int>(points.size());
        const std::string name = std::to_string(g) + "-" + slug(groups.order[g]);
        body += group_section(groups.order[g], name, points, metric, plot, front_total);
    }

    std::string page =
        "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>fovref sweep "
        "report</title><style>" +
        std::string(page_style) + "</style></head><body>\n<h1>fovref sweep: " + html_escape(o.out) +
        "</h1>\n<p>Error metric: " + metric.label +
        ". Time: the median over the evaluated frames of the single-thread time "
        "per frame (each stage the median of the repeats). A configuration is "
        "dominated when another is no slower and no worse, and better in one; "
        "the others form the Pareto front (joined, larger dots; green rows). "
        "Hover a dot for its configuration.</p>\n" +
        (groups.missing > 0 ? "<p><b>" + std::to_string(groups.missing) +
                                  " job(s) have no result yet and are not shown.</b></p>\n"
                            : std::string()) +
        body + "<p id=\"report-ready\">" + std::to_string(plot.written) + " plots, " +
        std::to_string(points_total) + " configurations, " + std::to_string(front_total) +
        " on the time front</p>\n</body></html>\n";
    write_file_atomic((fs::path(o.html) / "index.html").string(), page);
    std::printf(
        "sweep report: %d configuration(s) in %zu group(s), %d on the time front; wrote "
        "%s/index.html and %d plot(s) (%d as PNG%s)\n",
        points_total, groups.order.size(), front_total, o.html.c_str(), plot.written,
        plot.converted, plot.png ? "" : "; install librsvg2-bin for PNGs");
    return 0;
}

}  // namespace fovref
