#include "ref/stage/probe.h"

#include <cstdio>
#include <memory>

#include "ref/core/error.h"
#include "ref/core/vec.h"

namespace fovref {

std::string probe_float(float v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
    return text;
}

std::string probe_vec3(glm::vec3 v) {
    return "(" + probe_float(v.x) + ", " + probe_float(v.y) + ", " + probe_float(v.z) + ")";
}

namespace {

// The frame, pixel, texel and eye of a probe, checked before any work; a texel's x and y are 0.
void check_probe_target(const ModeInfo& mode, const RenderSettings& settings, int frame, int& x,
                        int& y, const std::optional<glm::ivec2>& texel, int eye) {
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
}

// "lp_ (3, 4), (4, 4)": the buffer texels pass 2 reads for the pixel, by buffer family.
std::string texels_text(const std::vector<TexelRead>& reads) {
    std::string text, family;
    for (const TexelRead& read : reads) {
        if (read.family != family) {
            text += (text.empty() ? "" : "; ") + read.family + "* ";
            family = read.family;
        } else {
            text += ", ";
        }
        text += "(" + std::to_string(read.texel.x) + ", " + std::to_string(read.texel.y) + ")";
    }
    return text.empty() ? "none (the barrel source leaves the eye's image)" : text;
}

// [screen]: the pixel (or the screen, for a texel), the frame, the camera, the viewing distance
// and, in a mode whose pass 2 reads buffer texels, the texels this pixel reads.
ProbeSection screen_section(const Scene* scene, const ModeInfo& mode, const RenderSettings& s,
                            const FrameResult& last, const ProbeReport& report,
                            const Camera& camera) {
    ProbeSection screen{"screen", report.texel ? "the screen" : "screen pixel", {}};
    const std::string size = std::to_string(s.width) + "x" + std::to_string(s.height);
    const glm::vec2 centre = pixel_centre(report.x, report.y);
    if (report.texel)
        screen.add("screen", size);
    else
        screen.add("pixel", "(" + std::to_string(report.x) + ", " + std::to_string(report.y) +
                                ") of " + size + ", centre (" + probe_float(centre.x) + ", " +
                                probe_float(centre.y) + ")");
    screen.add("frame",
               std::to_string(report.frame) + ", camera-path time " + probe_float(last.time));
    if (!scene) return screen;
    screen.add("camera", "position " + probe_vec3(camera.position) + ", forward " +
                             probe_vec3(camera.forward) + ", vfov " + probe_float(camera.vfov_deg) +
                             " deg");
    screen.add("viewing distance", probe_float(last.display_distance_px) + " px");
    if (!report.texel && mode.pixel_texels)
        screen.add("reads texels",
                   texels_text(mode.pixel_texels(*scene, s, report.frame, report.x, report.y)) +
                       " (pass 2's taps, traced or not)");
    return screen;
}

// [buffers]: every buffer's value at the pixel (or the texel), in pipeline order.
ProbeSection buffers_section(const RenderSettings& s, const FrameResult& last,
                             const ProbeReport& report) {
    const bool texel = report.texel.has_value();
    ProbeSection buffers{"buffers",
                         texel ? "every buffer at this texel, in pipeline order"
                               : "every buffer at this pixel, in "
                                 "pipeline order",
                         {}};
    // A texel is looked up in the buffers that are not screen-sized (the foveation buffers).
    const glm::ivec2 at = report.buffer_texel ? *report.buffer_texel
                          : texel             ? *report.texel
                                              : glm::ivec2(report.x, report.y);
    for (const StageRun& run : last.stages)
        if (!run.ran) buffers.add("stage " + run.name, "skipped (" + run.note + ")");
    for (const Buffer& b : last.buffers) {
        const std::string key = b.stage + " -> " + b.name;
        const bool screen_sized = b.image.width == s.width && b.image.height == s.height;
        if (screen_sized == texel || at.x >= b.image.width || at.y >= b.image.height) {
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
            value += (c ? ", " : "") + name + " " + probe_float(b.image.at(at.x, at.y, c));
        }
        buffers.add(key, value);
    }
    return buffers;
}

}  // namespace

ProbeReport probe_pixel(const Scene* scene, const ModeInfo& mode, const RenderSettings& settings,
                        int frame, int x, int y, std::optional<glm::ivec2> texel, int eye) {
    check_probe_target(mode, settings, frame, x, y, texel, eye);
    // Frames before `frame` run too: later modes carry state (TAA history) from frame to frame.
    RenderSettings s = settings;
    s.frame_count = frame + 1;
    s.requested = {"all"};
    FrameResult last, previous;
    render_each(scene, mode, s, [&](FrameResult& f) {
        if (f.frame == frame) last = std::move(f);  // the last frame
        if (f.frame + 1 == frame) previous = f;     // a copy: TAA reads it in the next frame
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
    report.sections.push_back(screen_section(scene, mode, s, last, report, camera));

    // What the mode's own explainer says about the pixel, stage by stage.
    if (mode.explain) {
        const Camera previous_camera =
            scene && frame > 0
                ? camera_at(*scene, s.time_start + static_cast<float>(frame - 1) * s.time_step)
                : camera;
        ProbeContext context{
            scene, &s,        &last,          frame > 0 ? &previous : nullptr, camera, x, y, texel,
            eye,   Offset2{}, previous_camera};
        mode.explain(context, report);
    }
    report.sections.push_back(buffers_section(s, last, report));
    report.rendered = std::make_shared<const FrameResult>(std::move(last));
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

}  // namespace fovref
