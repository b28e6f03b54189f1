#include "ref/metrics/compare.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include <nlohmann/json.hpp>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/image/image_io.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/ssim.h"

namespace fovref {

using json = nlohmann::json;

bool tolerance_pattern_matches(const std::string& pattern, const std::string& name) {
    // Iterative glob: on a mismatch, let the last `*` swallow one more character
    std::size_t p = 0, n = 0, star = std::string::npos, resume = 0;
    while (n < name.size()) {
        if (p < pattern.size() && pattern[p] == '*') {
            star = p++;
            resume = n;
        } else if (p < pattern.size() && pattern[p] == name[n]) {
            ++p;
            ++n;
        } else if (star != std::string::npos) {
            p = star + 1;
            n = ++resume;
        } else {
            return false;
        }
    }
    while (p < pattern.size() && pattern[p] == '*') ++p;
    return p == pattern.size();
}

std::string ToleranceTable::key_for(const std::string& name) const {
    if (buffers.count(name)) return name;
    std::string best;
    std::ptrdiff_t best_literal = -1;
    for (const auto& [key, tolerance] : buffers) {
        if (key.find('*') == std::string::npos || !tolerance_pattern_matches(key, name)) continue;
        const auto literal = static_cast<std::ptrdiff_t>(
            key.size() - static_cast<std::size_t>(std::count(key.begin(), key.end(), '*')));
        if (literal > best_literal) {
            best = key;
            best_literal = literal;
        }
    }
    return best;
}

const Tolerance& ToleranceTable::for_buffer(const std::string& name) const {
    const std::string key = key_for(name);
    return key.empty() ? fallback : buffers.at(key);
}

namespace {

void check_tolerance(const Tolerance& t, const std::string& where) {
    if (!(std::isfinite(t.abs) && t.abs >= 0.0) || !(std::isfinite(t.rel) && t.rel >= 0.0) ||
        t.ulp < 0 || t.max_failing_pixels < 0 || t.max_interior_mismatches < 0)
        throw Error(where +
                    ": abs, rel, ulp, max_failing_pixels and interior_mismatches must be finite "
                    "and >= 0");
    if (!(t.max_edge_mismatch_share >= 0.0 && t.max_edge_mismatch_share <= 1.0))
        throw Error(where + ": edge_mismatch_share must be in [0, 1]");
    if (!(t.max_failing_share >= 0.0 && t.max_failing_share <= 1.0))
        throw Error(where + ": max_failing_share must be in [0, 1]");
}

PixelDifference pixel_difference(const Image& golden, const Image& candidate, std::size_t pixel,
                                 double abs_error) {
    PixelDifference d;
    d.x = static_cast<int>(pixel % static_cast<std::size_t>(golden.width));
    d.y = static_cast<int>(pixel / static_cast<std::size_t>(golden.width));
    d.abs_error = abs_error;
    const auto channels = static_cast<std::size_t>(golden.channels);
    for (std::size_t c = 0; c < channels; ++c) {
        d.golden.push_back(golden.data[pixel * channels + c]);
        d.candidate.push_back(candidate.data[pixel * channels + c]);
    }
    return d;
}

}  // namespace

ToleranceTable read_tolerance_file(const std::string& path) {
    ToleranceTable table;
    read_tolerance_file(path, table);
    return table;
}

void read_tolerance_file(const std::string& path, ToleranceTable& table) {
    const std::string text = read_file(path);
    const json document = parse_json_document<json>(text, path);
    const JsonLocator locator(text, path);
    if (!document.is_object())
        throw file_error(path, 1, "expected an object mapping buffer names to tolerances");
    for (auto it = document.begin(); it != document.end(); ++it) {
        const std::string pointer = json_pointer_member("", it.key());
        auto fail = [&](const std::string& pointer_at, const std::string& message) {
            return file_error(path, locator.find(pointer_at).key_line,
                              "tolerance for '" + it.key() + "': " + message);
        };
        if (!it.value().is_object()) throw fail(pointer, "expected an object");
        Tolerance t;
        for (auto field = it.value().begin(); field != it.value().end(); ++field) {
            const std::string at = json_pointer_member(pointer, field.key());
            const json& v = field.value();
            if (field.key() == "reason") {
                if (!v.is_string()) throw fail(at, "\"reason\" must be a string");
                t.reason = v.get<std::string>();
            } else if (field.key() == "abs" || field.key() == "rel" ||
                       field.key() == "edge_mismatch_share" || field.key() == "max_failing_share") {
                if (!v.is_number()) throw fail(at, "\"" + field.key() + "\" must be a number");
                (field.key() == "abs"                 ? t.abs
                 : field.key() == "rel"               ? t.rel
                 : field.key() == "max_failing_share" ? t.max_failing_share
                                                      : t.max_edge_mismatch_share) =
                    v.get<double>();
            } else if (field.key() == "integer") {
                if (!v.is_boolean()) throw fail(at, "\"integer\" must be true or false");
                t.integer = v.get<bool>();
            } else if (field.key() == "margin") {
                if (!v.is_string() || v.get<std::string>().empty())
                    throw fail(at, "\"margin\" must name a golden buffer or a derivation");
                t.margin = v.get<std::string>();
                t.integer = true;
            } else if (field.key() == "margin_epsilon") {
                if (!v.is_array() || v.empty()) throw fail(at, "expected an array of numbers");
                for (const json& e : v) {
                    if (!e.is_number() || !(e.get<double>() >= 0.0))
                        throw fail(at, "\"margin_epsilon\" entries must be numbers >= 0");
                    t.margin_epsilon.push_back(e.get<double>());
                }
            } else if (field.key() == "ulp" || field.key() == "max_failing_pixels" ||
                       field.key() == "interior_mismatches") {
                if (!v.is_number_integer())
                    throw fail(at, "\"" + field.key() + "\" must be an integer");
                (field.key() == "ulp"                  ? t.ulp
                 : field.key() == "max_failing_pixels" ? t.max_failing_pixels
                                                       : t.max_interior_mismatches) =
                    v.get<std::int64_t>();
            } else {
                throw fail(at, "unknown key \"" + field.key() +
                                   "\" (expected abs, rel, ulp, max_failing_pixels, "
                                   "max_failing_share, edge_mismatch_share, "
                                   "interior_mismatches, integer, margin, margin_epsilon, "
                                   "reason)");
            }
            if (field.key() == "edge_mismatch_share" || field.key() == "interior_mismatches")
                t.integer = true;
        }
        if (!t.margin.empty() && t.margin_epsilon.empty())
            throw fail(pointer, "\"margin\" needs \"margin_epsilon\" (one epsilon per channel)");
        try {
            check_tolerance(t, "tolerance");
        } catch (const Error& e) {
            throw fail(pointer, e.what());
        }
        if (t.reason.empty()) t.reason = "tolerance file " + path;
        table.buffers[it.key()] = t;
    }
}

void parse_tolerance_option(const std::string& option, ToleranceTable& table) {
    const std::string where = "--tolerance '" + option + "'";
    const auto colon = option.rfind(':');
    if (colon == std::string::npos || colon == 0)
        throw Error(where + ": expected NAME:abs=X,rel=X,ulp=N,pixels=N,share=X,edge=X,interior=N");
    const std::string name = option.substr(0, colon);
    Tolerance t;
    std::string rest = option.substr(colon + 1);
    while (!rest.empty()) {
        const auto comma = rest.find(',');
        const std::string item = rest.substr(0, comma);
        rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
        const auto eq = item.find('=');
        if (eq == std::string::npos) throw Error(where + ": '" + item + "' is not KEY=VALUE");
        const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
        const char* first = value.data();
        const char* last = value.data() + value.size();
        std::from_chars_result r{};
        if (key == "abs" || key == "rel" || key == "edge" || key == "share") {
            double v = 0;
            r = std::from_chars(first, last, v);
            (key == "abs"     ? t.abs
             : key == "rel"   ? t.rel
             : key == "share" ? t.max_failing_share
                              : t.max_edge_mismatch_share) = v;
        } else if (key == "ulp" || key == "pixels" || key == "interior") {
            std::int64_t v = 0;
            r = std::from_chars(first, last, v);
            (key == "ulp"      ? t.ulp
             : key == "pixels" ? t.max_failing_pixels
                               : t.max_interior_mismatches) = v;
        } else {
            throw Error(where + ": unknown key '" + key +
                        "' (expected abs, rel, ulp, pixels, share, edge, interior)");
        }
        if (r.ec != std::errc() || r.ptr != last || value.empty())
            throw Error(where + ": '" + value + "' is not a valid value for " + key);
        if (key == "edge" || key == "interior") t.integer = true;
    }
    check_tolerance(t, where);
    t.reason = "command line";
    table.buffers[name] = t;
}

std::int64_t ulp_distance(float a, float b) {
    auto ordered = [](float x) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &x, sizeof bits);
        return (bits & 0x80000000u) ? -static_cast<std::int64_t>(bits & 0x7fffffffu)
                                    : static_cast<std::int64_t>(bits);
    };
    const std::int64_t d = ordered(a) - ordered(b);
    return d < 0 ? -d : d;
}

