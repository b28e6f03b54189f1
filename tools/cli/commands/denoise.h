// `fovref denoise bmfr IN_DIR OUT_DIR`: BMFR (ref/bmfr, docs/bmfr.md) on the per-frame buffers
// another renderer wrote, so that a GPU developer can denoise their own path tracer's frames
// with the reference and diff every phase (`fovref diff`). docs/bmfr.md, "Denoising external
// buffers", documents the input layout.
#pragma once

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fovref {

struct DenoiseOptions {
    std::string input;                ///< IN_DIR
    std::string output;               ///< OUT_DIR (a bundle)
    std::vector<std::string> params;  ///< --param k=v (bmfr_storage, the limits)
    bool quiet = false;
};

void add_denoise_options(CLI::App& command, DenoiseOptions& options);

/// Denoises every frame of IN_DIR and writes the bundle; throws fovref::Error naming the file.
int run_denoise(const DenoiseOptions& options);

}  // namespace fovref
