#include <string>

#include "ref/modes/modes.h"
#include "tools/cli/commands/diff/internal.h"
#include "tools/cli/common/number_text.h"

namespace fovref {

BufferSpace space_of(const std::string& mode, const std::string& name) {
    for (const ModeInfo& m : render_modes())
        if (m.name == mode) return buffer_space(m, name);
    return BufferSpace::screen;
}

namespace {

// The probe's point for element (x, y) of buffer item.name, by the buffer's space: a texel of a
// foveation buffer (--texel I,J; both eyes side by side: I,J,EYE with the eye from the half it
// lies in), a pixel of a window of the screen moved by the window's origin (the frame's
// gaze_window_* counters), a screen pixel; "" for a list of samples, which has no pixel.
std::string probe_point(const Manifest& m, const DiffItem& item, int x, int y) {
    const bool known_frame =
        item.frame >= 0 && item.frame < static_cast<int>(m.frame_counters.size());
    const Counters none;
    const Counters& counters =
        known_frame ? m.frame_counters[static_cast<std::size_t>(item.frame)] : none;
    switch (item.space) {
        case BufferSpace::texel: return " --texel " + std::to_string(x) + "," + std::to_string(y);
        case BufferSpace::stereo_texel: {
            const auto w = counters.get("buffer_width");
            const auto eye = w > 0 && x >= w ? 1 : 0;
            return " --texel " + std::to_string(x - eye * w) + "," + std::to_string(y) + "," +
                   std::to_string(eye);
        }
        case BufferSpace::screen_window:
            x += static_cast<int>(counters.get("gaze_window_x0"));
            y += static_cast<int>(counters.get("gaze_window_y0"));
            break;
        case BufferSpace::samples: return "";
        case BufferSpace::screen: break;
    }
    return " --pixel " + std::to_string(x) + "," + std::to_string(y);
}

}  // namespace

std::string probe_command(const Manifest& m, const DiffItem& item, int x, int y) {
    const GoldenCase& c = m.golden_case;
    if (c.scene.empty() && c.mode.empty()) return "";
    std::string command = "fovref probe";
    if (!c.scene.empty()) command += " --scene " + c.scene;
    command += " --mode " + c.mode + " --width " + std::to_string(c.width) + " --height " +
               std::to_string(c.height);
    if (c.time_start != 0.0f) command += " --time-start " + number_text(c.time_start, "%.4g", "-");
    if (c.frames > 1 || item.frame > 0)
        command += " --time-step " + number_text(c.time_step, "%.4g", "-");
    const std::string point = probe_point(m, item, x, y);
    if (point.empty()) return "";
    command += " --frame " + std::to_string(item.frame) + point;
    for (const auto& [key, value] : c.params.values()) command += " --param " + key + "=" + value;
    return command;
}

}  // namespace fovref