namespace {

/// Equal for an id comparison: the same bits, both zero (-0 == +0) or both NaN.
bool same_id(float a, float b) { return a == b || (std::isnan(a) && std::isnan(b)); }

// The sums behind the mean absolute error and the MSE: over finite element pairs, in pixel then
// channel order, in binary64.
struct ErrorSums {
    double abs = 0.0, squared = 0.0;
    std::int64_t finite_elements = 0;
};

// What one pixel's comparison found.
struct PixelVerdict {
    double abs = 0.0;    ///< largest channel error (+inf for a non-finite mismatch)
    bool fails = false;  ///< a channel outside the tolerance, or a non-finite mismatch
};

// The channels of pixel p compared element by element: counts and maxima into r, sums into sums.
PixelVerdict compare_pixel(const Image& golden, const Image& candidate, std::size_t p,
                           const Tolerance& tolerance, BufferComparison& r, ErrorSums& sums) {
    const auto channels = static_cast<std::size_t>(golden.channels);
    PixelVerdict verdict;
    for (std::size_t c = 0; c < channels; ++c) {
        const float g = golden.data[p * channels + c];
        const float v = candidate.data[p * channels + c];
        std::uint32_t gb = 0, vb = 0;
        std::memcpy(&gb, &g, 4);
        std::memcpy(&vb, &v, 4);
        if (gb != vb) ++r.differing_elements;
        if (!std::isfinite(g) || !std::isfinite(v)) {
            // NaN against NaN and inf against the same inf are equal; anything else with a
            // non-finite side is a mismatch no tolerance admits (a convention difference, or
            // a bug): no error figure is defined for it.
            if (!same_id(g, v)) {
                ++r.nonfinite_mismatches;
                if (std::isnan(g) != std::isnan(v)) ++r.nan_mismatches;
                verdict.fails = true;
                verdict.abs = std::numeric_limits<double>::infinity();
            }
            continue;
        }
        const double e = g == v ? 0.0 : std::fabs(static_cast<double>(v) - g);
        const double rel = g != 0.0f ? e / std::fabs(static_cast<double>(g)) : 0.0;
        const std::int64_t u = ulp_distance(g, v);
        r.max_abs = std::max(r.max_abs, e);
        r.max_rel = std::max(r.max_rel, rel);
        r.max_ulp = std::max(r.max_ulp, u);
        verdict.abs = std::max(verdict.abs, e);
        sums.abs += e;
        sums.squared += e * e;
        ++sums.finite_elements;
        const bool within = g == v || e <= tolerance.abs ||
                            (tolerance.rel > 0.0 && e <= tolerance.rel * std::fabs(g)) ||
                            (tolerance.ulp > 0 && u <= tolerance.ulp);
        if (!within) verdict.fails = true;
    }
    return verdict;
}

// Worst pixels: (abs error, pixel index), largest error first, then lowest index.
using WorstEntry = std::pair<double, std::size_t>;
bool worse(const WorstEntry& a, const WorstEntry& b) {
    return a.first != b.first ? a.first > b.first : a.second < b.second;
}

// Keeps the `keep` worst entries of a bounded, ordered list.
void keep_worst(std::vector<WorstEntry>& worst, const WorstEntry& entry, std::size_t keep) {
    if (worst.size() < keep || worse(entry, worst.back())) {
        worst.insert(std::upper_bound(worst.begin(), worst.end(), entry, worse), entry);
        if (worst.size() > keep) worst.pop_back();
    }
}

// SSIM and ring errors where they mean something: 1 or 3 channels, at least the SSIM window,
// no NaN/Inf. Masked-out pixels take the golden's value: no error where nothing is compared.
void add_image_metrics(const Image& golden, const Image& candidate,
                       const std::vector<std::uint8_t>* mask, const CompareOptions& options,
                       BufferComparison& r) {
    const auto channels = static_cast<std::size_t>(golden.channels);
    const bool image_like =
        (golden.channels == 1 || golden.channels == 3) && golden.width >= 11 && golden.height >= 11;
    bool finite = true;
    for (std::size_t i = 0; i < golden.data.size() && finite; ++i)
        finite = std::isfinite(golden.data[i]) && std::isfinite(candidate.data[i]);
    if (!image_like || !finite) return;
    Image masked;
    if (mask) {
        masked = candidate;
        for (std::size_t p = 0; p < golden.pixel_count(); ++p)
            if ((*mask)[p] == 0)
                for (std::size_t c = 0; c < channels; ++c)
                    masked.data[p * channels + c] = golden.data[p * channels + c];
    }
    const Image& compared = mask ? masked : candidate;
    const SsimMap map = ssim_map(luma(golden), luma(compared));
    r.ssim = map.mean;
    if (options.rings) r.rings = ring_errors(golden, compared, *options.rings, &map);
}

}  // namespace

