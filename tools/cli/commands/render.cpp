#include "tools/cli/commands/render.h"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <optional>

#include "ref/core/error.h"
#include "ref/core/simd.h"
#include "ref/image/image_io.h"
#include "ref/modes/modes.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/output_dir.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

// "frame F: stage stage (skipped) ..., counter N, ..." as render prints it.
std::string frame_line(const FrameResult& f) {
    std::string line = "frame " + std::to_string(f.frame) + ":";
    for (const StageRun& stage : f.stages)
        line += " " + stage.name + (stage.ran ? "" : " (skipped)");
    for (const auto& [k, v] : f.counters.values) line += ", " + k + " " + std::to_string(v);
    return line;
}

// --frames N or A..B: sets first_frame for a range.
int parse_count(const std::string& text, const std::string& what) {
    std::size_t used = 0;
    int value = -1;
    try {
        value = std::stoi(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])))
        throw Error("--frames " + what + ": '" + text + "' is not a non-negative integer");
    return value;
}

void parse_frames(RenderOptions& o) {
    const std::size_t dots = o.frames.find("..");
    if (dots == std::string::npos) {
        parse_count(o.frames, o.frames);
        return;
    }
    const int a = parse_count(o.frames.substr(0, dots), o.frames);
    const int b = parse_count(o.frames.substr(dots + 2), o.frames);
    if (b < a) throw Error("--frames " + o.frames + ": the range is empty (B < A)");
    if (a > 100000 || static_cast<std::int64_t>(b) - a + 1 > 100000)
        throw Error("--frames " + o.frames +
                    ": at most 100000 frames, starting at frame 100000 at the latest");
    if (o.first_frame != 0 && o.first_frame != a)
        throw Error("--frames " + o.frames + " and --first-frame " + std::to_string(o.first_frame) +
                    " disagree; give one");
    o.first_frame = a;
    o.frames = std::to_string(b - a + 1);
}

int frame_count(const RenderOptions& o) { return parse_count(o.frames, o.frames); }

// The buffers of frame `frame` in the bundle `directory`, checked to come from the same render.
// `free_param`: a parameter that may differ between the runs (the reference's spp).
std::vector<Buffer> resume_buffers(const std::string& directory, const GoldenCase& run, int frame,
                                   const std::string& free_param = "") {
    const Manifest manifest = read_manifest(directory);
    const GoldenCase& c = manifest.golden_case;
    Params bundle_params = c.params, run_params = run.params;
    if (!free_param.empty()) {
        bundle_params.set(free_param, "");
        run_params.set(free_param, "");
    }
    if (c.mode != run.mode || c.scene != run.scene || c.width != run.width ||
        c.height != run.height || bundle_params != run_params || c.time_start != run.time_start ||
        c.time_step != run.time_step)
        throw Error("--resume " + directory +
                    ": the bundle was rendered with other settings (mode, scene, size, "
                    "parameters or camera-path times differ)");
    std::vector<Buffer> buffers;
    for (const ManifestBuffer& b : manifest.buffers) {
        if (b.frame != frame || b.file.empty()) continue;
        Buffer buffer;
        buffer.name = b.name;
        buffer.image = read_image(directory + "/" + b.file);
        buffers.push_back(std::move(buffer));
    }
    if (buffers.empty())
        throw Error("--resume " + directory + ": the bundle holds no buffer of frame " +
                    std::to_string(frame) + " (dump frames up to " + std::to_string(frame) +
                    " with --dump)");
    return buffers;
}

// The case `render` renders, resolved once: its mode and scene, the frame count, the static
// camera, the primary visibility.
ResolvedCase render_case(const RenderOptions& o) {
    ResolvedCase c = resolve_case(o, "render");
    c.run.frames = frame_count(o);
    if (o.static_camera) {
        if (o.time_step != RenderOptions{}.time_step)
            throw Error(
                "--static-camera and --time-step both given: give one (--static-camera is "
                "--time-step 0)");
        c.run.time_step = 0.0f;
    }
    if (!o.primary.empty()) c.run.params.set("primary", o.primary);
    return c;
}

