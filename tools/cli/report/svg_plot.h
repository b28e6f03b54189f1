// Small self-contained SVG line plots for reports (ring errors against eccentricity, like Lund
// Fig. 5.7-5.11). Text only: no fonts or scripts needed, opens in any browser.
#pragma once

#include <string>
#include <vector>

namespace fovref {

struct PlotSeries {
    std::string name;
    std::vector<double> x, y;         ///< same length; non-finite y values leave a gap
    bool line = true;                 ///< join the points (false: a scatter of dots)
    double radius = 2.0;              ///< of the dot drawn at each point
    std::vector<std::string> tips{};  ///< optional, per point: shown when the mouse is over it
};

/// An axis's scale. automatic: logarithmic when every value is positive and they span at least
/// two decades (max >= 100 min), else linear.
enum class PlotScale { linear, log, automatic };

struct PlotSpec {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
    int width = 420, height = 260;
    PlotScale x_scale = PlotScale::linear, y_scale = PlotScale::linear;
};

/// The plot as an <svg> element (to inline in HTML or write as a .svg file). Infinite y values
/// (the PSNR of equal rings) are drawn at the top edge, marked "inf"; NaN leaves a gap. On a log
/// axis, values <= 0 leave a gap and the ticks are powers of ten (with 2 and 5 between them
/// when the range spans at most two decades).
std::string svg_line_plot(const PlotSpec& spec);

/// Escapes &, <, >, " and ' for HTML/SVG text and attributes.
std::string html_escape(const std::string& text);

}  // namespace fovref