namespace {

// The RMSE of each column and each row over the compared finite elements (binary64, row-major).
void add_axis_errors(const Image& golden, const Image& candidate,
                     const std::vector<std::uint8_t>* mask, BufferComparison& r) {
    std::vector<double> column_sum(static_cast<std::size_t>(golden.width), 0.0),
        row_sum(static_cast<std::size_t>(golden.height), 0.0);
    std::vector<std::int64_t> column_count(column_sum.size(), 0), row_count(row_sum.size(), 0);
    for (int y = 0; y < golden.height; ++y)
        for (int x = 0; x < golden.width; ++x) {
            const std::size_t p = static_cast<std::size_t>(y) * golden.width + x;
            if (mask && (*mask)[p] == 0) continue;
            for (int c = 0; c < golden.channels; ++c) {
                const double g = golden.at(x, y, c), v = candidate.at(x, y, c);
                if (!std::isfinite(g) || !std::isfinite(v)) continue;
                const double e = (v - g) * (v - g);
                column_sum[static_cast<std::size_t>(x)] += e;
                row_sum[static_cast<std::size_t>(y)] += e;
                ++column_count[static_cast<std::size_t>(x)];
                ++row_count[static_cast<std::size_t>(y)];
            }
        }
    const auto rmse = [](double sum, std::int64_t count) {
        return count > 0 ? std::sqrt(sum / static_cast<double>(count))
                         : std::numeric_limits<double>::quiet_NaN();
    };
    for (std::size_t x = 0; x < column_sum.size(); ++x)
        r.column_rmse.push_back(rmse(column_sum[x], column_count[x]));
    for (std::size_t y = 0; y < row_sum.size(); ++y)
        r.row_rmse.push_back(rmse(row_sum[y], row_count[y]));
}

}  // namespace

