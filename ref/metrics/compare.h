// Buffer comparison for `fovref diff` (SPEC §11, the diff contract): how a candidate buffer
// (written by a GPU implementation) differs from the golden one, element by element, and whether
// that is within the buffer's declared tolerance.
// clang-format off
//
//   abs error  |c - g|;  relative error |c - g| / |g| (only where g != 0; a non-zero c against
//   g = 0 shows in the absolute error);  ulp distance |o(c) - o(g)| with o the binary32 ordering
//   (o(x) = bits for x >= +0, -(bits & 0x7fffffff) for negative x: -0 and +0 are 0 apart).
//   NaN against a number is a mismatch that no tolerance admits; NaN against NaN is equal.
//
// An element is within tolerance when it is equal, or |c - g| <= abs, or |c - g| <= rel |g|, or
// its ulp distance <= ulp (each bound applies only when declared > 0; the default tolerance is 0,
// i.e. bit-exact up to the sign of zero). A non-finite value against a different one (NaN
// against a number, +-inf against a finite value: usually a different background convention)
// is a mismatch no tolerance admits; the error figures (max, mean, RMSE, PSNR) are taken over
// the elements finite on both sides. A pixel fails when any of its channels does; a buffer fails
// when more than max_failing_pixels pixels fail.
//
// Buffers of ids and masks (primitive id, material id, validity masks) are compared as integers
// (compare_id_buffers): a pixel matches when its values are equal; a mismatch is an *edge*
// mismatch when the golden has another id in the pixel's 3x3 neighbourhood (inside the image),
// else an *interior* one. The buffer passes when the edge mismatches are at most
// max_edge_mismatch_share of the golden's edge pixels and the interior ones at most
// max_interior_mismatches. The other buffers of the same frame can then be compared only where
// the ids agree (CompareOptions::mask).
// clang-format on
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

#include "ref/image/image.h"
#include "ref/metrics/rings.h"

