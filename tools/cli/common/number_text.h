// The one number formatter of fovref's command-line tool: every table, CSV, JSON-side text, HTML
// and SVG label formats a number through it, so a value prints the same everywhere.
#pragma once

#include <string>

namespace fovref {

/// `v` as printf's `format` (one conversion of a double, e.g. "%.4g", "%.9g" to round-trip a
/// binary32) writes it (infinities as "inf" and "-inf"); a NaN as `nan` when given (an undefined
/// value: "-" in a console table, "&ndash;" in HTML, "" in CSV), else as printf writes it.
std::string number_text(double v, const char* format = "%.4g", const char* nan = nullptr);

/// "1 pixel", "2 pixels", "0 pixels": a count and its noun (plural: noun + "s").
inline std::string count_text(long long count, const std::string& noun) {
    return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

}  // namespace fovref
