#include "tools/cli/commands/probe.h"

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "ref/core/error.h"
#include "ref/modes/modes.h"
#include "ref/stage/probe.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

#ifndef FOVREF_SOURCE_DIR
#define FOVREF_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;

namespace fovref {

namespace {

// The debugger command of `probe --debugger`: `fovref render` of the same case under gdb/lldb,
// with a conditional breakpoint on the pixel in each per-pixel function of the mode's passes. A
// stateless mode renders only the probed frame (--first-frame), so each breakpoint stops once
// per call at that pixel in that frame; with TAA (or a mode with state) frames 0 .. F run.
std::string debugger_line(const ProbeOptions& o, const ResolvedCase& c, int x, int y) {
    const ModeInfo& mode = *c.mode;
    const GoldenCase& run = c.run;
    if (!mode.pixel_functions)
        throw Error("--debugger: mode '" + o.mode +
                    "' names no per-pixel functions to stop in (basic and ground-truth do)");
#if FOVREF_DEBUGGABLE
    std::error_code ec;
    std::string program = fs::canonical("/proc/self/exe", ec).string();
    if (ec) program = "fovref";
#else
    const std::string program = std::string(FOVREF_SOURCE_DIR) + "/build/clang-O0/fovref";
#endif
    std::vector<std::string> args = {"render"};
    if (!o.scene.empty()) args.insert(args.end(), {"--scene", o.scene});
    args.insert(args.end(), {"--mode", o.mode, "--width", std::to_string(o.width), "--height",
                             std::to_string(o.height)});
    char text[32];
    if (o.time_start != 0.0f) {
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(o.time_start));
        args.insert(args.end(), {"--time-start", text});
    }
    std::snprintf(text, sizeof text, "%.9g", static_cast<double>(o.time_step));
    args.insert(args.end(), {"--time-step", text});
    // TAA and BMFR carry state from frame to frame: then frames 0 .. F run (the breakpoints stop
    // in each).
    if (!carries_state(mode, run.params))
        args.insert(args.end(), {"--first-frame", std::to_string(o.frame), "--frames", "1"});
    else
        args.insert(args.end(), {"--frames", std::to_string(o.frame + 1)});
    for (const auto& [key, value] : run.params.values())
        args.insert(args.end(), {"--param", key + "=" + value});
    args.insert(args.end(), {"--out", "/tmp/fovref-debug", "-q"});
    return debugger_command(o.debugger, program, args, mode.pixel_functions(run.params), x, y);
}

nlohmann::json probe_json(const ProbeReport& report, const std::string& debug_command) {
    nlohmann::json j;
    if (!debug_command.empty()) j["debugger_command"] = debug_command;
    j["mode"] = report.mode;
    j["frame"] = report.frame;
    if (report.texel && report.eye >= 0)
        j["texel"] = {report.texel->x, report.texel->y, report.eye};
    else if (report.texel)
        j["texel"] = {report.texel->x, report.texel->y};
    else
        j["pixel"] = {report.x, report.y};
    j["consistent"] = report.consistent;
    for (const ProbeSection& section : report.sections) {
        nlohmann::json js;
        js["stage"] = section.stage;
        js["title"] = section.title;
        js["lines"] = nlohmann::json::array();
        for (const ProbeLine& line : section.lines)
            js["lines"].push_back({{"key", line.key}, {"value", line.value}});
        j["sections"].push_back(js);
    }
    return j;
}

// The [debugger] section of the text report: the functions it stops in and the command.
void print_debugger_section(const ResolvedCase& c, const std::string& debug_command) {
    std::cout << "\n[debugger] stop at this pixel in each pass's per-pixel function\n";
    for (const PixelFunction& f : c.mode->pixel_functions(c.run.params))
        std::cout << "  " << f.stage << ": " << f.function
                  << (f.note.empty() ? "" : " (" + f.note + ")") << "\n";
#if !FOVREF_DEBUGGABLE
    std::cout << "  this fovref has no debug info: build the debug preset first\n"
                 "  (cmake --preset debug && cmake --build --preset debug)\n";
#endif
    std::cout << "debug it: " << debug_command << "\n";
}

}  // namespace

void add_probe_options(CLI::App& c, ProbeOptions& o) {
    add_scene_options(c, o.scene);
    c.add_option("--mode", o.mode, "render mode (see `fovref modes`)")->required();
    add_screen_options(c, o.width, o.height, " in pixels");
    c.add_option("--frame", o.frame, "frame number (frames before it run too)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    c.add_option("--pixel", o.pixel, "X,Y of the screen pixel");
    c.add_option("--texel", o.texel,
                 "I,J of a texel of a foveated mode's log-polar buffer (column I, row J), "
                 "explained instead of a pixel: its screen point, ray, hit and shading; "
                 "stereo-lp: I,J,EYE (EYE 0 left, 1 right)");
    c.add_option("--time-start", o.time_start, "camera-path time of frame 0")
        ->capture_default_str();
    c.add_option("--time-step", o.time_step, "camera-path time between frames")
        ->capture_default_str();
    c.add_option("--param", o.params, "mode parameter key=value (repeatable)");
    add_gaze_option(c, o);
    c.add_flag("--json", o.json, "machine-readable output");
    c.add_option("--debugger", o.debugger,
                 "also print a gdb or lldb command line that renders this case and stops in "
                 "each pass's per-pixel function at this pixel (README: Debugging one pixel)")
        ->check(CLI::IsMember({"gdb", "lldb"}));
}

int run_probe(const ProbeOptions& o) {
    if (o.pixel.empty() == o.texel.empty())
        throw Error("probe: give --pixel X,Y or --texel I,J (one of them)");
    int x = -1, y = -1;
    char tail = 0;
    std::optional<glm::ivec2> texel;
    int eye = -1;
    if (!o.texel.empty()) {
        const bool with_eye = std::sscanf(o.texel.c_str(), "%d,%d,%d%c", &x, &y, &eye, &tail) == 3;
        if (!with_eye) eye = -1;
        const bool ok = with_eye ? eye == 0 || eye == 1
                                 : std::sscanf(o.texel.c_str(), "%d,%d%c", &x, &y, &tail) == 2;
        if (!ok)
            throw Error("--texel '" + o.texel +
                        "': expected I,J (e.g. 10,20), or I,J,EYE with EYE 0 or 1 (stereo-lp)");
        texel = glm::ivec2(x, y);
        if (!o.debugger.empty())
            throw Error("--texel with --debugger: stop at a pixel (--pixel) instead");
    } else if (std::sscanf(o.pixel.c_str(), "%d,%d%c", &x, &y, &tail) != 2) {
        throw Error("--pixel '" + o.pixel + "': expected X,Y (e.g. 10,20)");
    }
    const ResolvedCase c = resolve_case(o, "probe");
    Progress progress("probe " + o.mode, o.quiet);
    const ProbeReport report = probe_pixel(
        c.scene_or_null(), *c.mode, case_settings(c.run, {}, [&](double f) { progress.update(f); }),
        o.frame, x, y, texel, eye);
    progress.finish();
    std::string debug_command;
    if (!o.debugger.empty()) debug_command = debugger_line(o, c, x, y);
    if (o.json) {
        std::cout << probe_json(report, debug_command).dump(1) << "\n";
    } else {
        std::cout << probe_text(report);
        if (!debug_command.empty()) print_debugger_section(c, debug_command);
    }
    return report.consistent ? exit_ok : exit_check_failed;
}

}  // namespace fovref
