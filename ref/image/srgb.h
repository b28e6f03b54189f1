// sRGB transfer functions (IEC 61966-2-1:1999), in binary32; the one copy used by the image files
// (PNG read and write), the display transform and LDR-FLIP:
//   encode(L) = 12.92 L                      for L <= 0.0031308
//               1.055 L^(1/2.4) - 0.055      otherwise
//   decode(V) = V / 12.92                    for V <= 0.04045
//               ((V + 0.055) / 1.055)^2.4    otherwise
// The powers are dm::pow's values, computed through dm::PowFixed's tables (the same bits, several
// times faster). Values outside [0,1] follow the same formulas (no clamping here; write_png and
// display_transform clamp first).
#pragma once

#include "ref/core/dmath.h"

namespace fovref {

/// L^(1/2.4) and x^2.4 with the exponents rounded to binary32, as dm::pow(L, 1.0f / 2.4f).
inline const dm::PowFixed& srgb_encode_power() {
    static const dm::PowFixed power(1.0f / 2.4f);
    return power;
}
inline const dm::PowFixed& srgb_decode_power() {
    static const dm::PowFixed power(2.4f);
    return power;
}

/// The power segment of the encoding from L^(1/2.4) (for callers that batch the powers).
inline float srgb_encode_from_power(float powered) { return 1.055f * powered - 0.055f; }

inline float srgb_encode(float linear) {
    if (linear <= 0.0031308f) return 12.92f * linear;
    return srgb_encode_from_power(srgb_encode_power()(linear));
}

inline float srgb_decode(float encoded) {
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return srgb_decode_power()((encoded + 0.055f) / 1.055f);
}

}  // namespace fovref
