#include "tools/cli/commands/probe.h"

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <vector>

#include "ref/core/error.h"
#include "ref/modes/modes.h"
#include "ref/stage/debugger.h"
#include "ref/stage/probe.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

#ifndef FOVREF_SOURCE_DIR
#define FOVREF_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;

namespace fovref {

namespace {

// What `probe --debugger` stops at: the pixel and the texels pass 2 reads for it, or the probed
// texel (stereo: its column in both eyes' buffer, report.buffer_texel).
DebugTarget debug_target(const ResolvedCase& c, const ProbeReport& report,
                         const RenderSettings& settings) {
    const ModeInfo& mode = *c.mode;
    DebugTarget target;
    target.frame = report.frame;
    target.eye_width = settings.width / 2;
    if (report.texel) {
        std::string family;
        for (const BufferFamily& f : mode.buffer_families)
            if (family.empty() &&
                (f.space == BufferSpace::texel || f.space == BufferSpace::stereo_texel))
                family = f.prefix;
        target.texels = {{family, report.buffer_texel.value_or(*report.texel)}};
        return target;
    }
    target.pixel = glm::ivec2(report.x, report.y);
    if (mode.pixel_texels && c.scene)
        target.texels = mode.pixel_texels(*c.scene, settings, report.frame, report.x, report.y);
    // The screen points of the target that no triangle covers (the rasterized G-buffer's -1)
    const Buffer* primitive =
        report.rendered ? report.rendered->find("gbuffer_primitive_id") : nullptr;
    if (primitive) {
        std::vector<glm::ivec2> points = {*target.pixel};
        for (const TexelRead& read : target.texels)
            if (read.family == "gbuffer_") points.push_back(read.texel);
        for (const glm::ivec2& p : points)
            if (p.x >= 0 && p.y >= 0 && p.x < primitive->image.width &&
                p.y < primitive->image.height && primitive->image.at(p.x, p.y) == -1.0f)
                target.background.push_back(p);
    }
    return target;
}

// `probe --debugger`: the breakpoints, and `fovref render` of the same case under gdb/lldb. A
// stateless mode renders only the probed frame (--first-frame); with TAA or BMFR (state carried
// from frame to frame) frames 0 .. F run, and every breakpoint's condition names the frame.
struct DebugPlan {
    std::vector<Breakpoint> breakpoints;
    std::string command;
};

DebugPlan debug_plan(const ProbeOptions& o, const ResolvedCase& c, const ProbeReport& report) {
    const ModeInfo& mode = *c.mode;
    const GoldenCase& run = c.run;
    if (!mode.pixel_functions)
        throw Error("--debugger: mode '" + o.mode +
                    "' names no per-pixel functions to stop in (`fovref modes` lists the modes)");
    const RenderSettings settings = case_settings(run, {});
    DebugPlan plan;
    plan.breakpoints = debugger_breakpoints(mode.pixel_functions(run.params),
                                            mode.build(c.scene_or_null(), settings), settings,
                                            debug_target(c, report, settings));
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
    if (!carries_state(mode, run.params))
        args.insert(args.end(), {"--first-frame", std::to_string(o.frame), "--frames", "1"});
    else
        args.insert(args.end(), {"--frames", std::to_string(o.frame + 1)});
    for (const auto& [key, value] : run.params.values())
        args.insert(args.end(), {"--param", key + "=" + value});
    // --scalar: the per-pixel functions run at every pixel (no SIMD path covers any)
    args.insert(args.end(), {"--out", "/tmp/fovref-debug", "--scalar", "-q"});
    plan.command = debugger_command(o.debugger, program, args, plan.breakpoints);
    return plan;
}

nlohmann::json probe_json(const ProbeReport& report, const DebugPlan& debug) {
    nlohmann::json j;
    if (!debug.command.empty()) {
        j["debugger_command"] = debug.command;
        for (const Breakpoint& b : debug.breakpoints) {
            nlohmann::json points = nlohmann::json::array();
            for (const glm::ivec2& p : b.points) points.push_back({p.x, p.y});
            j["breakpoints"].push_back({{"stage", b.function.stage},
                                        {"stage_index", b.stage},
                                        {"function", b.function.function},
                                        {"condition", b.condition},
                                        {"parameters", {b.x_name, b.y_name}},
                                        {"points", points},
                                        {"eye", b.eye},
                                        {"coordinates", b.coordinates},
                                        {"skipped", b.skipped}});
        }
    }
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

// The [debugger] section of the text report: where each function stops, and the command.
void print_debugger_section(const DebugPlan& debug) {
    std::cout << "\n[debugger] stop where this is computed, in each pass's per-pixel function\n";
    for (const Breakpoint& b : debug.breakpoints) {
        std::cout << "  " << b.function.stage << ": " << b.function.function;
        if (!b.condition.empty())
            std::cout << " at " << b.coordinates;
        else
            std::cout << ": no stop (" << b.skipped << ")";
        std::cout << (b.function.note.empty() ? "" : "; " + b.function.note) << "\n";
    }
    std::cout << "  every stop is in the probed frame (fovref::debugger_position.frame) and in its "
                 "stage (.stage)\n";
#if !FOVREF_DEBUGGABLE
    std::cout << "  this fovref has no debug info: build the debug preset first\n"
                 "  (cmake --preset debug && cmake --build --preset debug)\n";
#endif
    std::cout << "debug it: " << debug.command << "\n";
}

}  // namespace

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
    } else if (std::sscanf(o.pixel.c_str(), "%d,%d%c", &x, &y, &tail) != 2) {
        throw Error("--pixel '" + o.pixel + "': expected X,Y (e.g. 10,20)");
    }
    const ResolvedCase c = resolve_case(o, "probe");
    Progress progress("probe " + o.mode, o.quiet);
    const ProbeReport report = probe_pixel(
        c.scene_or_null(), *c.mode, case_settings(c.run, {}, [&](double f) { progress.update(f); }),
        o.frame, x, y, texel, eye);
    progress.finish();
    DebugPlan debug;
    if (!o.debugger.empty()) debug = debug_plan(o, c, report);
    if (o.json) {
        std::cout << probe_json(report, debug).dump(1) << "\n";
    } else {
        std::cout << probe_text(report);
        if (!debug.command.empty()) print_debugger_section(debug);
    }
    return report.consistent ? exit_ok : exit_check_failed;
}

}  // namespace fovref
