// `fovref render`: renders frames of a mode and writes its final buffers (--out) and/or every
// intermediate buffer (--dump) as a bundle: PFM/EXR + PNG + manifest.json (docs/golden.md).
#pragma once

#include <string>
#include <vector>

#include "tools/cli/common/cli_common.h"

namespace CLI {
class App;
}

namespace fovref {

struct RenderOptions : CaseOptions {
    std::string frames = "1";    ///< a count N (frames 0..N-1 from --first-frame) or a range A..B
    int first_frame = 0;         ///< number of the first frame
    std::string resume;          ///< a bundle holding frame first_frame - 1 (state of TAA)
    bool static_camera = false;  ///< --time-step 0: every frame at the path's time_start
    std::string primary;         ///< "ray" or "raster": --param primary=... of basic ("" = unset)
    std::vector<std::string> outputs;  ///< buffers --out keeps ("all"; default: final outputs)
    std::string out_dir;               ///< the final (or --output) buffers
    std::string dump_dir;              ///< every buffer
    bool with_scene = false;           ///< also the scene files into DIR/scene of --out and --dump
    bool scalar = false;               ///< --scalar: the SIMD paths off (ref/core/simd.h)
    bool quiet = false;
};

/// Registers the command's options on `command`.
void add_render_options(CLI::App& command, RenderOptions& options);

/// Renders and writes the bundles. Returns 0; throws fovref::Error for usage and input errors.
int run_render(const RenderOptions& options);

}  // namespace fovref
