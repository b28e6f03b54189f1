// `fovref probe --debugger`: the conditional breakpoints that stop a debugger where one screen
// pixel (or one buffer texel) is computed - in each pass's per-pixel function, at the
// coordinates that function receives (the pixel, the texels pass 2 reads for it, the pixel within
// its eye, the BMFR block), in the probed frame and the stage that calls it - and the gdb or lldb
// command line that sets them.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ref/stage/pipeline.h"

namespace fovref {

/// Where to stop: a screen pixel with the texels pass 2 reads for it (ModeInfo::pixel_texels),
/// or one texel of the mode's buffer (`probe --texel`; then `pixel` is empty).
struct DebugTarget {
    int frame = 0;
    std::optional<glm::ivec2> pixel;
    std::vector<TexelRead> texels;
    int eye_width = 0;  ///< stereo: W / 2, the width of one eye's half of the screen
    /// Screen points no triangle covers (G-buffer primitive -1): the rasterizer never reaches
    /// them (PixelFunction::needs_geometry).
    std::vector<glm::ivec2> background;
};

/// One function's breakpoint for a target.
struct Breakpoint {
    PixelFunction function;
    int stage = -1;         ///< the stage's index in the pipeline (DebuggerPosition::stage)
    std::string condition;  ///< the debugger's condition; empty: no breakpoint (`skipped`)
    std::vector<glm::ivec2> points;  ///< the coordinates it stops at (x, y or cell_x, cell_y)
    std::string x_name = "x", y_name = "y";  ///< the function's parameters holding them
    int eye = -1;                            ///< eye_pixel: the eye it stops in
    std::string coordinates;  ///< what it stops at, e.g. "x, y in texels (75..76, 215..216)"
    std::string skipped;      ///< why this function has no breakpoint for the target
};

/// The breakpoints of `functions` (a mode's ModeInfo::pixel_functions) for `target`, in order:
/// each conditioned on the coordinates its function receives, on the frame and on the index of
/// its stage in `pipeline` (fovref::debugger_position). A function that does not compute the
/// target (a screen pass for a texel; a gaze-buffer pass for a pixel read from the log-polar
/// buffer) gets no condition and a reason. Throws fovref::Error for a stage `pipeline` lacks.
std::vector<Breakpoint> debugger_breakpoints(const std::vector<PixelFunction>& functions,
                                             const Pipeline& pipeline,
                                             const RenderSettings& settings,
                                             const DebugTarget& target);

/// A shell command line that runs `program` with `arguments` under `debugger` ("gdb" or "lldb")
/// with `breakpoints` set (those with a condition). Throws fovref::Error for another debugger or
/// when no breakpoint has a condition.
std::string debugger_command(const std::string& debugger, const std::string& program,
                             const std::vector<std::string>& arguments,
                             const std::vector<Breakpoint>& breakpoints);

/// Quotes `text` for a POSIX shell when it needs it ('...' with embedded quotes escaped).
std::string shell_quote(const std::string& text);

}  // namespace fovref
