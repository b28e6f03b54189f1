#include "tools/cli/report/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "ref/core/dmath.h"
#include "tools/cli/common/number_text.h"

namespace fovref {

namespace {

// Distinguishable line colours (Okabe-Ito palette).
constexpr const char* colours[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                   "#e69f00", "#56b4e9", "#000000", "#f0e442"};

std::string number(double v) { return number_text(v); }

std::string coordinate(double v) { return number_text(v, "%.1f"); }

std::string format_with(double v, int significant) {
    const std::string format = "%." + std::to_string(significant) + "g";
    return number_text(v, format.c_str());
}

// Axis ticks: multiples of a "nice" step (1, 2 or 5 times a power of ten) covering [lo, hi],
// labelled with the fewest significant digits that keep every label distinct (so a range like
// 0.99991 .. 1 does not read "1, 1, 1"). Powers of ten by repeated multiplication: no libm.
struct Axis {
    double lo = 0, hi = 1;
    std::vector<double> ticks;
    std::vector<std::string> labels;
};

Axis nice_axis(double lo, double hi, int target_ticks) {
    Axis axis;
    const double raw = (hi - lo) / target_ticks;
    double power = 1.0;
    while (power * 10.0 <= raw) power *= 10.0;
    while (power > raw) power /= 10.0;
    double step = power;
    for (const double m : {1.0, 2.0, 5.0, 10.0})
        if (power * m >= raw) {
            step = power * m;
            break;
        }
    axis.lo = std::floor(lo / step + 1e-9) * step;  // 1e-9: 0.999 / 0.0005 is 1997.99...
    axis.hi = std::ceil(hi / step - 1e-9) * step;
    if (lo >= 0.0 && axis.lo < 0.0) axis.lo = 0.0;  // a non-negative quantity stays >= 0
    for (double k = std::round(axis.lo / step); k * step <= axis.hi + 0.5 * step; k += 1.0)
        axis.ticks.push_back(k * step == 0.0 ? 0.0 : k * step);  // no "-0"
    // Fixed notation with as many decimals as the step has, for moderate magnitudes; else %g.
    int decimals = 0;
    for (double scaled = step; decimals < 12; scaled *= 10.0, ++decimals)
        if (std::fabs(scaled - std::round(scaled)) <= 1e-9 * scaled) break;
    const double magnitude = std::max(std::fabs(axis.lo), std::fabs(axis.hi));
    if (magnitude < 1e6 && step >= 1e-4) {
        char text[48];
        for (const double t : axis.ticks) {
            std::snprintf(text, sizeof text, "%.*f", decimals, t);
            axis.labels.push_back(text);
        }
        return axis;
    }
    for (int significant = 2; significant <= 17; ++significant) {
        axis.labels.clear();
        for (const double t : axis.ticks) axis.labels.push_back(format_with(t, significant));
        bool distinct = true;
        for (std::size_t i = 1; i < axis.labels.size(); ++i)
            distinct = distinct && axis.labels[i] != axis.labels[i - 1];
        if (distinct) break;
    }
    return axis;
}

// A logarithmic axis over [lo, hi] (both > 0): its ends are powers of ten; the ticks are the
// powers of ten between them, plus 2 and 5 times each when the axis spans at most two decades.
// lo and hi of the result are log10 of the ends (the plot maps log10 of the values).
Axis log_axis(double lo, double hi) {
    Axis axis;
    double low = 1.0;
    int e_low = 0;
    while (low > lo) low /= 10.0, --e_low;
    while (low * 10.0 <= lo) low *= 10.0, ++e_low;
    double high = low;
    int e_high = e_low;
    while (high < hi) high *= 10.0, ++e_high;
    if (e_high == e_low) high *= 10.0, ++e_high;
    const bool fine = e_high - e_low <= 2;
    for (double decade = low; decade <= high * 1.0000001; decade *= 10.0)
        for (const double m : {1.0, 2.0, 5.0}) {
            if (m != 1.0 && !fine) continue;
            const double t = decade * m;
            if (t > high * 1.0000001) break;
            axis.ticks.push_back(t);
            char text[32];
            std::snprintf(text, sizeof text, "%g", t);
            axis.labels.push_back(text);
        }
    axis.lo = static_cast<double>(e_low);
    axis.hi = static_cast<double>(e_high);
    return axis;
}

bool use_log(PlotScale scale, double lo, double hi) {
    if (scale == PlotScale::log) return lo > 0.0;
    if (scale == PlotScale::automatic) return lo > 0.0 && hi >= 100.0 * lo;
    return false;
}

// The plotted ranges over finite values, widened where they are empty or a point, and whether
// some y is infinite.
struct Ranges {
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    bool has_inf = false;
};

// A point is drawn when x is finite (and > 0 on a log x axis) and y is not NaN (and > 0 on a log
// y axis).
bool drawn(const PlotSpec& spec, double x, double y) {
    if (!std::isfinite(x) || std::isnan(y)) return false;
    if (spec.x_scale == PlotScale::log && x <= 0.0) return false;
    if (spec.y_scale == PlotScale::log && y <= 0.0) return false;
    return true;
}

Ranges data_ranges(const PlotSpec& spec) {
    Ranges r;
    for (const PlotSeries& s : spec.series)
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (!drawn(spec, s.x[i], s.y[i])) continue;
            r.x0 = std::min(r.x0, s.x[i]);
            r.x1 = std::max(r.x1, s.x[i]);
            if (std::isinf(s.y[i])) r.has_inf = true;
            if (!std::isfinite(s.y[i])) continue;
            r.y0 = std::min(r.y0, s.y[i]);
            r.y1 = std::max(r.y1, s.y[i]);
        }
    if (!(r.x0 <= r.x1)) r.x0 = 0, r.x1 = 1;
    if (!(r.y0 <= r.y1)) r.y0 = 0, r.y1 = 1;
    if (r.x0 == r.x1) r.x0 -= 0.5, r.x1 += 0.5;
    return r;
}

// The axes and where the plot area lies in the picture: values map to pixels with px and py.
struct Frame {
    Axis xa, ya;
    bool log_x = false, log_y = false;
    double left = 0, top = 0, w = 0, h = 0, plot_w = 0, plot_h = 0;

