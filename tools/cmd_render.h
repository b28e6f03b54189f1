// `fovref render`: renders frames of a mode and writes its final buffers (--out) and/or every
// intermediate buffer (--dump) as a bundle: PFM/EXR + PNG + manifest.json (docs/golden.md).
#pragma once

#include <string>
#include <vector>

#include "tools/cli_common.h"

namespace CLI {
class App;
}

namespace fovref {

struct RenderOptions : CaseOptions {
    int frames = 1;       ///< number of frames
    int first_frame = 0;  ///< number of the first frame (stateless modes only)
    std::string primary;  ///< "ray" or "raster": --param primary=... of basic ("" = unset)
    std::vector<std::string> outputs;  ///< buffers --out keeps ("all"; default: final outputs)
    std::string out_dir;               ///< the final (or --output) buffers
    std::string dump_dir;              ///< every buffer
    bool with_scene = false;           ///< also the scene files into DIR/scene of --out and --dump
    bool quiet = false;
};

/// Registers the command's options on `command`.
void add_render_options(CLI::App& command, RenderOptions& options);

/// Renders and writes the bundles. Returns 0; throws fovref::Error for usage and input errors.
int run_render(const RenderOptions& options);

}  // namespace fovref