BufferComparison compare_buffers(const std::string& name, const Image& golden,
                                 const Image& candidate, const Tolerance& tolerance,
                                 const CompareOptions& options) {
    check_same_shape(golden, candidate, ("buffer '" + name + "'").c_str());
    const std::vector<std::uint8_t>* mask = options.mask;
    FOVREF_CHECK(!mask || mask->size() == golden.pixel_count(),
                 "compare mask of buffer '" + name + "' has " +
                     std::to_string(mask ? mask->size() : 0) + " entries, the buffer " +
                     std::to_string(golden.pixel_count()) + " pixels");
    BufferComparison r;
    r.name = name;
    r.width = golden.width;
    r.height = golden.height;
    r.channels = golden.channels;
    r.tolerance = tolerance;
    r.threshold = options.threshold;
    r.abs_error = Image(golden.width, golden.height, 1, 0.0f);
    r.failing_map.assign(golden.pixel_count(), 0);

    ErrorSums sums;
    std::vector<WorstEntry> worst;
    const std::size_t keep = static_cast<std::size_t>(std::max(options.worst_pixels, 0));
    for (std::size_t p = 0; p < golden.pixel_count(); ++p) {
        if (mask && (*mask)[p] == 0) {
            ++r.masked_pixels;
            continue;
        }
        const PixelVerdict pixel = compare_pixel(golden, candidate, p, tolerance, r, sums);
        r.abs_error.data[p] = static_cast<float>(pixel.abs);
        const bool over = r.threshold >= 0.0 ? pixel.abs > r.threshold : pixel.fails;
        if (over) ++r.pixels_over_threshold;
        if (pixel.fails) ++r.failing_pixels, r.failing_map[p] = 1;
        if (pixel.fails && r.failing_listed.size() < BufferComparison::failing_listed_max)
            r.failing_listed.emplace_back(static_cast<int>(p % golden.width),
                                          static_cast<int>(p / golden.width));
        if (pixel.fails && !r.first_failing)
            r.first_failing = pixel_difference(golden, candidate, p, pixel.abs);
        if (keep > 0 && pixel.abs > 0.0) keep_worst(worst, WorstEntry(pixel.abs, p), keep);
    }
    for (const auto& [error, pixel] : worst)
        r.worst.push_back(pixel_difference(golden, candidate, pixel, error));
    if (sums.finite_elements > 0) {
        r.mean_abs = sums.abs / static_cast<double>(sums.finite_elements);
        const double mse_value = sums.squared / static_cast<double>(sums.finite_elements);
        r.rmse = std::sqrt(mse_value);
        r.psnr = psnr(mse_value);
    } else {
        r.psnr = std::numeric_limits<double>::infinity();
    }
    const auto compared = static_cast<double>(
        static_cast<std::int64_t>(golden.width) * golden.height - r.masked_pixels);
    r.allowed_failing_pixels =
        std::max(tolerance.max_failing_pixels,
                 static_cast<std::int64_t>(std::floor(tolerance.max_failing_share * compared)));
    r.pass = r.nonfinite_mismatches == 0 && r.failing_pixels <= r.allowed_failing_pixels;
    add_image_metrics(golden, candidate, mask, options, r);
    if (options.axis_errors) add_axis_errors(golden, candidate, mask, r);
    return r;
}