    double px(double x) const {
        const double v = log_x ? dm::log10_d(x) : x;
        return left + (v - xa.lo) / (xa.hi - xa.lo) * plot_w;
    }
    double py(double y) const {
        if (std::isinf(y)) return y > 0 ? top : top + plot_h;
        const double v = log_y ? dm::log10_d(y) : y;
        return top + (ya.hi - v) / (ya.hi - ya.lo) * plot_h;
    }
};

Frame plot_frame(const PlotSpec& spec, const Ranges& r) {
    double y0 = r.y0, y1 = r.y1;
    // A range below 1e-9 of the values is constant for the eye (e.g. SSIM 1 - 1e-13): plot it as
    // constant, on an axis of +-0.1% around the value, with readable ticks.
    const bool nonnegative = y0 >= 0.0;
    if (y1 - y0 <= 1e-9 * std::max(std::fabs(y0), std::fabs(y1))) {
        const double mid = 0.5 * (y0 + y1);
        const double half = std::max(1e-3 * std::fabs(mid), 1e-12);
        y0 = mid - half;
        y1 = mid + half;
    }
    Frame f;
    f.log_x = use_log(spec.x_scale, r.x0, r.x1);
    f.log_y = use_log(spec.y_scale, r.y0, r.y1);
    f.xa = f.log_x ? log_axis(r.x0, r.x1) : nice_axis(r.x0, r.x1, 4);
    f.ya = f.log_y ? log_axis(r.y0, r.y1) : nice_axis(y0, y1, 4);
    if (!f.log_y && nonnegative && f.ya.lo < 0.0) f.ya.lo = 0.0;

    // The left margin fits the longest y label (11 px sans-serif: ~6.5 px per character).
    std::size_t longest = 0;
    for (const std::string& label : f.ya.labels) longest = std::max(longest, label.size());
    // The right margin fits half of the last x label, which is centred on the right edge.
    const double last_x =
        f.xa.labels.empty() ? 0.0 : static_cast<double>(f.xa.labels.back().size());
    const double left = 30 + 6.5 * static_cast<double>(longest),
                 right = std::max(16.0, 3.25 * last_x + 4.0), top = 26,
                 bottom = 40 + 14.0 * static_cast<double>((spec.series.size() + 2) / 3);
    const double w = spec.width + std::max(0.0, left - 58), h = spec.height + bottom - 40;
    f.left = left;
    f.top = top;
    f.w = w;
    f.h = h;
    f.plot_w = w - left - right;
    f.plot_h = h - top - bottom;
    return f;
}

// The title, the plot area's box, the ticks with their labels and grid lines, the "inf" mark
// and the axis labels.
std::string axes_svg(const PlotSpec& spec, const Frame& f, bool has_inf) {
    const double left = f.left, top = f.top, plot_w = f.plot_w, plot_h = f.plot_h;
    std::string svg = "<text x=\"" + coordinate(f.w / 2) +
                      "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">" +
                      html_escape(spec.title) + "</text>\n";
    svg += "<rect x=\"" + coordinate(left) + "\" y=\"" + coordinate(top) + "\" width=\"" +
           coordinate(plot_w) + "\" height=\"" + coordinate(plot_h) +
           "\" fill=\"none\" stroke=\"#444\"/>\n";
    for (std::size_t i = 0; i < f.xa.ticks.size(); ++i) {
        const double x = f.px(f.xa.ticks[i]);
        svg += "<line x1=\"" + coordinate(x) + "\" y1=\"" + coordinate(top) + "\" x2=\"" +
               coordinate(x) + "\" y2=\"" + coordinate(top + plot_h) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text class=\"tick-x\" x=\"" + coordinate(x) + "\" y=\"" +
               coordinate(top + plot_h + 13) + "\" text-anchor=\"middle\">" + f.xa.labels[i] +
               "</text>\n";
    }
    for (std::size_t i = 0; i < f.ya.ticks.size(); ++i) {
        const double y = f.py(f.ya.ticks[i]);
        svg += "<line x1=\"" + coordinate(left) + "\" y1=\"" + coordinate(y) + "\" x2=\"" +
               coordinate(left + plot_w) + "\" y2=\"" + coordinate(y) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text class=\"tick-y\" x=\"" + coordinate(left - 4) + "\" y=\"" +
               coordinate(y + 4) + "\" text-anchor=\"end\">" + f.ya.labels[i] + "</text>\n";
    }
    if (has_inf)
        svg += "<text x=\"" + coordinate(left + 3) + "\" y=\"" + coordinate(top + 11) +
               "\">inf</text>\n";
    svg += "<text x=\"" + coordinate(left + plot_w / 2) + "\" y=\"" +
           coordinate(top + plot_h + 27) + "\" text-anchor=\"middle\">" +
           html_escape(spec.x_label) + "</text>\n";
    svg += "<text transform=\"translate(12 " + coordinate(top + plot_h / 2) +
           ") rotate(-90)\" text-anchor=\"middle\">" + html_escape(spec.y_label) + "</text>\n";
    return svg;
}

// Series k: a polyline broken at NaN, a dot per point, and its legend entry.
std::string series_svg(const PlotSpec& spec, const PlotSeries& s, std::size_t k, const Frame& f) {
    const std::string colour = colours[k % (sizeof colours / sizeof colours[0])];
    std::string svg, points;
    auto flush = [&] {
        if (!points.empty())
            svg += "<polyline fill=\"none\" stroke=\"" + colour +
                   "\" stroke-width=\"1.6\" points=\"" + points + "\"/>\n";
        points.clear();
    };
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
        if (!drawn(spec, s.x[i], s.y[i])) {
            flush();
            continue;
        }
        const std::string p = coordinate(f.px(s.x[i])) + "," + coordinate(f.py(s.y[i]));
        if (s.line) points += (points.empty() ? "" : " ") + p;
        const std::string tip =
            i < s.tips.size() ? "<title>" + html_escape(s.tips[i]) + "</title>" : std::string();
        svg += "<circle cx=\"" + coordinate(f.px(s.x[i])) + "\" cy=\"" + coordinate(f.py(s.y[i])) +
               "\" r=\"" + coordinate(s.radius) + "\" fill=\"" + colour + "\"" +
               (tip.empty() ? "/>\n" : ">" + tip + "</circle>\n");
    }
    flush();
    const double lx = f.left + static_cast<double>(k % 3) * (f.plot_w / 3);
    const double ly = f.top + f.plot_h + 40 + 14.0 * static_cast<double>(k / 3);
    if (s.line)
        svg += "<line x1=\"" + coordinate(lx) + "\" y1=\"" + coordinate(ly - 4) + "\" x2=\"" +
               coordinate(lx + 16) + "\" y2=\"" + coordinate(ly - 4) + "\" stroke=\"" + colour +
               "\" stroke-width=\"2\"/>\n";
    else  // a scatter's legend is its dot
        svg += "<circle cx=\"" + coordinate(lx + 8) + "\" cy=\"" + coordinate(ly - 4) + "\" r=\"" +
               coordinate(s.radius) + "\" fill=\"" + colour + "\"/>\n";
    svg += "<text x=\"" + coordinate(lx + 20) + "\" y=\"" + coordinate(ly) + "\">" +
           html_escape(s.name) + "</text>\n";
    return svg;
}

}  // namespace

std::string html_escape(const std::string& text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            case '\'': out += "&#39;"; break;
            default: out += c;
        }
    }
    return out;
}

std::string svg_line_plot(const PlotSpec& spec) {
    const Ranges ranges = data_ranges(spec);
    const Frame f = plot_frame(spec, ranges);
    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"" +
                      number(f.w) + "\" height=\"" + number(f.h) + "\" viewBox=\"0 0 " +
                      number(f.w) + " " + number(f.h) +
                      "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += axes_svg(spec, f, ranges.has_inf);
    for (std::size_t k = 0; k < spec.series.size(); ++k)
        svg += series_svg(spec, spec.series[k], k, f);
    svg += "</svg>\n";
    return svg;
}

}  // namespace fovref
