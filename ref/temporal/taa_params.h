// The TAA parameters of the modes that run the TAA pass (basic and the log-polar modes; SPEC §7,
// docs/temporal.md): `--param taa=off|depth|clamp-screen|clamp-buffer` and its tunables, and the
// Halton jitter of a frame.
#pragma once

#include <string>
#include <vector>

#include "ref/core/halton.h"
#include "ref/stage/params.h"
#include "ref/temporal/taa.h"

namespace fovref {

enum class TaaMode {
    off,           ///< no TAA and no jitter (the default)
    depth,         ///< depth-based rejection with tau (Lund §3.4.1)
    clamp_screen,  ///< Karis clamping to the 3x3 neighbourhood of the screen image (Lund §3.4.2)
    clamp_buffer,  ///< Karis clamping to the 3x3 neighbourhood in the buffer's own space
};
const char* taa_mode_name(TaaMode mode);

struct TaaSettings {
    TaaMode mode = TaaMode::off;
    TaaParams params;      ///< tau, the age cap, the periphery radius (rejection follows mode)
    int jitter_start = 0;  ///< frame f uses Halton point (f + start) mod 16 (SPEC §7)
    bool enabled() const { return mode != TaaMode::off; }
};

/// taa, taa_tau, taa_age_cap, taa_periphery, taa_jitter_start.
std::vector<ParamSpec> taa_param_specs();
/// Throws fovref::Error naming the parameter.
TaaSettings parse_taa_params(const Params& params);

/// The launch offset inside a pixel or texel for frame `frame` (SPEC §7): the scaled Halton(2,3)
/// point (frame + start) mod 16 when TAA is on and the camera is stationary; the centre
/// (1/2, 1/2) without TAA or while the camera moves (Lund §5.3.4).
Offset2 taa_jitter(const TaaSettings& settings, int frame, bool camera_moves);

}  // namespace fovref
