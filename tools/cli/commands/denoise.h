// `fovref denoise bmfr IN_DIR OUT_DIR`: BMFR (ref/bmfr, docs/bmfr.md) on the per-frame buffers
// another renderer wrote, so that a GPU developer can denoise their own path tracer's frames
// with the reference and diff every phase (`fovref diff`). docs/bmfr.md, "Denoising external
// buffers", documents the input layout.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "ref/stage/pipeline.h"

namespace CLI {
class App;
}

namespace fovref {

struct DenoiseOptions {
    std::string input;                 ///< IN_DIR
    std::string output;                ///< OUT_DIR (a bundle)
    std::vector<std::string> params;   ///< --param k=v (bmfr_storage, the limits)
    bool demodulated = false;          ///< the input colour is already divided by albedo
    std::string frames;                ///< "N" or "A..B" ("": every frame)
    std::vector<std::string> outputs;  ///< buffers to write (empty or "all": every one)
    bool previews = false;             ///< a PNG of every buffer written
    bool quiet = false;
};

void add_denoise_options(CLI::App& command, DenoiseOptions& options);

/// What a denoise run covers: frames first .. last written (0 .. last run), the screen, the
/// BMFR parameters (--param and cameras.json's limits).
struct DenoiseRun {
    int first = 0, last = 0, width = 0, height = 0;
    Params params;
};

/// Reads IN_DIR's cameras, checks every input file of frames 0 .. last, then (unless `on_frame`
/// is empty) runs the load stage and BMFR's stages frame by frame, handing frames first .. last
/// to `on_frame` with the `requested` buffers and the stages' times. Throws fovref::Error naming
/// the file or option.
DenoiseRun denoise_each(const DenoiseOptions& options, const std::vector<std::string>& requested,
                        const std::function<void(double)>& progress,
                        const std::function<void(FrameResult&)>& on_frame);

/// Denoises every frame of IN_DIR and writes the bundle; throws fovref::Error naming the file.
int run_denoise(const DenoiseOptions& options);

}  // namespace fovref
