// Halton(2,3) sub-pixel offsets (Lund §3.2, §3.4, eq. 3.11; SPEC §7).
#pragma once

#include <array>
#include <cstdint>

namespace fovref {

struct Offset2 {
    float x = 0.5f;
    float y = 0.5f;
    bool operator==(const Offset2&) const = default;
};

/// Radical inverse of `index` in `base` (2 or 3), computed exactly in integers and rounded once to
/// float: halton(1, 2) = 0.5, halton(2, 2) = 0.25, halton(1, 3) = 1/3.
float halton(std::uint32_t index, std::uint32_t base);

/// Halton(2,3) points 1..16 (index 0 skipped), unscaled.
std::array<Offset2, 16> halton23_points16();

/// The 16 points scaled per axis by 0.5 / mean (Lund eq. 3.11) so that the mean offset is 0.5.
/// The scaled values are quantised to multiples of 2^-20 pixel with largest-remainder rounding,
/// which makes the mean exactly 0.5 in binary32 (rounding each product to float would miss it by
/// about an ulp); the quantisation moves no offset by more than 2^-20.
std::array<Offset2, 16> halton23_offsets16();

/// Offset used by frame `frame` with start index `start` (SPEC §7): point (frame + start) mod 16.
Offset2 halton_jitter(std::uint32_t frame, std::uint32_t start);

}  // namespace fovref
