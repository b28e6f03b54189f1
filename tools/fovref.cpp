// fovref: the command-line tool of the reference renderer.
// Exit codes: 0 ok, 1 a check failed (golden verify, diff), 2 usage or input error.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"
#include "ref/stage/probe.h"
#include "ref/trace/rays_file.h"
#include "tools/bench_metrics.h"
#include "tools/bench_rays.h"
#include "tools/diff.h"
#include "tools/evaluate.h"
#include "tools/progress.h"

#ifndef FOVREF_SOURCE_DIR
#define FOVREF_SOURCE_DIR "."
#endif

namespace fs = std::filesystem;
using namespace fovref;

namespace {

constexpr int exit_ok = 0, exit_check_failed = 1, exit_usage = 2;
constexpr int golden_max_width = 320, golden_max_height = 180;

struct Options {
    bool quiet = false;
    // scene
    std::string scene;
    std::string directory;
    bool json = false;
    // render
    std::string mode = "splat";
    int width = 320, height = 180, frames = 1;
    float time_start = 0.0f, time_step = 1.0f / 30;
    std::vector<std::string> params;
    std::vector<std::string> outputs;
    std::string out_dir, dump_dir;
    // golden
    std::string golden_dir;
    std::vector<std::string> case_names;
    std::string case_name;
    std::optional<int> export_width, export_height, export_frames;
    bool export_scene_files = false;
    // rays
    std::string rays_path, hits_path;
    bool any_hit = false;
    bool make_camera = false;
    std::uint32_t random_count = 0, seed = 1;
    float time = 0.0f;
    std::string primary;
    // bench
    BenchRaysOptions bench;
    BenchMetricsOptions bench_metrics;
    // diff
    DiffOptions diff;
    // evaluate
    EvaluateOptions evaluate;
    // probe
    int probe_frame = 0;
    std::string pixel;
    std::string debugger;  ///< gdb or lldb: print a command that stops at the pixel
    int first_frame = 0;   ///< render: number of the first frame rendered
};

void say(const Options& o, const std::string& line) {
    if (!o.quiet) std::cout << line << "\n";
}

std::string vec3_text(glm::vec3 v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", static_cast<double>(v.x),
                  static_cast<double>(v.y), static_cast<double>(v.z));
    return text;
}

// ---- scene ------------------------------------------------------------------------------------

