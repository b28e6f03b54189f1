// `fovref gain`: the theoretical gain of foveated rendering for a display (SPEC §5.6, Koskela P1
// §4; ref/analysis/gain.h): with no FOV given, P1's three headline cases next to the figures the
// sources quote; with --fov-deg, one FOV and display. docs/gain.md.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

/// The acuity model and the density assumption, as `gain` prints them (table, one case, --json)
/// and as its --help footer quotes them.
inline constexpr const char* gain_model_line =
    "V(e) = 60 c/deg for e <= 5.79 deg, 449.4 / (0.3 e + 1)^2 beyond (P1 eq. 2), clamped to "
    "V_max; e from the FOV centre (the gaze), degrees as planar coordinates";
inline constexpr const char* gain_density_note =
    "sample density is taken proportional to V (c/deg), not to V^2 (samples per deg^2), as in "
    "the sources";

struct GainOptions {
    std::string shape;            ///< "disc" or "ellipse"; "": one --fov-deg value is a disc
    std::vector<double> fov_deg;  ///< W (disc diameter) or W,H (ellipse); empty: P1's cases
    double max_cpd = 60.0;        ///< the display's maximum c/deg
    bool max_cpd_given = false;   ///< --max-cpd was on the command line
    int angle_steps = 4096;       ///< quadrature nodes per quadrant (ellipse)
    bool json = false;            ///< machine-readable output
};

/// Registers the command's options on `command`.
void add_gain_options(CLI::App& command, GainOptions& options);

/// Prints the gain (or P1's table). Returns 0; throws fovref::Error naming the option for a bad
/// value (the CLI exits 2).
int run_gain(const GainOptions& options);

}  // namespace fovref
