// IEEE-754 binary16 ("half") in integer code (SPEC §9 item 5): BMFR stores its block matrix in
// binary16, as the authors' OpenCL code does (vstore_half, round to nearest even). No compiler
// extension or instruction set is used, so the bits are the same on every build.
#pragma once

#include <cstdint>

namespace fovref {

/// The binary16 nearest to f, ties to even; |f| >= 65520 gives +-inf, NaN a quiet NaN.
std::uint16_t half_from_float(float f);

/// The exact value of a binary16 (every half is a float).
float float_from_half(std::uint16_t h);

/// The largest finite binary16.
inline constexpr float half_max = 65504.0f;

/// What storing f as binary16 and loading it back gives, saturating instead of overflowing:
/// f is first clamped to [-65504, 65504] (so a finite input never becomes infinite; SPEC §0),
/// then rounded to the nearest binary16, ties to even. NaN stays NaN.
float round_to_half(float f);

}  // namespace fovref