int scene_info(const Options& o) {
    const Scene scene = load_scene(o.scene);
    const Bounds bounds = scene_bounds(scene);
    int lights_by_type[3] = {0, 0, 0};
    for (const Light& light : scene.lights) ++lights_by_type[static_cast<int>(light.type)];
    if (o.json) {
        nlohmann::json j;
        j["name"] = scene.name;
        j["source"] = scene.source;
        j["triangles"] = scene.triangle_count();
        j["bounds"] = {{"min", {bounds.min.x, bounds.min.y, bounds.min.z}},
                       {"max", {bounds.max.x, bounds.max.y, bounds.max.z}}};
        j["scene_scale"] = scene.scene_scale;
        j["materials"] = nlohmann::json::array();
        for (const Material& m : scene.materials)
            j["materials"].push_back({{"name", m.name},
                                      {"albedo", {m.albedo.x, m.albedo.y, m.albedo.z}},
                                      {"texture", m.texture},
                                      {"emission", {m.emission.x, m.emission.y, m.emission.z}},
                                      {"specular", {m.specular.x, m.specular.y, m.specular.z}},
                                      {"roughness", m.roughness}});
        j["textures"] = nlohmann::json::array();
        for (const Texture& t : scene.textures)
            j["textures"].push_back(
                {{"name", t.name}, {"width", t.image.width}, {"height", t.image.height}});
        j["lights"] = {{"point", lights_by_type[0]},
                       {"quad", lights_by_type[1]},
                       {"triangle", lights_by_type[2]}};
        j["camera_path_keys"] = scene.camera_path.size();
        j["presets"] = nlohmann::json::array();
        for (const auto& [name, text] : scene.presets) j["presets"].push_back(name);
        j["dropped"] = {{"zero_area_triangles", scene.load_stats.zero_area_triangles_dropped}};
        j["repaired"] = {{"polygons_triangulated", scene.load_stats.polygons_triangulated},
                         {"normals_generated", scene.load_stats.normals_generated}};
        j["warnings"] = scene.load_stats.warnings;
        std::cout << j.dump(2) << "\n";
        return exit_ok;
    }
    std::printf("scene      %s\n", scene.name.c_str());
    std::printf("source     %s\n", scene.source.c_str());
    std::printf("triangles  %zu\n", scene.triangle_count());
    std::printf("bounds     %s .. %s (scale %.6g)\n", vec3_text(bounds.min).c_str(),
                vec3_text(bounds.max).c_str(), static_cast<double>(scene.scene_scale));
    std::printf("materials  %zu\n", scene.materials.size());
    for (std::size_t k = 0; k < scene.materials.size(); ++k) {
        const Material& m = scene.materials[k];
        std::printf(
            "  [%zu] %-20s albedo %s%s%s%s\n", k, m.name.c_str(), vec3_text(m.albedo).c_str(),
            m.texture >= 0 ? (" texture " + scene.textures[m.texture].name).c_str() : "",
            m.emission != glm::vec3(0.0f) ? (" emission " + vec3_text(m.emission)).c_str() : "",
            m.specular != glm::vec3(0.0f) ? (" specular " + vec3_text(m.specular) + " roughness " +
                                             std::to_string(m.roughness))
                                                .c_str()
                                          : "");
    }
    std::printf("textures   %zu\n", scene.textures.size());
    for (const Texture& t : scene.textures)
        std::printf("  %s %dx%d\n", t.name.c_str(), t.image.width, t.image.height);
    std::printf("lights     %zu (point %d, quad %d, emissive triangles %d)\n", scene.lights.size(),
                lights_by_type[0], lights_by_type[1], lights_by_type[2]);
    for (const Light& l : scene.lights)
        if (l.type != Light::Type::triangle)
            std::printf("  %-5s at %s intensity %s\n", light_type_name(l.type),
                        vec3_text(l.position).c_str(), vec3_text(l.intensity).c_str());
    const Camera& c = scene.camera;
    std::printf("camera     at %s forward %s vfov %.6g deg\n", vec3_text(c.position).c_str(),
                vec3_text(c.forward).c_str(), static_cast<double>(c.vfov_deg));
    if (scene.camera_path.empty())
        std::printf("path       none (static camera)\n");
    else
        std::printf("path       %zu keys, t = %.6g .. %.6g\n", scene.camera_path.size(),
                    static_cast<double>(scene.camera_path.front().time),
                    static_cast<double>(scene.camera_path.back().time));
    const char* display = scene.display.kind == DisplayModel::Kind::field_of_view ? "field of view"
                          : scene.display.kind == DisplayModel::Kind::diagonal    ? "diagonal"
                                                                               : "fixed distance";
    std::printf("display    %s\n", display);
    std::string presets;
    for (const auto& [name, text] : scene.presets) presets += (presets.empty() ? "" : ", ") + name;
    std::printf("presets    %s\n", presets.empty() ? "none" : presets.c_str());
    std::printf("dropped    %lld zero-area triangles\n",
                static_cast<long long>(scene.load_stats.zero_area_triangles_dropped));
    std::printf("repaired   %lld polygons triangulated, %lld triangles without normals\n",
                static_cast<long long>(scene.load_stats.polygons_triangulated),
                static_cast<long long>(scene.load_stats.normals_generated));
    for (const std::string& w : scene.load_stats.warnings)
        std::printf("warning    %s\n", w.c_str());
    return exit_ok;
}

int scene_export(const Options& o) {
    const Scene scene = load_scene(o.scene);
    export_scene(scene, o.directory);
    say(o, "exported " + scene.name + " (" + std::to_string(scene.triangle_count()) +
               " triangles) to " + o.directory + "/scene.json");
    return exit_ok;
}

int scene_list(const Options&) {
    for (const ProceduralSceneInfo& info : procedural_scenes())
        std::printf("%-14s %s\n", info.name.c_str(), info.description.c_str());
    return exit_ok;
}

// ---- render -----------------------------------------------------------------------------------

int modes_list(const Options&) {
    for (const ModeInfo& mode : render_modes()) {
        std::printf("%-12s %s%s\n", mode.name.c_str(), mode.description.c_str(),
                    mode.needs_scene ? "" : " (no scene needed)");
        for (const ParamSpec& p : mode.params)
            std::printf("    --param %s=<%s>  %s\n", p.name.c_str(), p.default_value.c_str(),
                        p.doc.c_str());
    }
    return exit_ok;
}

// The case a render-like command (render, probe) describes with its options.
GoldenCase command_case(const Options& o, const std::string& name) {
    GoldenCase run;
    run.name = name;
    run.scene = o.scene;
    run.mode = o.mode;
    run.width = o.width;
    run.height = o.height;
    run.frames = o.frames;
    run.time_start = o.time_start;
    run.time_step = o.time_step;
    for (const std::string& p : o.params) run.params.set_from_assignment(p);
    if (!o.primary.empty()) run.params.set("primary", o.primary);
    return run;
}

std::optional<Scene> command_scene(const Options& o, const std::string& command) {
    if (!find_mode(o.mode).needs_scene) return std::nullopt;
    if (o.scene.empty()) throw Error(command + ": mode '" + o.mode + "' needs --scene");
    return load_scene(o.scene);
}

