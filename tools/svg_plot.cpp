#include "tools/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace fovref {

namespace {

// Distinguishable line colours (Okabe-Ito palette).
constexpr const char* colours[] = {"#0072b2", "#d55e00", "#009e73", "#cc79a7",
                                   "#e69f00", "#56b4e9", "#000000", "#f0e442"};

std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

std::string coordinate(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.1f", v);
    return text;
}

std::string format_with(double v, int significant) {
    char text[48];
    std::snprintf(text, sizeof text, "%.*g", significant, v);
    return text;
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
    // Ranges over finite values.
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    bool has_inf = false;
    for (const PlotSeries& s : spec.series)
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (!std::isfinite(s.x[i])) continue;
            x0 = std::min(x0, s.x[i]);
            x1 = std::max(x1, s.x[i]);
            if (std::isinf(s.y[i])) has_inf = true;
            if (!std::isfinite(s.y[i])) continue;
            y0 = std::min(y0, s.y[i]);
            y1 = std::max(y1, s.y[i]);
        }
    if (!(x0 <= x1)) x0 = 0, x1 = 1;
    if (!(y0 <= y1)) y0 = 0, y1 = 1;
    if (x0 == x1) x0 -= 0.5, x1 += 0.5;
    // A range below 1e-9 of the values is constant for the eye (e.g. SSIM 1 - 1e-13): plot it as
    // constant, on an axis of +-0.1% around the value, with readable ticks.
    const bool nonnegative = y0 >= 0.0;
    if (y1 - y0 <= 1e-9 * std::max(std::fabs(y0), std::fabs(y1))) {
        const double mid = 0.5 * (y0 + y1);
        const double half = std::max(1e-3 * std::fabs(mid), 1e-12);
        y0 = mid - half;
        y1 = mid + half;
    }
    const Axis xa = nice_axis(x0, x1, 4);
    Axis ya = nice_axis(y0, y1, 4);
    if (nonnegative && ya.lo < 0.0) ya.lo = 0.0;

    // The left margin fits the longest y label (11 px sans-serif: ~6.5 px per character).
    std::size_t longest = 0;
    for (const std::string& label : ya.labels) longest = std::max(longest, label.size());
    const double left = 30 + 6.5 * static_cast<double>(longest), right = 16, top = 26,
                 bottom = 40 + 14.0 * static_cast<double>((spec.series.size() + 2) / 3);
    const double w = spec.width + std::max(0.0, left - 58), h = spec.height + bottom - 40;
    const double plot_w = w - left - right, plot_h = h - top - bottom;
    auto px = [&](double x) { return left + (x - xa.lo) / (xa.hi - xa.lo) * plot_w; };
    auto py = [&](double y) {
        if (std::isinf(y)) return y > 0 ? top : top + plot_h;
        return top + (ya.hi - y) / (ya.hi - ya.lo) * plot_h;
    };

    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"plot\" width=\"" +
                      number(w) + "\" height=\"" + number(h) + "\" viewBox=\"0 0 " + number(w) +
                      " " + number(h) + "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + coordinate(w / 2) +
           "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">" + html_escape(spec.title) +
           "</text>\n";
    // Axes, ticks and grid.
    svg += "<rect x=\"" + coordinate(left) + "\" y=\"" + coordinate(top) + "\" width=\"" +
           coordinate(plot_w) + "\" height=\"" + coordinate(plot_h) +
           "\" fill=\"none\" stroke=\"#444\"/>\n";
    for (std::size_t i = 0; i < xa.ticks.size(); ++i) {
        const double x = px(xa.ticks[i]);
        svg += "<line x1=\"" + coordinate(x) + "\" y1=\"" + coordinate(top) + "\" x2=\"" +
               coordinate(x) + "\" y2=\"" + coordinate(top + plot_h) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text class=\"tick-x\" x=\"" + coordinate(x) + "\" y=\"" +
               coordinate(top + plot_h + 13) + "\" text-anchor=\"middle\">" + xa.labels[i] +
               "</text>\n";
    }
    for (std::size_t i = 0; i < ya.ticks.size(); ++i) {
        const double y = py(ya.ticks[i]);
        svg += "<line x1=\"" + coordinate(left) + "\" y1=\"" + coordinate(y) + "\" x2=\"" +
               coordinate(left + plot_w) + "\" y2=\"" + coordinate(y) + "\" stroke=\"#ddd\"/>\n";
        svg += "<text class=\"tick-y\" x=\"" + coordinate(left - 4) + "\" y=\"" +
               coordinate(y + 4) + "\" text-anchor=\"end\">" + ya.labels[i] + "</text>\n";
    }
    if (has_inf)
        svg += "<text x=\"" + coordinate(left + 3) + "\" y=\"" + coordinate(top + 11) +
               "\">inf</text>\n";
    svg += "<text x=\"" + coordinate(left + plot_w / 2) + "\" y=\"" +
           coordinate(top + plot_h + 27) + "\" text-anchor=\"middle\">" +
           html_escape(spec.x_label) + "</text>\n";
    svg += "<text transform=\"translate(12 " + coordinate(top + plot_h / 2) +
           ") rotate(-90)\" text-anchor=\"middle\">" + html_escape(spec.y_label) + "</text>\n";
    // Series: polylines broken at NaN, a dot per point, and a legend entry.
    for (std::size_t k = 0; k < spec.series.size(); ++k) {
        const PlotSeries& s = spec.series[k];
        const std::string colour = colours[k % (sizeof colours / sizeof colours[0])];
        std::string points;
        auto flush = [&] {
            if (!points.empty())
                svg += "<polyline fill=\"none\" stroke=\"" + colour +
                       "\" stroke-width=\"1.6\" points=\"" + points + "\"/>\n";
            points.clear();
        };
        for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
            if (std::isnan(s.y[i]) || !std::isfinite(s.x[i])) {
                flush();
                continue;
            }
            const std::string p = coordinate(px(s.x[i])) + "," + coordinate(py(s.y[i]));
            points += (points.empty() ? "" : " ") + p;
            svg += "<circle cx=\"" + coordinate(px(s.x[i])) + "\" cy=\"" + coordinate(py(s.y[i])) +
                   "\" r=\"2\" fill=\"" + colour + "\"/>\n";
        }
        flush();
        const double lx = left + static_cast<double>(k % 3) * (plot_w / 3);
        const double ly = top + plot_h + 40 + 14.0 * static_cast<double>(k / 3);
        svg += "<line x1=\"" + coordinate(lx) + "\" y1=\"" + coordinate(ly - 4) + "\" x2=\"" +
               coordinate(lx + 16) + "\" y2=\"" + coordinate(ly - 4) + "\" stroke=\"" + colour +
               "\" stroke-width=\"2\"/>\n<text x=\"" + coordinate(lx + 20) + "\" y=\"" +
               coordinate(ly) + "\">" + html_escape(s.name) + "</text>\n";
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace fovref
