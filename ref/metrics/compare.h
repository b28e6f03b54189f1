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
// i.e. bit-exact up to the sign of zero). A pixel fails when any of its channels does; a buffer
// fails when more than max_failing_pixels pixels fail.
// clang-format on
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ref/image/image.h"
#include "ref/metrics/rings.h"

namespace fovref {

struct Tolerance {
    double abs = 0.0;
    double rel = 0.0;
    std::int64_t ulp = 0;
    std::int64_t max_failing_pixels = 0;
    std::string reason;  ///< SPEC §11: every tolerance states why
    bool operator==(const Tolerance&) const = default;
};

/// Per-buffer tolerances; "*" (or the default-constructed fallback) applies to the rest.
struct ToleranceTable {
    std::map<std::string, Tolerance> buffers;
    Tolerance fallback;
    const Tolerance& for_buffer(const std::string& name) const;
};

/// Tolerance file (JSON): { "buffer name" or "*": {"abs": x, "rel": x, "ulp": n,
/// "max_failing_pixels": n, "reason": "..."} }. Throws fovref::Error naming the file, line and key.
ToleranceTable read_tolerance_file(const std::string& path);
/// Command-line form "NAME:abs=1e-6,rel=1e-4,ulp=2,pixels=10" (NAME may be "*"); added to
/// `table`, overriding a file's entry for the same name. Throws fovref::Error naming the option.
void parse_tolerance_option(const std::string& option, ToleranceTable& table);

/// Distance of two floats in the binary32 ordering (see above); both must not be NaN.
std::int64_t ulp_distance(float a, float b);

struct PixelDifference {
    int x = 0, y = 0;
    double abs_error = 0.0;  ///< largest channel |c - g| (inf for a NaN mismatch)
    std::vector<float> golden, candidate;
};

struct CompareOptions {
    /// Absolute threshold for the "share of pixels over the threshold" figure; < 0 means the
    /// tolerance's abs (so with the default tolerance: pixels that differ at all).
    double threshold = -1.0;
    int worst_pixels = 5;  ///< how many worst pixels to list
    /// Ring errors and SSIM are computed for 1- and 3-channel buffers of at least 11x11; the
    /// ring layout (may be null: no ring errors).
    const RingLayout* rings = nullptr;
};

struct BufferComparison {
    std::string name;
    int width = 0, height = 0, channels = 0;
    Tolerance tolerance;
    double max_abs = 0.0, max_rel = 0.0;
    std::int64_t max_ulp = 0;
    std::int64_t nan_mismatches = 0;      ///< elements where exactly one side is NaN
    std::int64_t differing_elements = 0;  ///< elements whose bits differ
    double mean_abs = 0.0, rmse = 0.0, psnr = 0.0;
    std::optional<double> ssim;  ///< luma SSIM for 3 channels, the channel itself for 1
    double threshold = 0.0;
    std::int64_t pixels_over_threshold = 0;
    std::int64_t failing_pixels = 0;
    bool pass = true;
    std::optional<PixelDifference> first_failing;  ///< row-major first failing pixel
    std::vector<PixelDifference> worst;            ///< largest abs error first; ties row-major
    Image abs_error;                               ///< per-pixel largest channel |c - g|
    std::vector<RingStats> rings;
};

/// Compares candidate against golden (same shape: the caller checks and reports a mismatch as an
/// input error). Sums in binary64, row-major then channel.
BufferComparison compare_buffers(const std::string& name, const Image& golden,
                                 const Image& candidate, const Tolerance& tolerance,
                                 const CompareOptions& options = {});

}  // namespace fovref