// The debugger command of `probe --debugger`: `fovref render` of the same case under gdb/lldb,
// with a conditional breakpoint on the pixel in each per-pixel function of the mode's passes. A
// stateless mode renders only the probed frame (--first-frame), so each breakpoint stops once
// per call at that pixel in that frame.
std::string debugger_line(const Options& o, int x, int y) {
    const ModeInfo& mode = find_mode(o.mode);
    if (!mode.pixel_functions)
        throw Error("--debugger: mode '" + o.mode +
                    "' names no per-pixel functions to stop in (basic and ground-truth do)");
    const GoldenCase run = command_case(o, "probe");
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
    if (mode.stateless)
        args.insert(args.end(), {"--first-frame", std::to_string(o.probe_frame), "--frames", "1"});
    else
        args.insert(args.end(), {"--frames", std::to_string(o.probe_frame + 1)});
    for (const auto& [key, value] : run.params.values())
        args.insert(args.end(), {"--param", key + "=" + value});
    args.insert(args.end(), {"--out", "/tmp/fovref-debug", "-q"});
    return debugger_command(o.debugger, program, args, mode.pixel_functions(run.params), x, y);
}

int probe_command(const Options& o) {
    int x = -1, y = -1;
    char tail = 0;
    if (std::sscanf(o.pixel.c_str(), "%d,%d%c", &x, &y, &tail) != 2)
        throw Error("--pixel '" + o.pixel + "': expected X,Y (e.g. 10,20)");
    const std::optional<Scene> scene = command_scene(o, "probe");
    const GoldenCase run = command_case(o, "probe");
    Progress progress("probe " + o.mode, o.quiet);
    const ProbeReport report = probe_pixel(
        scene ? &*scene : nullptr, o.mode,
        case_settings(run, {}, [&](double f) { progress.update(f); }), o.probe_frame, x, y);
    progress.finish();
    std::string debug_command;
    if (!o.debugger.empty()) debug_command = debugger_line(o, x, y);
    if (o.json) {
        nlohmann::json j;
        if (!debug_command.empty()) j["debugger_command"] = debug_command;
        j["mode"] = report.mode;
        j["frame"] = report.frame;
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
        std::cout << j.dump(1) << "\n";
    } else {
        std::cout << probe_text(report);
        if (!debug_command.empty()) {
            std::cout << "\n[debugger] stop at this pixel in each pass's per-pixel function\n";
            for (const PixelFunction& f : find_mode(o.mode).pixel_functions(run.params))
                std::cout << "  " << f.stage << ": " << f.function
                          << (f.note.empty() ? "" : " (" + f.note + ")") << "\n";
#if !FOVREF_DEBUGGABLE
            std::cout << "  this fovref has no debug info: build the debug preset first\n"
                         "  (cmake --preset debug && cmake --build --preset debug)\n";
#endif
            std::cout << "debug it: " << debug_command << "\n";
        }
    }
    return report.consistent ? exit_ok : exit_check_failed;
}

