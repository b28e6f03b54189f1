#include "ref/stage/probe.h"

#include <cstdio>
#include <cstring>

#include "ref/core/error.h"

namespace fovref {

std::string probe_float(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
    return text;
}

std::string probe_vec3(glm::vec3 v) {
    return "(" + probe_float(v.x) + ", " + probe_float(v.y) + ", " + probe_float(v.z) + ")";
}

std::string probe_bits(float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, 4);
    char text[16];
    std::snprintf(text, sizeof text, "0x%08x", bits);
    return text;
}

ProbeReport probe_pixel(const Scene* scene, const ModeInfo& mode, const RenderSettings& settings,
                        int frame, int x, int y, std::optional<glm::ivec2> texel, int eye) {
    validate_settings(settings);      // --width 0 is a bad width, not a pixel outside the screen
    constexpr int max_frame = 99999;  // frames 0 .. F run: at most 100000 (validate_settings)
    if (frame < 0 || frame > max_frame)
        throw Error("--frame " + std::to_string(frame) + ": must be in [0, " +
                    std::to_string(max_frame) + "] (frames 0 .. F are rendered)");
    if (eye >= 0 && !texel) throw Error("an eye is given with --texel I,J,EYE only");
    if (texel) {
        x = 0;
        y = 0;
        if (!mode.explain || !mode.explains_texels)
            throw Error("--texel: mode '" + mode.name +
                        "' has no foveation buffer (give --pixel X,Y)");
    }
    if (x < 0 || y < 0 || x >= settings.width || y >= settings.height)
        throw Error("--pixel " + std::to_string(x) + "," + std::to_string(y) + ": outside the " +
                    std::to_string(settings.width) + "x" + std::to_string(settings.height) +
                    " screen");
    // Frames before `frame` run too: later modes carry state (TAA history) from frame to frame.
    RenderSettings s = settings;
    s.frame_count = frame + 1;
    s.requested = {"all"};
    FrameResult last, previous;
    render_each(scene, mode, s, [&](FrameResult& f) {
        if (f.frame == frame) last = std::move(f);
        if (f.frame + 1 == frame) previous = std::move(f);
    });

    ProbeReport report;
    report.mode = mode.name;
    report.frame = frame;
    report.x = x;
    report.y = y;
    report.texel = texel;
    report.eye = eye;
    const float time = s.time_start + static_cast<float>(frame) * s.time_step;
    const Camera camera = scene ? camera_at(*scene, time) : Camera{};

    ProbeSection screen{"screen", texel ? "the screen" : "screen pixel", {}};
    if (texel)
        screen.add("screen", std::to_string(s.width) + "x" + std::to_string(s.height));
    else
        screen.add("pixel", "(" + std::to_string(x) + ", " + std::to_string(y) + ") of " +
                                std::to_string(s.width) + "x" + std::to_string(s.height) +
                                ", centre (" + probe_float(static_cast<float>(x) + 0.5f) + ", " +
                                probe_float(static_cast<float>(y) + 0.5f) + ")");
    screen.add("frame", std::to_string(frame) + ", camera-path time " + probe_float(time));
    if (scene) {
        screen.add("camera", "position " + probe_vec3(camera.position) + ", forward " +
                                 probe_vec3(camera.forward) + ", vfov " +
                                 probe_float(camera.vfov_deg) + " deg");
        screen.add("viewing distance", probe_float(last.display_distance_px) + " px");
    }
    report.sections.push_back(screen);

    // What the mode's own explainer says about the pixel, stage by stage.
    if (mode.explain) {
        ProbeContext context{scene, &s,    &last, frame > 0 ? &previous : nullptr, camera, x,
                             y,     texel, eye};
        mode.explain(context, report);
    }

    // Every buffer's value at the pixel, in pipeline order (screen-sized buffers only).
    ProbeSection buffers{"buffers",
                         texel ? "every buffer at this texel, in pipeline order"
                               : "every buffer at this pixel, in "
                                 "pipeline order",
                         {}};
    // A texel is looked up in the buffers that are not screen-sized (the foveation buffers).
    const glm::ivec2 at = report.buffer_texel ? *report.buffer_texel
                          : texel             ? *texel
                                              : glm::ivec2(x, y);
    const int bx = at.x, by = at.y;
    for (const StageRun& run : last.stages)
        if (!run.ran) buffers.add("stage " + run.name, "skipped (" + run.note + ")");
    for (const Buffer& b : last.buffers) {
        const std::string key = b.stage + " -> " + b.name;
        const bool screen_sized = b.image.width == s.width && b.image.height == s.height;
        if (screen_sized == texel.has_value() || bx >= b.image.width || by >= b.image.height) {
            buffers.add(key,
                        std::to_string(b.image.width) + "x" + std::to_string(b.image.height) +
                            (texel ? " (a screen-space buffer)" : " (not a screen-space buffer)"));
            continue;
        }
        std::string value;
        for (int c = 0; c < b.image.channels; ++c) {
            const std::string name = c < static_cast<int>(b.channel_names.size())
                                         ? b.channel_names[static_cast<std::size_t>(c)]
                                         : std::to_string(c);
            value += (c ? ", " : "") + name + " " + probe_float(b.image.at(bx, by, c));
        }
        buffers.add(key, value);
    }
    report.sections.push_back(buffers);
    return report;
}

std::string probe_text(const ProbeReport& report) {
    const std::string target =
        report.texel
            ? "texel (" + std::to_string(report.texel->x) + ", " + std::to_string(report.texel->y) +
                  ")" + (report.eye >= 0 ? " of eye " + std::to_string(report.eye) : "")
            : "pixel (" + std::to_string(report.x) + ", " + std::to_string(report.y) + ")";
    std::string out = "fovref probe: mode " + report.mode + ", frame " +
                      std::to_string(report.frame) + ", " + target + "\n";
    for (const ProbeSection& section : report.sections) {
        out += "\n[" + section.stage + "] " + section.title + "\n";
        std::size_t width = 0;
        for (const ProbeLine& line : section.lines) width = std::max(width, line.key.size());
        for (const ProbeLine& line : section.lines)
            out += "  " + line.key + std::string(width - line.key.size(), ' ') + "  " + line.value +
                   "\n";
    }
    if (!report.consistent)
        out +=
            "\nWARNING: the probe's recomputation differs from the rendered buffer (see above)\n";
    return out;
}

std::string shell_quote(const std::string& text) {
    const bool plain = !text.empty() && text.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789_-+=/.,:@%") == std::string::npos;
    if (plain) return text;
    std::string out = "'";
    for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

std::string debugger_command(const std::string& debugger, const std::string& program,
                             const std::vector<std::string>& arguments,
                             const std::vector<PixelFunction>& functions, int x, int y) {
    if (functions.empty())
        throw Error("--debugger: this mode names no per-pixel functions to stop in");
    const std::string condition = "x == " + std::to_string(x) + " && y == " + std::to_string(y);
    std::string command;
    if (debugger == "gdb") {
        command = "gdb -q";
        for (const PixelFunction& f : functions)
            command += " -ex " + shell_quote("break " + f.function + " if " + condition);
        command += " -ex run --args " + shell_quote(program);
    } else if (debugger == "lldb") {
        command = "lldb";
        for (const PixelFunction& f : functions)
            command += " -o " +
                       shell_quote("breakpoint set -n " + f.function + " -c \"" + condition + "\"");
        command += " -o run -- " + shell_quote(program);
    } else {
        throw Error("--debugger '" + debugger + "': expected gdb or lldb");
    }
    for (const std::string& a : arguments) command += " " + shell_quote(a);
    return command;
}

}  // namespace fovref
