// `fovref density MODE` (issue 13, point 6; Lund §5.2 `mid_range_res`, SPEC §5.6): the radial and
// angular rays per pixel of a log-polar mode at the middle of each error ring, with Koskela's
// relative visual acuity for comparison, as a table, CSV and an SVG plot
// (ref/analysis/density.h). docs/foveation.md, "Density".
#pragma once

#include <string>
#include <vector>

#include "tools/cli/common/cli_common.h"

namespace CLI {
class App;
}

namespace fovref {

struct DensityOptions : CaseOptions {
    int rings = 20;          ///< error rings (Lund §4.3.3)
    float max_range = 1.0f;  ///< fraction of the largest eccentricity covered
    std::string out_dir;     ///< density.csv and density.svg here ("": table only)
    bool quiet = false;
};

void add_density_options(CLI::App& command, DensityOptions& options);

/// Prints the table and writes the files. Returns 0; throws fovref::Error for a mode that is not
/// a log-polar mode, or bad options.
int run_density(const DensityOptions& options);

}  // namespace fovref
