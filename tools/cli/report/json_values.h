// Metric values and ring statistics as JSON, shared by the reports of `fovref diff` and `fovref
// evaluate`.
#pragma once

#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "ref/metrics/rings.h"

namespace fovref {

/// A metric value for JSON: finite numbers as numbers, +-infinity as the strings "inf"/"-inf"
/// (PSNR of equal images), NaN (undefined, e.g. SSIM of a ring outside the valid region) as null.
inline nlohmann::json number_json(double v) {
    if (std::isnan(v)) return nullptr;
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    return v;
}

/// One ring's statistics.
inline nlohmann::json ring_json(const RingStats& s) {
    return {{"ring", s.ring},
            {"inner_deg", s.inner_deg},
            {"outer_deg", s.outer_deg},
            {"pixels", s.pixels},
            {"mse", number_json(s.mse)},
            {"rmse", number_json(s.rmse)},
            {"psnr", number_json(s.psnr)},
            {"ssim", number_json(s.ssim)},
            {"sd", number_json(s.sd)}};
}

}  // namespace fovref
