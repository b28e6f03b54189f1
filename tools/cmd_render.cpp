#include "tools/cmd_render.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <optional>

#include "ref/core/error.h"
#include "ref/modes/modes.h"
#include "tools/progress.h"

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

}  // namespace

void add_render_options(CLI::App& c, RenderOptions& o) {
    c.add_option("--scene", o.scene, "procedural scene name or scene file");
    c.add_option("--mode", o.mode, "render mode (see `fovref modes`)")->capture_default_str();
    c.add_option("--width", o.width, "screen width in pixels")->capture_default_str();
    c.add_option("--height", o.height, "screen height in pixels")->capture_default_str();
    c.add_option("--frames", o.frames, "number of frames")->capture_default_str();
    c.add_option("--first-frame", o.first_frame,
                 "number of the first frame (seeds rand() and sets the camera-path time): "
                 "render frame F of a sequence alone, bit-identical to the sequence's")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    c.add_option("--time-start", o.time_start, "camera-path time of frame 0")
        ->capture_default_str();
    c.add_option("--time-step", o.time_step, "camera-path time between frames")
        ->capture_default_str();
    c.add_option("--param", o.params, "mode parameter key=value (repeatable)");
    add_gaze_option(c, o);
    c.add_option("--primary", o.primary,
                 "primary visibility for 'basic': ray or raster (= --param primary=...)")
        ->check(CLI::IsMember({"ray", "raster"}));
    c.add_option("--output", o.outputs, "buffers to produce (default: the mode's final outputs)")
        ->delimiter(',');
    c.add_option("--out", o.out_dir,
                 "write the final buffers (PFM/EXR + PNG + manifest.json) here");
    c.add_option("--dump", o.dump_dir,
                 "write every intermediate buffer (PFM/EXR + PNG preview + manifest.json) here");
    c.add_flag("--with-scene", o.with_scene,
               "also write the scene into DIR/scene of --out and --dump (OBJ + MTL + "
               "textures + scene.json; OBJ triangle k is primitive id k)");
}

int run_render(const RenderOptions& o) {
    if (o.out_dir.empty() && o.dump_dir.empty())
        throw Error("render: give --out DIR and/or --dump DIR");
    const std::optional<Scene> scene = command_scene(o, "render");
    GoldenCase run = command_case(o, "render");
    run.frames = o.frames;
    if (!o.primary.empty()) run.params.set("primary", o.primary);
    const bool keep_all = std::find(o.outputs.begin(), o.outputs.end(), "all") != o.outputs.end();
    // With --dump every buffer is computed; --out keeps the requested (or final) ones.
    const std::vector<std::string> requested =
        o.dump_dir.empty() ? o.outputs : std::vector<std::string>{"all"};

    BundleOptions options;
    options.previews_for_all = true;
    options.include_timings = true;
    std::optional<BundleWriter> dump, out;
    if (!o.dump_dir.empty()) dump.emplace(o.dump_dir, run, options);
    if (!o.out_dir.empty()) out.emplace(o.out_dir, run, options);
    if (o.with_scene) {
        if (!scene) throw Error("render --with-scene: mode '" + o.mode + "' has no scene");
        if (dump) dump->add_scene(*scene, "scene");
        if (out) out->add_scene(*scene, "scene");
    }
    const std::vector<std::string> wanted =
        o.outputs.empty() ? find_mode(o.mode)
                                .build(scene ? &*scene : nullptr, case_settings(run, {}))
                                .final_outputs
                          : o.outputs;
    Progress progress("render " + o.mode, o.quiet);
    std::vector<std::string> lines;
    RenderSettings settings = case_settings(run, requested, [&](double f) { progress.update(f); });
    if (o.first_frame > 0 && !find_mode(o.mode).stateless)
        throw Error("--first-frame: mode '" + o.mode +
                    "' carries state from frame to frame; render from frame 0");
    settings.first_frame = o.first_frame;
    render_each(scene ? &*scene : nullptr, o.mode, settings, [&](FrameResult& f) {
        lines.push_back(frame_line(f));
        if (dump) dump->add_frame(f);
        if (out) {
            if (!keep_all)
                std::erase_if(f.buffers, [&](const Buffer& b) {
                    return std::find(wanted.begin(), wanted.end(), b.name) == wanted.end();
                });
            out->add_frame(f);
        }
    });
    progress.finish();
    if (dump) dump->commit();
    if (out) out->commit();
    for (const std::string& line : lines) say(o.quiet, line);
    if (dump)
        say(o.quiet,
            "dumped every buffer of " + std::to_string(o.frames) + " frame(s) to " + o.dump_dir);
    if (out) say(o.quiet, "wrote " + std::to_string(o.frames) + " frame(s) to " + o.out_dir);
    return exit_ok;
}

}  // namespace fovref