int render_command(const Options& o) {
    if (o.out_dir.empty() && o.dump_dir.empty())
        throw Error("render: give --out DIR and/or --dump DIR");
    const std::optional<Scene> scene = command_scene(o, "render");
    const GoldenCase run = command_case(o, "render");
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
    if (o.export_scene_files) {
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
        std::string line = "frame " + std::to_string(f.frame) + ":";
        for (const StageRun& stage : f.stages)
            line += " " + stage.name + (stage.ran ? "" : " (skipped)");
        for (const auto& [k, v] : f.counters.values) line += ", " + k + " " + std::to_string(v);
        lines.push_back(line);
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
    for (const std::string& line : lines) say(o, line);
    if (dump)
        say(o, "dumped every buffer of " + std::to_string(o.frames) + " frame(s) to " + o.dump_dir);
    if (out) say(o, "wrote " + std::to_string(o.frames) + " frame(s) to " + o.out_dir);
    return exit_ok;
}

// ---- rays -------------------------------------------------------------------------------------

int rays_trace(const Options& o) {
    const Scene scene = load_scene(o.scene);
    const std::vector<Ray> rays = read_rays(o.rays_path);
    Progress progress("rays trace", o.quiet);
    const Bvh bvh = build_bvh(scene.positions);
    TraceStats stats;
    const std::size_t step = std::max<std::size_t>(1, rays.size() / 100);
    if (o.any_hit) {
        std::vector<std::uint32_t> occluded(rays.size());
        for (std::size_t k = 0; k < rays.size(); ++k) {
            occluded[k] = trace_any(bvh, rays[k], stats) ? 1u : 0u;
            if (k % step == 0)
                progress.update(static_cast<double>(k) / static_cast<double>(rays.size()));
        }
        progress.finish();
        write_occlusion(o.hits_path, occluded);
    } else {
        std::vector<Hit> hits(rays.size());
        for (std::size_t k = 0; k < rays.size(); ++k) {
            hits[k] = trace_closest(bvh, rays[k], stats);
            if (k % step == 0)
                progress.update(static_cast<double>(k) / static_cast<double>(rays.size()));
        }
        progress.finish();
        write_hits(o.hits_path, hits);
    }
    say(o, "traced " + std::to_string(rays.size()) + (o.any_hit ? " occlusion" : " closest-hit") +
               " rays: " + std::to_string(stats.hits) + " hit, " +
               std::to_string(stats.nodes_visited) + " nodes visited, " +
               std::to_string(stats.triangles_tested) + " triangles tested -> " + o.hits_path);
    return exit_ok;
}

int rays_make(const Options& o) {
    const Scene scene = load_scene(o.scene);
    std::vector<Ray> rays;
    if (o.make_camera == (o.random_count > 0))
        throw Error(
            "rays make: give exactly one of --camera (with --width/--height) or --random N");
    if (o.make_camera) {
        RenderSettings check;
        check.width = o.width;
        check.height = o.height;
        validate_settings(check);
        rays = camera_rays_list(camera_at(scene, o.time), o.width, o.height);
    } else {
        rays = random_rays(scene, o.random_count, o.seed);
    }
    write_rays(o.rays_path, rays);
    say(o, "wrote " + std::to_string(rays.size()) + " rays to " + o.rays_path);
    return exit_ok;
}

// ---- golden -----------------------------------------------------------------------------------

// The golden directory as an absolute, normalised path without a trailing separator; its parent
// is the repository root that relative scene paths in cases.json are resolved against.
std::string golden_directory(const Options& o) {
    fs::path dir = !o.golden_dir.empty()             ? fs::path(o.golden_dir)
                   : fs::exists("golden/cases.json") ? fs::path("golden")
                                                     : fs::path(FOVREF_SOURCE_DIR) / "golden";
    dir = fs::absolute(dir).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();
    return dir.string();
}

std::string repository_root(const std::string& golden_dir) {
    return fs::path(golden_dir).parent_path().string();
}

std::vector<GoldenCase> selected_cases(const Options& o, const std::vector<GoldenCase>& all) {
    if (o.case_names.empty()) return all;
    std::vector<GoldenCase> chosen;
    for (const std::string& name : o.case_names) chosen.push_back(find_golden_case(all, name));
    return chosen;
}

int golden_list(const Options& o) {
    const std::string dir = golden_directory(o);
    for (const GoldenCase& c : load_golden_cases(dir + "/cases.json"))
        std::printf("%-28s %-12s %-14s %dx%d x%d  %s\n", c.name.c_str(), c.mode.c_str(),
                    c.scene.empty() ? "-" : c.scene.c_str(), c.width, c.height, c.frames,
                    c.description.c_str());
    return exit_ok;
}

int golden_verify(const Options& o) {
    const std::string dir = golden_directory(o);
    const std::vector<GoldenCase> cases = selected_cases(o, load_golden_cases(dir + "/cases.json"));
    SceneCache scenes(repository_root(dir));
    int failed = 0;
    Progress progress("golden verify", o.quiet);
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const GoldenCase& c = cases[k];
        const std::string bundle = dir + "/" + c.name;
        std::vector<std::string> report;  // printed after the progress line is cleared
        try {
            if (!fs::exists(bundle + "/manifest.json")) {
                report.push_back("FAIL " + c.name + ": no bundle at " + bundle +
                                 " (run `fovref golden update --case " + c.name + "`)");
            } else {
                const Manifest manifest = read_manifest(bundle);
                if (!(manifest.golden_case == c)) {
                    report.push_back(
                        "FAIL " + c.name +
                        ": the bundle was made for a different case definition (run `fovref golden "
                        "update --case " +
                        c.name + "`)");
                } else {
                    const std::vector<FrameResult> frames =
                        render_golden_case(c, scenes.get(c.scene), {"all"});
                    const std::vector<GoldenDifference> differences =
                        compare_with_bundle(bundle, manifest, frames);
                    std::size_t buffers = 0;
                    for (const FrameResult& f : frames) buffers += f.buffers.size();
                    if (differences.empty()) {
                        char line[160];
                        std::snprintf(line, sizeof line, "ok   %-28s %zu buffers, %d frame(s)",
                                      c.name.c_str(), buffers, c.frames);
                        if (!o.quiet) report.push_back(line);
                    } else {
                        report.push_back("FAIL " + c.name + ": " +
                                         std::to_string(differences.size()) +
                                         " difference(s); first in pipeline order:");
                        for (const GoldenDifference& d : differences)
                            report.push_back("     frame " + std::to_string(d.frame) + ", buffer " +
                                             d.buffer + ": " + d.what);
                    }
                }
            }
        } catch (const Error& e) {
            report.push_back("FAIL " + c.name + ": " + e.what());
        }
        if (!report.empty() && report.front().rfind("FAIL", 0) == 0) ++failed;
        progress.clear();
        for (const std::string& line : report) std::printf("%s\n", line.c_str());
        std::fflush(stdout);
        progress.update(static_cast<double>(k + 1) / static_cast<double>(cases.size()));
    }
    progress.finish();
    std::printf("golden verify: %zu cases, %d failed (%s, %s)\n", cases.size(), failed,
                fovref_compiler().c_str(), fovref_build_flags().c_str());
    return failed ? exit_check_failed : exit_ok;
}

