// sRGB transfer functions (IEC 61966-2-1:1999), in binary32 with dm::pow; the one copy used by the
// image files (PNG read and write) and by LDR-FLIP:
//   encode(L) = 12.92 L                      for L <= 0.0031308
//               1.055 L^(1/2.4) - 0.055      otherwise
//   decode(V) = V / 12.92                    for V <= 0.04045
//               ((V + 0.055) / 1.055)^2.4    otherwise
// Values outside [0,1] follow the same formulas (no clamping here; write_png clamps first).
#pragma once

#include "ref/core/dmath.h"

namespace fovref {

inline float srgb_encode(float linear) {
    if (linear <= 0.0031308f) return 12.92f * linear;
    return 1.055f * dm::pow(linear, 1.0f / 2.4f) - 0.055f;
}

inline float srgb_decode(float encoded) {
    if (encoded <= 0.04045f) return encoded / 12.92f;
    return dm::pow((encoded + 0.055f) / 1.055f, 2.4f);
}

}  // namespace fovref
