// Counter-based random numbers (SPEC §0). There is no generator state: a number is a pure
// function of (frame, pixel index, dimension), so results never depend on evaluation order.
//
// Hash: PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering", pcg_hash), chained
//   rand_u32(f, p, d) = pcg_hash(pcg_hash(pcg_hash(f) ^ p) ^ d)
// mapped to [0,1) as (x >> 8) * 2^-24 (exact in float). The Wang hash is provided for BMFR's
// stochastic regularisation, which SPEC §9 takes from the authors' code.
#pragma once

#include <cstdint>

namespace fovref {

inline constexpr std::uint32_t pcg_hash(std::uint32_t input) {
    std::uint32_t state = input * 747796405u + 2891336453u;
    std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/// Bob Jenkins' 32-bit integer hash in six shifts (as Hoedt gives it): the BMFR authors'
/// `random()` in bmfr.cl, the default of BMFR's stochastic regularisation (SPEC §9 item 6,
/// docs/bmfr.md). Unsigned 32-bit wrap-around.
inline constexpr std::uint32_t jenkins_hash(std::uint32_t a) {
    a = (a + 0x7ed55d16u) + (a << 12u);
    a = (a ^ 0xc761c23cu) ^ (a >> 19u);
    a = (a + 0x165667b1u) + (a << 5u);
    a = (a + 0xd3a2646cu) ^ (a << 9u);
    a = (a + 0xfd7046c5u) + (a << 3u);
    a = (a ^ 0xb55a4f09u) ^ (a >> 16u);
    return a;
}

/// Thomas Wang's 32-bit integer hash: BMFR's regularisation with `bmfr_noise_hash=wang` (what
/// fovref used before it followed the authors' code; docs/bmfr.md).
inline constexpr std::uint32_t wang_hash(std::uint32_t seed) {
    seed = (seed ^ 61u) ^ (seed >> 16u);
    seed *= 9u;
    seed = seed ^ (seed >> 4u);
    seed *= 0x27d4eb2du;
    seed = seed ^ (seed >> 15u);
    return seed;
}

inline constexpr std::uint32_t rand_u32(std::uint32_t frame, std::uint32_t pixel,
                                        std::uint32_t dimension) {
    return pcg_hash(pcg_hash(pcg_hash(frame) ^ pixel) ^ dimension);
}

/// Uniform in [0, 1): the top 24 bits times 2^-24, exactly representable in float.
inline constexpr float u32_to_unit(std::uint32_t x) {
    return static_cast<float>(x >> 8u) * (1.0f / 16777216.0f);
}

inline constexpr float rand_unit(std::uint32_t frame, std::uint32_t pixel,
                                 std::uint32_t dimension) {
    return u32_to_unit(rand_u32(frame, pixel, dimension));
}

}  // namespace fovref