int golden_update(const Options& o) {
    const std::string dir = golden_directory(o);
    const std::vector<GoldenCase> all = load_golden_cases(dir + "/cases.json");
    const std::vector<GoldenCase> cases = selected_cases(o, all);
    SceneCache scenes(repository_root(dir));
    BundleOptions options;
    options.max_stored_pixels = static_cast<std::size_t>(golden_max_width) * golden_max_height;
    for (const GoldenCase& c : cases) {
        if (c.width > golden_max_width || c.height > golden_max_height)
            throw Error("golden case '" + c.name + "': " + std::to_string(c.width) + "x" +
                        std::to_string(c.height) +
                        " exceeds the repository limit of 320x180 (use "
                        "`fovref golden export --width --height` for larger bundles)");
        const std::string bundle = dir + "/" + c.name;
        const std::vector<FrameResult> frames = render_golden_case(c, scenes.get(c.scene), {"all"});
        std::string status = "new";
        if (fs::exists(bundle + "/manifest.json")) {
            const Manifest old = read_manifest(bundle);
            const std::vector<GoldenDifference> differences =
                old.golden_case == c ? compare_with_bundle(bundle, old, frames)
                                     : std::vector<GoldenDifference>{};
            status = !(old.golden_case == c) ? "case definition changed"
                     : differences.empty()
                         ? "unchanged"
                         : std::to_string(differences.size()) + " buffer(s) changed";
            for (const GoldenDifference& d : differences)
                say(o, "  " + c.name + " frame " + std::to_string(d.frame) + " " + d.buffer + ": " +
                           d.what);
        }
        write_bundle(bundle, c, frames, options);
        say(o, "updated " + c.name + ": " + status);
    }
    // Bundles whose case is gone from cases.json are stale (removed in name order).
    if (o.case_names.empty()) {
        std::vector<std::string> stale;
        for (const auto& entry : fs::directory_iterator(dir)) {
            if (!entry.is_directory() || !fs::exists(entry.path() / "manifest.json")) continue;
            const std::string name = entry.path().filename().string();
            bool known = false;
            for (const GoldenCase& c : all) known = known || c.name == name;
            if (!known) stale.push_back(name);
        }
        std::sort(stale.begin(), stale.end());
        for (const std::string& name : stale) {
            fs::remove_all(fs::path(dir) / name);
            say(o, "removed " + name + ": no longer in cases.json");
        }
    }
    return exit_ok;
}

int golden_export(const Options& o) {
    const std::string dir = golden_directory(o);
    GoldenCase c = find_golden_case(load_golden_cases(dir + "/cases.json"), o.case_name);
    if (o.export_width) c.width = *o.export_width;
    if (o.export_height) c.height = *o.export_height;
    if (o.export_frames) c.frames = *o.export_frames;
    for (const std::string& assignment : o.params) c.params.set_from_assignment(assignment);
    SceneCache scenes(repository_root(dir));
    const Scene* scene = scenes.get(c.scene);
    if (o.export_scene_files && !scene)
        throw Error("--with-scene: case '" + c.name + "' has no scene");
    BundleOptions options;
    options.previews_for_all = true;
    BundleWriter writer(o.directory, c, options);
    if (o.export_scene_files) writer.add_scene(*scene, "scene");
    Progress progress("golden export " + c.name, o.quiet);
    render_each(scene, c.mode, case_settings(c, {"all"}, [&](double f) { progress.update(f); }),
                [&](FrameResult& frame) { writer.add_frame(frame); });
    progress.finish();
    writer.commit();
    say(o, "exported " + c.name + " at " + std::to_string(c.width) + "x" +
               std::to_string(c.height) + ", " + std::to_string(c.frames) + " frame(s), to " +
               o.directory);
    return exit_ok;
}

}  // namespace

