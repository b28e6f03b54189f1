// Small self-contained SVG line plots for reports (ring errors against eccentricity, like Lund
// Fig. 5.7-5.11). Text only: no fonts or scripts needed, opens in any browser.
#pragma once

#include <string>
#include <vector>

namespace fovref {

struct PlotSeries {
    std::string name;
    std::vector<double> x, y;  ///< same length; non-finite y values leave a gap
};

struct PlotSpec {
    std::string title, x_label, y_label;
    std::vector<PlotSeries> series;
    int width = 420, height = 260;
};

/// The plot as an <svg> element (to inline in HTML or write as a .svg file). Infinite y values
/// (the PSNR of equal rings) are drawn at the top edge, marked "inf"; NaN leaves a gap.
std::string svg_line_plot(const PlotSpec& spec);

/// Escapes &, <, >, " and ' for HTML/SVG text and attributes.
std::string html_escape(const std::string& text);

}  // namespace fovref
