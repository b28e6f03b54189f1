// The lane helpers of ref/core/avx_lanes.h give the standard library's bits: std_max and std_min
// (vmaxps and vminps with their operands swapped) against std::max and std::min on every pair of
// hostile values, ties of +0 and -0 and NaN with payloads included.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "ref/core/avx_lanes.h"
#include "ref/core/simd.h"

using namespace fovref;

namespace {

// Lane l of std_max(a, b) and std_min(a, b) into max[l] and min[l].
__attribute__((target("avx"))) void lanes_max_min(const float* a, const float* b, float* max,
                                                  float* min) {
    const __m256 x = _mm256_loadu_ps(a), y = _mm256_loadu_ps(b);
    _mm256_storeu_ps(max, avx::std_max(x, y));
    _mm256_storeu_ps(min, avx::std_min(x, y));
}

}  // namespace

TEST_CASE("AVX lanes: std_max and std_min give std::max's and std::min's bits") {
    if (!cpu_has_avx()) {
        MESSAGE("no AVX on this CPU: nothing to compare");
        return;
    }
    constexpr float inf = std::numeric_limits<float>::infinity();
    const std::vector<float> values = {0.0f,
                                       -0.0f,
                                       1.0f,
                                       -1.0f,
                                       inf,
                                       -inf,
                                       1e-40f,
                                       -1e-40f,
                                       2.5f,
                                       2.5f,
                                       std::bit_cast<float>(0x7fc00001u),
                                       std::bit_cast<float>(0xffc00002u),
                                       3.0e38f,
                                       -7.0f};
    // Every ordered pair, eight at a time (the last group padded with its first pair).
    std::vector<float> a, b;
    for (const float x : values)
        for (const float y : values) {
            a.push_back(x);
            b.push_back(y);
        }
    while (a.size() % 8 != 0) {
        a.push_back(a.front());
        b.push_back(b.front());
    }
    int checked = 0;
    for (std::size_t i = 0; i < a.size(); i += 8) {
        float max[8], min[8];
        lanes_max_min(&a[i], &b[i], max, min);
        for (std::size_t l = 0; l < 8; ++l) {
            CAPTURE(a[i + l]);
            CAPTURE(b[i + l]);
            CHECK(std::bit_cast<std::uint32_t>(max[l]) ==
                  std::bit_cast<std::uint32_t>(std::max(a[i + l], b[i + l])));
            CHECK(std::bit_cast<std::uint32_t>(min[l]) ==
                  std::bit_cast<std::uint32_t>(std::min(a[i + l], b[i + l])));
            ++checked;
        }
    }
    CHECK(checked >= static_cast<int>(values.size() * values.size()));
}