namespace fovref {

struct Tolerance {
    double abs = 0.0;
    double rel = 0.0;
    std::int64_t ulp = 0;
    std::int64_t max_failing_pixels = 0;
    /// Failing pixels allowed as a share of the compared pixels, in [0, 1] (the larger of this
    /// and max_failing_pixels applies): for path-traced buffers, where a ray decided differently
    /// changes a whole pixel and the count grows with the resolution.
    double max_failing_share = 0.0;
    // Id buffers only:
    double max_edge_mismatch_share = 0.0;  ///< of the golden's edge pixels, in [0, 1]
    std::int64_t max_interior_mismatches = 0;
    /// Compare as integers (compare_id_buffers) although the buffer is not an id buffer: masks,
    /// accept bits, ages, sample counts, whose values are discrete decisions. Id buffers always
    /// are; the edge and interior limits apply.
    bool integer = false;
    /// Threshold decisions (a validity bit, an accept/reject, an age restart, a rounded index):
    /// where the oracle's own decision lay within margin_epsilon of its threshold, a flip is
    /// *near-threshold*: counted and reported, not a failure; any other flip fails (the edge
    /// share no longer applies). `margin` names where the oracle's margin comes from: a golden
    /// buffer of the same frame and size (channel c: the distance from the threshold of the
    /// decision's c-th test, in that test's units), or a margin the diff derives
    /// (decision_margin_names(): "screen_border(lp_screen_point)"...). margin_epsilon: one ε per
    /// channel; a flip is near-threshold when any channel's |margin| <= its ε.
    std::string margin;
    std::vector<double> margin_epsilon;
    std::string reason;  ///< SPEC §11: every tolerance states why
    bool operator==(const Tolerance&) const = default;
};

/// Per-buffer tolerances. A key is a buffer name or a pattern with `*` wildcards ("lp_gbuffer_*",
/// "*_valid"; "*" alone: every buffer). A buffer takes its exact entry, else the most specific
/// pattern that matches it (the most characters besides `*`; on a tie the first in name order),
/// else the default-constructed fallback (bit-exact).
struct ToleranceTable {
    std::map<std::string, Tolerance> buffers;
    Tolerance fallback;
    /// A profile's entries for the images after path tracing, and after BMFR (the output and
    /// what follows it), which tolerance_profile puts over `buffers` for such a golden.
    std::map<std::string, Tolerance> path_traced, denoised;
    const Tolerance& for_buffer(const std::string& name) const;
    /// The key for_buffer(name) uses ("" for the fallback).
    std::string key_for(const std::string& name) const;
};

/// True when `name` matches `pattern`, whose `*` stands for any run of characters (others match
/// themselves).
bool tolerance_pattern_matches(const std::string& pattern, const std::string& name);

/// Tolerance file (JSON): { "buffer name" or pattern: {"abs": x, "rel": x, "ulp": n,
/// "max_failing_pixels": n, "max_failing_share": x, "edge_mismatch_share": x,
/// "interior_mismatches": n, "integer": bool, "margin": "buffer", "margin_epsilon": [x, ...],
/// "reason": "..."} } (edge_mismatch_share or interior_mismatches imply "integer"). Entries are
/// added to `table`, replacing one of the same name. Throws fovref::Error naming the file, line and
/// key.
ToleranceTable read_tolerance_file(const std::string& path);
void read_tolerance_file(const std::string& path, ToleranceTable& table);
/// Command-line form "NAME:abs=1e-6,rel=1e-4,ulp=2,pixels=10,share=0.001,edge=0.01,interior=0"
/// (NAME may be
/// a pattern; edge= or interior= compare the buffer as integers); added to `table`, overriding an
/// entry for the same name. Throws fovref::Error naming the option.
void parse_tolerance_option(const std::string& option, ToleranceTable& table);

/// The shipped tolerance profiles (docs/diff.md), each entry with its reason: "bit-exact" (the
/// default: 0 everywhere), "gpu-raster" (a correct GPU rasterizer's G-buffer) and "gpu-rt" (a
/// correct GPU ray tracer's primary hits), each covering every buffer family. `golden`: the
/// golden's buffer names, which say whether it path traces (a radiance buffer) or runs BMFR
/// (bmfr_taa): then its output and what follows carry the paths' or the fit's error. Throws
/// fovref::Error for another name.
ToleranceTable tolerance_profile(const std::string& name,
                                 const std::vector<std::string>& golden = {});
const std::vector<std::string>& tolerance_profile_names();

/// Distance of two floats in the binary32 ordering (see above); both must not be NaN.
std::int64_t ulp_distance(float a, float b);

struct PixelDifference {
    int x = 0, y = 0;
    double abs_error = 0.0;  ///< largest channel |c - g| (inf for a NaN mismatch)
    std::vector<float> golden, candidate;
};

struct CompareOptions {
    /// Absolute threshold for the "pixels over the threshold" figure; < 0: no threshold, the
    /// figure counts the pixels out of tolerance (failing pixels).
    double threshold = -1.0;
    int worst_pixels = 5;  ///< how many worst pixels to list
    /// Ring errors and SSIM are computed for 1- and 3-channel buffers of at least 11x11; the
    /// ring layout (may be null: no ring errors).
    const RingLayout* rings = nullptr;
    /// Pixels to compare (1) or leave out (0), width x height entries; null: every pixel. The
    /// diff passes the pixels where the frame's ids agree. Left-out pixels count in no figure;
    /// SSIM and the ring errors see the golden's value there (zero error).
    const std::vector<std::uint8_t>* mask = nullptr;
    /// Also the RMSE of each column and of each row (a buffer-space image, whose columns u and
    /// rows v are the mapping's radius and angle, summarised along its axes instead of rings).
    bool axis_errors = false;
};

struct BufferComparison {
    std::string name;
    int width = 0, height = 0, channels = 0;
    Tolerance tolerance;
    double max_abs = 0.0, max_rel = 0.0;
    std::int64_t max_ulp = 0;
    std::int64_t nan_mismatches = 0;  ///< elements where exactly one side is NaN
    /// Elements non-finite on one side and different on the other (NaN against a number, inf
    /// against a finite value or the other inf): NaN mismatches included.
    std::int64_t nonfinite_mismatches = 0;
    std::int64_t differing_elements = 0;  ///< elements whose bits differ
    std::int64_t masked_pixels = 0;       ///< left out by CompareOptions::mask
    double mean_abs = 0.0, rmse = 0.0, psnr = 0.0;
    std::optional<double> ssim;  ///< luma SSIM for 3 channels, the channel itself for 1
    double threshold = -1.0;     ///< < 0: none given (pixels_over_threshold = failing_pixels)
    std::int64_t pixels_over_threshold = 0;
    std::int64_t failing_pixels = 0;
    /// The failing pixels the tolerance allows: max(max_failing_pixels, share x compared)
    std::int64_t allowed_failing_pixels = 0;
    /// Failing pixels explained by a near-threshold decision flip nearby (set by the diff after
    /// comparing every decision buffer; see attribute_to_decisions); they do not count against
    /// allowed_failing_pixels. attributed_to: the decision buffers that explain them.
    std::int64_t attributed_pixels = 0;
    std::vector<std::string> attributed_to;
    /// 1 where the pixel fails (width x height), for the attribution.
    std::vector<std::uint8_t> failing_map;
    bool pass = true;
    std::optional<PixelDifference> first_failing;  ///< row-major first failing pixel
    /// The first failing pixels in row-major order, at most failing_listed_max of them (the
    /// report rings them in the heatmap when that is all of them).
    std::vector<glm::ivec2> failing_listed;
    static constexpr std::size_t failing_listed_max = 64;
    std::vector<PixelDifference> worst;  ///< largest abs error first; ties row-major
    Image abs_error;                     ///< per-pixel largest channel |c - g|
    std::vector<RingStats> rings;
    /// CompareOptions::axis_errors: RMSE over the compared finite elements of each column (u)
    /// and each row (v), binary64 sums in row-major order; NaN where none was compared.
    std::vector<double> column_rmse, row_rmse;
};

/// Compares candidate against golden (same shape: the caller checks and reports a mismatch as an
/// input error). Sums in binary64, row-major then channel.
BufferComparison compare_buffers(const std::string& name, const Image& golden,
                                 const Image& candidate, const Tolerance& tolerance,
                                 const CompareOptions& options = {});

struct IdMismatch {
    int x = 0, y = 0;
    bool edge = false;  ///< another id in the golden's 3x3 neighbourhood
    std::vector<float> golden, candidate;
};

struct IdComparison {
    std::string name;
    int width = 0, height = 0, channels = 0;
    Tolerance tolerance;
    std::int64_t pixels = 0;
    std::int64_t edge_pixels = 0;  ///< golden pixels with another id in their 3x3 neighbourhood
    std::int64_t edge_mismatches = 0, interior_mismatches = 0;
    std::int64_t allowed_edge_mismatches = 0;  ///< floor(share x edge_pixels)
    /// Decision buffers (Tolerance::margin): the flips where the oracle lay within ε of the
    /// threshold (not counted as edge or interior mismatches), and their pixels; the largest
    /// |margin| among them, and the smallest among the far flips (-1: none).
    std::int64_t near_threshold = 0;
    std::vector<glm::ivec2> near_pixels;
    double near_max_margin = -1.0, far_min_margin = -1.0;
    std::string margin_source;  ///< the margin's buffer or derivation ("" without)
    bool pass = true;
    /// The first `listed` interior mismatches, then the first edge ones (row-major each).
    std::vector<IdMismatch> mismatches;
    /// 1 where the ids agree, 0 where they differ (width x height): the diff's mask.
    std::vector<std::uint8_t> agree;
    /// Per pixel: 0 agree, 1 edge mismatch, 2 interior mismatch.
    Image mismatch_map;
};

/// Compares an id or mask buffer as integers (see above). Values are equal when bit-equal, both
/// zero, or both NaN. `margin` (the oracle's decision margins, same width and height, one channel
/// per ε of tolerance.margin_epsilon) makes it a decision buffer: see Tolerance::margin.
IdComparison compare_id_buffers(const std::string& name, const Image& golden,
                                const Image& candidate, const Tolerance& tolerance, int listed = 5,
                                const Image* margin = nullptr);

/// The margins the diff derives itself (Tolerance::margin): "screen_border(POINTS)", the
/// distance in pixels of each texel's screen point (golden buffer POINTS, 2 channels) from the
/// border of the screen [0, W) x [0, H) (validity: on screen or not; the gaze circle's edge is
/// not covered), and "pixel_edge(POINTS)", its distance from the nearest pixel edge (which pixel
/// floor(point) picks).
Image derived_decision_margin(const std::string& derivation, const Image& points, int screen_width,
                              int screen_height);
/// The golden buffer a derivation reads ("lp_screen_point" of "screen_border(lp_screen_point)"),
/// "" when `margin` is a plain buffer name.
std::string decision_margin_input(const std::string& margin);

}  // namespace fovref