namespace {

// Whether the flip at (x, y) lies within ε of the oracle's threshold (any channel of `margin`
// within its ε); records it in r (near: counted and listed; far: the smallest margin).
bool near_threshold_flip(const Image& margin, const std::vector<double>& epsilon, int x, int y,
                         IdComparison& r) {
    double nearest = std::numeric_limits<double>::infinity();
    bool near = false;
    for (int c = 0; c < margin.channels && c < static_cast<int>(epsilon.size()); ++c) {
        const double m = std::fabs(static_cast<double>(margin.at(x, y, c)));
        if (!std::isfinite(m)) continue;
        nearest = std::min(nearest, m);
        near = near || m <= epsilon[static_cast<std::size_t>(c)];
    }
    if (near) {
        ++r.near_threshold;
        r.near_pixels.push_back({x, y});
        r.near_max_margin = std::max(r.near_max_margin, nearest);
    } else if (std::isfinite(nearest)) {
        r.far_min_margin = r.far_min_margin < 0.0 ? nearest : std::min(r.far_min_margin, nearest);
    }
    return near;
}

// The derivations derived_decision_margin knows, as "name(" prefixes.
constexpr const char* margin_derivations[] = {"screen_border(", "pixel_edge("};

}  // namespace

std::string decision_margin_input(const std::string& margin) {
    for (const char* d : margin_derivations) {
        const std::string prefix = d;
        if (margin.rfind(prefix, 0) == 0 && margin.size() > prefix.size() + 1 &&
            margin.back() == ')')
            return margin.substr(prefix.size(), margin.size() - prefix.size() - 1);
    }
    return "";
}