// The first frame and the state it starts from (--first-frame, --resume), checked against the
// mode: a stateful mode renders from frame 0 or resumes from frame F - 1's dump; the reference
// continues the same frame's sums.
void set_first_frame(const RenderOptions& o, const ResolvedCase& c, RenderSettings& settings) {
    const ModeInfo& mode = *c.mode;
    if (o.first_frame > 0 && !mode.stateless)
        throw Error("--first-frame: mode '" + o.mode +
                    "' carries state from frame to frame; render from frame 0");
    settings.first_frame = o.first_frame;
    if (o.resume.empty()) return;
    if (mode.resume_same_frame) {
        // the reference: continue the same frame's sums
        if (frame_count(o) != 1)
            throw Error("--resume " + o.resume + ": mode '" + o.mode +
                        "' continues the accumulation of one frame: render one frame "
                        "(--frames 1, --first-frame F)");
        settings.state_buffers = resume_buffers(o.resume, c.run, o.first_frame, "spp");
        return;
    }
    if (!carries_state(mode, c.run.params))
        throw Error("--resume " + o.resume + ": mode '" + o.mode +
                    "' carries no state from frame to frame with these parameters (no TAA, "
                    "no BMFR): render frame F alone with --first-frame F");
    if (o.first_frame == 0)
        throw Error("--resume " + o.resume +
                    ": frame 0 has no previous frame; give "
                    "--first-frame F (or --frames A..B with A > 0)");
    settings.state_buffers = resume_buffers(o.resume, c.run, o.first_frame - 1);
}

// The bundles render writes: --dump (every buffer) and --out (the requested or final ones), each
// with the scene on --with-scene.
struct RenderWriters {
    std::optional<BundleWriter> dump, out;
};
void open_writers(const RenderOptions& o, const ResolvedCase& c, RenderWriters& w) {
    BundleOptions options;
    options.previews_for_all = true;
    options.include_timings = true;
    if (!o.dump_dir.empty()) w.dump.emplace(o.dump_dir, c.run, options);
    if (!o.out_dir.empty()) w.out.emplace(o.out_dir, c.run, options);
    if (o.with_scene) {
        if (!c.scene) throw Error("render --with-scene: mode '" + o.mode + "' has no scene");
        if (w.dump) w.dump->add_scene(*c.scene, "scene");
        if (w.out) w.out->add_scene(*c.scene, "scene");
    }
}

}  // namespace

int run_render(const RenderOptions& given) {
    RenderOptions o = given;
    parse_frames(o);
    if (o.out_dir.empty() && o.dump_dir.empty())
        throw Error("render: give --out DIR and/or --dump DIR");
    if (o.scalar) set_simd_allowed(false);
    // The outputs checked before any work (BundleWriter stages and swaps each in at the end)
    for (const auto& [option, dir] : {std::pair{"--out", o.out_dir}, {"--dump", o.dump_dir}})
        if (!dir.empty()) check_output_directory(option, dir);
    check_separate_outputs({{"--out", o.out_dir}, {"--dump", o.dump_dir}});
    const ResolvedCase c = render_case(o);
    const bool keep_all = std::find(o.outputs.begin(), o.outputs.end(), "all") != o.outputs.end();
    // With --dump every buffer is computed; --out keeps the requested (or final) ones.
    const std::vector<std::string> requested =
        o.dump_dir.empty() ? o.outputs : std::vector<std::string>{"all"};
    RenderWriters writers;
    open_writers(o, c, writers);
    Progress progress("render " + o.mode, o.quiet);
    RenderSettings settings =
        case_settings(c.run, requested, [&](double f) { progress.update(f); });
    set_first_frame(o, c, settings);
    const std::vector<std::string> wanted =
        o.outputs.empty() ? c.mode->build(c.scene_or_null(), settings).final_outputs : o.outputs;
    std::vector<std::string> lines;
    render_each(c.scene_or_null(), *c.mode, settings, [&](FrameResult& f) {
        lines.push_back(frame_line(f));
        if (writers.dump) writers.dump->add_frame(f);
        // --out writes the wanted buffers; the frame keeps the others, for render_each to hand
        // back to the stages that recycle or carry them.
        if (writers.out) writers.out->add_frame(f, keep_all ? nullptr : &wanted);
    });
    progress.finish();
    if (writers.dump) writers.dump->commit();
    if (writers.out) writers.out->commit();
    for (const std::string& line : lines) say(o.quiet, line);
    const std::string count = std::to_string(c.run.frames);
    if (writers.dump)
        say(o.quiet, "dumped every buffer of " + count + " frame(s) to " + o.dump_dir);
    if (writers.out) say(o.quiet, "wrote " + count + " frame(s) to " + o.out_dir);
    return exit_ok;
}

}  // namespace fovref
