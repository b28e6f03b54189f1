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

/// Thomas Wang's 32-bit integer hash, which SPEC §9 names for BMFR's stochastic regularisation
/// (the authors' published OpenCL code uses Bob Jenkins' six-shift hash instead; docs/bmfr.md).
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
