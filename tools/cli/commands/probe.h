// `fovref probe`: explains one screen pixel of a mode and frame stage by stage, recomputed by the
// passes' own per-pixel functions and checked against the rendered buffers; --debugger prints a
// gdb or lldb command that stops in each pass at the pixel. docs/probe-evaluate.md.
#pragma once

#include <string>

#include "tools/cli/common/cli_common.h"

namespace CLI {
class App;
}

namespace fovref {

struct ProbeOptions : CaseOptions {
    int frame = 0;         ///< frame number (frames before it run too)
    std::string pixel;     ///< "X,Y" of the screen pixel
    std::string texel;     ///< "I,J" of a foveation buffer texel (instead of --pixel)
    bool json = false;     ///< machine-readable output
    std::string debugger;  ///< "gdb" or "lldb": print a command that stops at the pixel
    bool quiet = false;
};

/// Registers the command's options on `command`.
void add_probe_options(CLI::App& command, ProbeOptions& options);

/// Prints the report. Returns 0, or 1 when the recomputation differs from the rendered buffer;
/// throws fovref::Error for usage and input errors.
int run_probe(const ProbeOptions& options);

}  // namespace fovref
