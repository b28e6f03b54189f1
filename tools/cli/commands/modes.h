// `fovref modes`: the render modes (ref/modes/modes.h) with their parameters, defaults and
// whether they need a scene. The command has no options.
#pragma once

namespace fovref {

/// Prints every mode and its `--param` keys on stdout. Returns 0.
int run_modes();

}  // namespace fovref
