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
    const double left = 58, right = 12, top = 26,
                 bottom = 40 + 14.0 * static_cast<double>((spec.series.size() + 2) / 3);
    const double w = spec.width, h = spec.height + bottom - 40;
    const double plot_w = w - left - right, plot_h = h - top - bottom;

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
    if (y0 == y1)
        y0 -= 0.5 * std::max(std::fabs(y0), 1e-12), y1 += 0.5 * std::max(std::fabs(y1), 1e-12);
    const double pad = 0.05 * (y1 - y0);
    y0 -= pad;
    y1 += pad;
    auto px = [&](double x) { return left + (x - x0) / (x1 - x0) * plot_w; };
    auto py = [&](double y) {
        if (std::isinf(y)) return y > 0 ? top : top + plot_h;
        return top + (y1 - y) / (y1 - y0) * plot_h;
    };

    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + number(w) +
                      "\" height=\"" + number(h) + "\" viewBox=\"0 0 " + number(w) + " " +
                      number(h) + "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    svg += "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    svg += "<text x=\"" + coordinate(w / 2) +
           "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\">" + html_escape(spec.title) +
           "</text>\n";
    // Axes, ticks and grid.
    svg += "<rect x=\"" + coordinate(left) + "\" y=\"" + coordinate(top) + "\" width=\"" +
           coordinate(plot_w) + "\" height=\"" + coordinate(plot_h) +
           "\" fill=\"none\" stroke=\"#444\"/>\n";
    for (int i = 0; i <= 4; ++i) {
        const double fx = x0 + (x1 - x0) * i / 4, fy = y0 + (y1 - y0) * i / 4;
        svg += "<line x1=\"" + coordinate(px(fx)) + "\" y1=\"" + coordinate(top) + "\" x2=\"" +
               coordinate(px(fx)) + "\" y2=\"" + coordinate(top + plot_h) +
               "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + coordinate(px(fx)) + "\" y=\"" + coordinate(top + plot_h + 13) +
               "\" text-anchor=\"middle\">" + number(fx) + "</text>\n";
        svg += "<line x1=\"" + coordinate(left) + "\" y1=\"" + coordinate(py(fy)) + "\" x2=\"" +
               coordinate(left + plot_w) + "\" y2=\"" + coordinate(py(fy)) +
               "\" stroke=\"#ddd\"/>\n";
        svg += "<text x=\"" + coordinate(left - 4) + "\" y=\"" + coordinate(py(fy) + 4) +
               "\" text-anchor=\"end\">" + number(fy) + "</text>\n";
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