Image derived_decision_margin(const std::string& derivation, const Image& points, int screen_width,
                              int screen_height) {
    FOVREF_CHECK(points.channels >= 2, "a decision margin from screen points needs 2 channels");
    const bool border = derivation.rfind("screen_border(", 0) == 0;
    FOVREF_CHECK(border || derivation.rfind("pixel_edge(", 0) == 0,
                 "unknown decision margin derivation");
    Image out(points.width, points.height, 1, 0.0f);
    const double w = screen_width, h = screen_height;
    for (int y = 0; y < points.height; ++y)
        for (int x = 0; x < points.width; ++x) {
            const double px = points.at(x, y, 0), py = points.at(x, y, 1);
            double m = 0.0;
            if (border) {
                // Signed distance to the rectangle's boundary: inside the smallest distance to
                // an edge, outside the Euclidean distance to the rectangle
                const double dx = std::max({-px, px - w, 0.0}), dy = std::max({-py, py - h, 0.0});
                m = dx > 0.0 || dy > 0.0 ? std::sqrt(dx * dx + dy * dy)
                                         : std::min({px, w - px, py, h - py});
            } else {
                const double fx = px - std::floor(px), fy = py - std::floor(py);
                m = std::min({fx, 1.0 - fx, fy, 1.0 - fy});
            }
            out.at(x, y) = static_cast<float>(std::isfinite(m) ? m : 1e30);
        }
    return out;
}

IdComparison compare_id_buffers(const std::string& name, const Image& golden,
                                const Image& candidate, const Tolerance& tolerance, int listed,
                                const Image* margin) {
    check_same_shape(golden, candidate, ("buffer '" + name + "'").c_str());
    IdComparison r;
    r.name = name;
    r.width = golden.width;
    r.height = golden.height;
    r.channels = golden.channels;
    r.tolerance = tolerance;
    r.pixels = static_cast<std::int64_t>(golden.pixel_count());
    r.agree.assign(golden.pixel_count(), 1);
    r.mismatch_map = Image(golden.width, golden.height, 1, 0.0f);
    const int channels = golden.channels;
    auto same_pixel = [&](const Image& a, int ax, int ay, const Image& b, int bx, int by) {
        for (int c = 0; c < channels; ++c)
            if (!same_id(a.at(ax, ay, c), b.at(bx, by, c))) return false;
        return true;
    };
    auto values = [&](const Image& image, int x, int y) {
        std::vector<float> v;
        for (int c = 0; c < channels; ++c) v.push_back(image.at(x, y, c));
        return v;
    };
    const auto keep = static_cast<std::size_t>(std::max(listed, 0));
    std::vector<IdMismatch> interior, edge;
    for (int y = 0; y < golden.height; ++y)
        for (int x = 0; x < golden.width; ++x) {
            // An edge pixel: the golden has another id in the 3x3 neighbourhood (inside).
            bool is_edge = false;
            for (int dy = -1; dy <= 1 && !is_edge; ++dy)
                for (int dx = -1; dx <= 1 && !is_edge; ++dx) {
                    const int nx = x + dx, ny = y + dy;
                    if (nx < 0 || ny < 0 || nx >= golden.width || ny >= golden.height) continue;
                    is_edge = !same_pixel(golden, x, y, golden, nx, ny);
                }
            r.edge_pixels += is_edge ? 1 : 0;
            if (same_pixel(golden, x, y, candidate, x, y)) continue;
            const std::size_t p = static_cast<std::size_t>(y) * golden.width + x;
            r.agree[p] = 0;
            if (margin && near_threshold_flip(*margin, tolerance.margin_epsilon, x, y, r)) {
                r.mismatch_map.data[p] = 3.0f;
                continue;
            }
            r.mismatch_map.data[p] = is_edge ? 1.0f : 2.0f;
            (is_edge ? r.edge_mismatches : r.interior_mismatches) += 1;
            std::vector<IdMismatch>& list = is_edge ? edge : interior;
            if (list.size() < keep)
                list.push_back({x, y, is_edge, values(golden, x, y), values(candidate, x, y)});
        }
    r.allowed_edge_mismatches = static_cast<std::int64_t>(
        std::floor(tolerance.max_edge_mismatch_share * static_cast<double>(r.edge_pixels)));
    r.pass = r.edge_mismatches <= r.allowed_edge_mismatches &&
             r.interior_mismatches <= tolerance.max_interior_mismatches;
    if (margin) {  // a decision buffer: every flip far from the threshold fails
        r.margin_source = tolerance.margin;
        r.allowed_edge_mismatches = 0;
        r.pass = r.edge_mismatches == 0 && r.interior_mismatches == 0;
    }
    r.mismatches = interior;
    r.mismatches.insert(r.mismatches.end(), edge.begin(), edge.end());
    return r;
}

}  // namespace fovref