int main(int argc, char** argv) {
    Options o;
    CLI::App app{
        "fovref: deterministic reference renderer for foveated ray and path tracing.\n"
        "Exit codes: 0 ok, 1 a check failed, 2 usage or input error.\n"
        "Input limits (file size, image pixels, rays; raise them with FOVREF_MAX_* environment "
        "variables): docs/limits.md."};
    app.set_version_flag("--version", "fovref " + fovref_version());
    app.add_flag("-q,--quiet", o.quiet, "print only errors and failures, no progress bar");
    app.require_subcommand(1);
    app.fallthrough();  // global options (--quiet) may follow a subcommand
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("fovref: ") + e.what() + " (see --help)\n";
    });
    app.footer(
        "Commands:\n"
        "  fovref scene list                      the procedural scenes\n"
        "  fovref scene info SCENE [--json]       counts, bounds, materials, lights, camera, "
        "drops\n"
        "  fovref scene export SCENE DIR          OBJ + MTL + textures + scene.json\n"
        "  fovref modes                           render modes and their parameters\n"
        "  fovref render --scene S --mode M --width W --height H [--frames N] [--param k=v]\n"
        "                [--output a,b] [--out DIR] [--dump DIR]\n"
        "  fovref rays make SCENE RAYS (--camera --width W --height H | --random N [--seed S])\n"
        "  fovref rays trace SCENE RAYS HITS [--any-hit]   closest hits / occlusion of a ray file\n"
        "  fovref bench rays [--scene S] [--width W --height H]   BVH and ray throughput (vs "
        "Embree)\n"
        "  fovref bench metrics [--size WxH]      metric times (vs scikit-image's SSIM)\n"
        "  fovref golden list                     the golden cases (golden/cases.json)\n"
        "  fovref golden verify [--case C]        recompute, compare bit-exactly, exit 1 on a "
        "difference\n"
        "  fovref golden update [--case C]        recompute and rewrite, saying what changed\n"
        "  fovref golden export CASE DIR [--width W --height H --frames N] [--param k=v]\n"
        "                [--with-scene]             a full bundle (and the scene) for a GPU\n"
        "  fovref probe --scene S --mode M --width W --height H --frame F --pixel X,Y\n"
        "                                         explain one pixel stage by stage\n"
        "  fovref evaluate --scene S --mode M[,M2] [--frames N --every K] --out DIR\n"
        "                                         ring errors against the ground truth\n"
        "  fovref diff GOLDEN CANDIDATE [--tolerance N:abs=X] [--json F] [--html DIR]\n"
        "                                         compare a GPU's buffers with a golden bundle\n"
        "SCENE is a procedural scene name (see `scene list`) or a scene file or directory.\n"
        "Run `fovref COMMAND --help` for each command's options.");

    // scene
    CLI::App* scene = app.add_subcommand("scene", "inspect, list and export scenes");
    scene->require_subcommand(1);
    scene->fallthrough();
    CLI::App* scene_info_cmd = scene->add_subcommand(
        "info",
        "triangles, lights, bounds, materials, camera, and what the loader dropped or repaired");
    scene_info_cmd->add_option("SCENE", o.scene, "procedural scene name or scene file/directory")
        ->required();
    scene_info_cmd->add_flag("--json", o.json, "machine-readable output");
    CLI::App* scene_export_cmd = scene->add_subcommand(
        "export", "write any scene (procedural ones too) as OBJ + MTL + textures + scene.json");
    scene_export_cmd->add_option("SCENE", o.scene, "procedural scene name or scene file")
        ->required();
    scene_export_cmd->add_option("DIR", o.directory, "output directory (created)")->required();
    CLI::App* scene_list_cmd = scene->add_subcommand("list", "the procedural scenes");

    // render
    CLI::App* render_cmd =
        app.add_subcommand("render", "render frames of a mode and write its buffers");
    render_cmd->add_option("--scene", o.scene, "procedural scene name or scene file");
    render_cmd->add_option("--mode", o.mode, "render mode (see `fovref modes`)")
        ->capture_default_str();
    render_cmd->add_option("--width", o.width, "screen width in pixels")->capture_default_str();
    render_cmd->add_option("--height", o.height, "screen height in pixels")->capture_default_str();
    render_cmd->add_option("--frames", o.frames, "number of frames")->capture_default_str();
    render_cmd
        ->add_option("--first-frame", o.first_frame,
                     "number of the first frame (seeds rand() and sets the camera-path time): "
                     "render frame F of a sequence alone, bit-identical to the sequence's")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    render_cmd->add_option("--time-start", o.time_start, "camera-path time of frame 0")
        ->capture_default_str();
    render_cmd->add_option("--time-step", o.time_step, "camera-path time between frames")
        ->capture_default_str();
    render_cmd->add_option("--param", o.params, "mode parameter key=value (repeatable)");
    render_cmd
        ->add_option("--primary", o.primary,
                     "primary visibility for 'basic': ray or raster (= --param primary=...)")
        ->check(CLI::IsMember({"ray", "raster"}));
    render_cmd
        ->add_option("--output", o.outputs,
                     "buffers to produce (default: the mode's final outputs)")
        ->delimiter(',');
    render_cmd->add_option("--out", o.out_dir,
                           "write the final buffers (PFM/EXR + PNG + manifest.json) here");
    render_cmd->add_option(
        "--dump", o.dump_dir,
        "write every intermediate buffer (PFM/EXR + PNG preview + manifest.json) here");
    render_cmd->add_flag("--with-scene", o.export_scene_files,
                         "also write the scene into DIR/scene of --out and --dump (OBJ + MTL + "
                         "textures + scene.json; OBJ triangle k is primitive id k)");
    CLI::App* modes_cmd = app.add_subcommand("modes", "list render modes and their parameters");

    // rays
    CLI::App* rays =
        app.add_subcommand("rays", "trace ray files (check a GPU traversal) and make them");
    rays->require_subcommand(1);
    rays->fallthrough();
    CLI::App* rays_trace_cmd =
        rays->add_subcommand("trace",
                             "closest hits (t, primitive, u, v; miss = -1) or, with --any-hit, "
                             "occlusion of every ray in RAYS");
    rays_trace_cmd->add_option("SCENE", o.scene, "procedural scene name or scene file")->required();
    rays_trace_cmd->add_option("RAYS", o.rays_path, "ray file: 8 x binary32 per ray (docs/rays.md)")
        ->required();
    rays_trace_cmd
        ->add_option("HITS", o.hits_path, "output: 16-byte hit records, or 4-byte occlusion flags")
        ->required();
    rays_trace_cmd->add_flag("--any-hit", o.any_hit,
                             "occlusion queries (shadow rays) instead of closest hits");
    CLI::App* rays_make_cmd =
        rays->add_subcommand("make", "write a camera's primary rays or fixed-seed random rays");
    rays_make_cmd->add_option("SCENE", o.scene, "procedural scene name or scene file")->required();
    rays_make_cmd->add_option("RAYS", o.rays_path, "output ray file")->required();
    rays_make_cmd->add_flag("--camera", o.make_camera, "primary rays through every pixel centre");
    rays_make_cmd->add_option("--width", o.width, "with --camera")->capture_default_str();
    rays_make_cmd->add_option("--height", o.height, "with --camera")->capture_default_str();
    rays_make_cmd->add_option("--time", o.time, "camera-path time, with --camera")
        ->capture_default_str();
    rays_make_cmd
        ->add_option("--random", o.random_count,
                     "N random rays: origins in the scene bounds, uniform "
                     "directions")
        ->check(CLI::Range(1u, 100000000u));
    rays_make_cmd->add_option("--seed", o.seed, "seed of the random rays (the rand() frame)")
        ->capture_default_str();

    // bench
    CLI::App* bench = app.add_subcommand("bench", "benchmarks (figures, not tests)");
    bench->require_subcommand(1);
    bench->fallthrough();
    CLI::App* bench_rays_cmd =
        bench->add_subcommand("rays",
                              "BVH build, Mrays/s for primary, incoherent and shadow rays, "
                              "G-buffer pass times; with Embree "
                              "installed, the same rays through Embree in the same run");
    bench_rays_cmd->add_option("--scene", o.bench.scenes,
                               "procedural scene (repeatable; default: all)");
    bench_rays_cmd->add_option("--width", o.bench.width, "primary rays: screen width")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    bench_rays_cmd->add_option("--height", o.bench.height, "primary rays: screen height")
        ->check(CLI::Range(1, 16384))
        ->capture_default_str();
    bench_rays_cmd->add_option("--repeats", o.bench.repeats, "each timing is the fastest of N runs")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    bench_rays_cmd
        ->add_option("--explain", o.bench.explain,
                     "list up to N hit/miss disagreements with Embree per row: the ray, both "
                     "answers, the brute force's, the distance to an edge")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();

    CLI::App* bench_metrics_cmd = bench->add_subcommand(
        "metrics",
        "time of each metric at 1280x720 and 3840x2160; with python3-skimage installed, "
        "scikit-image's SSIM on the same images in the same run");
    bench_metrics_cmd->add_option("--size", o.bench_metrics.sizes, "WxH (repeatable)")
        ->capture_default_str();
    bench_metrics_cmd->add_option("--repeats", o.bench_metrics.repeats, "fastest of N runs")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();

    // golden
    CLI::App* golden =
        app.add_subcommand("golden", "verify, update, list and export golden bundles");
    golden->require_subcommand(1);
    golden->fallthrough();
    golden->add_option("--dir", o.golden_dir,
                       "golden directory (default: ./golden, else the source tree's)");
    CLI::App* verify_cmd = golden->add_subcommand("verify",
                                                  "recompute every golden and compare bit-exactly; "
                                                  "names the first differing buffer and pixel");
    verify_cmd->add_option("--case", o.case_names, "only these cases");
    CLI::App* update_cmd =
        golden->add_subcommand("update", "recompute and rewrite goldens, saying what changed");
    update_cmd->add_option("--case", o.case_names, "only these cases");
    CLI::App* list_cmd = golden->add_subcommand("list", "the golden cases");
    CLI::App* export_cmd = golden->add_subcommand(
        "export", "write a full bundle (every buffer of every frame) of a case at any size");
    export_cmd->add_option("CASE", o.case_name, "golden case name (see `fovref golden list`)")
        ->required();
    export_cmd->add_option("DIR", o.directory, "output directory")->required();
    export_cmd->add_option("--width", o.export_width, "override the case's width")
        ->check(CLI::Range(1, 16384));
    export_cmd->add_option("--height", o.export_height, "override the case's height")
        ->check(CLI::Range(1, 16384));
    export_cmd->add_option("--frames", o.export_frames, "override the case's frame count")
        ->check(CLI::Range(1, 16384));
    export_cmd->add_option("--param", o.params,
                           "override or add a mode parameter of the case, key=value (repeatable; "
                           "e.g. fill_rule=gl)");
    export_cmd->add_flag("--with-scene", o.export_scene_files,
                         "also write the scene into DIR/scene (OBJ + MTL + textures + scene.json; "
                         "OBJ triangle k is primitive id k), for a GPU implementation to render");

    // probe
    CLI::App* probe_cmd = app.add_subcommand(
        "probe",
        "explain one screen pixel of a mode and frame stage by stage: buffer coordinates, ray, "
        "hit, texels and weights, shading inputs, light samples, every buffer's value; exit 1 "
        "if the recomputation differs from the rendered buffer");
    probe_cmd->add_option("--scene", o.scene, "procedural scene name or scene file");
    probe_cmd->add_option("--mode", o.mode, "render mode (see `fovref modes`)")->required();
    probe_cmd->add_option("--width", o.width, "screen width in pixels")->capture_default_str();
    probe_cmd->add_option("--height", o.height, "screen height in pixels")->capture_default_str();
    probe_cmd->add_option("--frame", o.probe_frame, "frame number (frames before it run too)")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    probe_cmd->add_option("--pixel", o.pixel, "X,Y of the screen pixel")->required();
    probe_cmd->add_option("--time-start", o.time_start, "camera-path time of frame 0")
        ->capture_default_str();
    probe_cmd->add_option("--time-step", o.time_step, "camera-path time between frames")
        ->capture_default_str();
    probe_cmd->add_option("--param", o.params, "mode parameter key=value (repeatable)");
    probe_cmd->add_flag("--json", o.json, "machine-readable output");
    probe_cmd
        ->add_option("--debugger", o.debugger,
                     "also print a gdb or lldb command line that renders this case and stops in "
                     "each pass's per-pixel function at this pixel (README: Debugging one pixel)")
        ->check(CLI::IsMember({"gdb", "lldb"}));

    // evaluate
    CLI::App* evaluate_cmd = app.add_subcommand(
        "evaluate",
        "render modes (or read rendered frames) along the camera path and compute error ranges "
        "against the ground truth every k-th frame: CSV, JSON, SVG plot, heatmaps");
    add_evaluate_options(*evaluate_cmd, o.evaluate);

    // diff
    CLI::App* diff_cmd = app.add_subcommand(
        "diff",
        "compare a candidate (a GPU implementation's buffers or one image) with a golden bundle "
        "or image: per-buffer errors, worst pixels, error ranges, pass/fail by tolerance; exit 0 "
        "pass, 1 out of tolerance, 2 usage or input error");
    add_diff_options(*diff_cmd, o.diff);

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? exit_ok : exit_usage;
    }
    try {
        if (scene_info_cmd->parsed()) return scene_info(o);
        if (scene_export_cmd->parsed()) return scene_export(o);
        if (scene_list_cmd->parsed()) return scene_list(o);
        if (render_cmd->parsed()) return render_command(o);
        if (modes_cmd->parsed()) return modes_list(o);
        if (rays_trace_cmd->parsed()) return rays_trace(o);
        if (bench_rays_cmd->parsed()) {
            BenchRaysOptions options = o.bench;
            options.quiet = o.quiet;
            return run_bench_rays(options);
        }
        if (bench_metrics_cmd->parsed()) return run_bench_metrics(o.bench_metrics);
        if (rays_make_cmd->parsed()) return rays_make(o);
        if (verify_cmd->parsed()) return golden_verify(o);
        if (update_cmd->parsed()) return golden_update(o);
        if (list_cmd->parsed()) return golden_list(o);
        if (export_cmd->parsed()) return golden_export(o);
        if (probe_cmd->parsed()) return probe_command(o);
        if (evaluate_cmd->parsed()) {
            EvaluateOptions options = o.evaluate;
            options.quiet = o.quiet;
            return run_evaluate(options);
        }
        if (diff_cmd->parsed()) {
            DiffOptions options = o.diff;
            options.quiet = o.quiet;
            return run_diff(options);
        }
    } catch (const Error& e) {
        std::fprintf(stderr, "fovref: %s\n", e.what());
        return exit_usage;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fovref: unexpected error: %s\n", e.what());
        return exit_usage;
    }
    return exit_usage;
}
