#include "tools/cli/common/cli_common.h"
#include <charconv>
#include <cmath>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "ref/core/error.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"

#ifndef FOVREF_SOURCE_DIR
#define FOVREF_SOURCE_DIR "."
#endif
#ifndef FOVREF_DATA_FROM_BIN
#define FOVREF_DATA_FROM_BIN "../share/fovref"
#endif

namespace fovref {

void say(bool quiet, const std::string& line) {
    if (!quiet) std::cout << line << "\n";
}

GoldenCase command_case(const CaseOptions& o, const std::string& name) {
    GoldenCase run;
    run.name = name;
    run.scene = o.scene;
    run.mode = o.mode;
    run.width = o.width;
    run.height = o.height;
    run.frames = 1;
    run.time_start = o.time_start;
    run.time_step = o.time_step;
    run.params = Params::from_assignments(o.params);
    if (!o.gaze.empty()) {
        if (run.params.given("gaze"))
            throw Error(name + ": --gaze and --param gaze=... both given; give one");
        run.params.set("gaze", o.gaze);
    }
    return run;
}

void add_gaze_option(CLI::App& c, CaseOptions& o) {
    c.add_option("--gaze", o.gaze,
                 "gaze point X,Y in screen pixels for the foveated modes (any finite point, off "
                 "screen too; default the screen centre) (= --param gaze=X,Y)");
}

namespace {

std::optional<Scene> scene_of(const CaseOptions& o, const ModeInfo& mode,
                              const std::string& command) {
    if (!mode.needs_scene) return std::nullopt;
    if (o.scene.empty()) throw Error(command + ": mode '" + o.mode + "' needs --scene");
    return load_cli_scene(o.scene);
}

}  // namespace

ResolvedCase resolve_case(const CaseOptions& o, const std::string& command) {
    ResolvedCase c;
    c.mode = &find_mode(o.mode);
    c.scene = scene_of(o, *c.mode, command);
    c.run = command_case(o, command);
    return c;
}

SceneLoadOptions& cli_scene_options() {
    static SceneLoadOptions options;
    return options;
}

CLI::Option* add_scene_options(CLI::App& c, std::string& scene, const std::string& help) {
    CLI::Option* option = c.add_option("--scene", scene, help);
    add_scene_load_options(c);
    return option;
}

CLI::Option* add_scenes_options(CLI::App& c, std::vector<std::string>& scenes) {
    CLI::Option* option =
        c.add_option("--scene", scenes,
                     "procedural scene, scene file or model file (.obj, .gltf, .glb) (repeatable; "
                     "default: every procedural scene)");
    add_scene_load_options(c);
    return option;
}

void add_screen_options(CLI::App& c, int& width, int& height, const std::string& of, int min_side) {
    CLI::Option* w = c.add_option("--width", width, "screen width" + of)->capture_default_str();
    CLI::Option* h = c.add_option("--height", height, "screen height" + of)->capture_default_str();
    if (min_side > 0) {
        w->check(CLI::Range(min_side, 16384));
        h->check(CLI::Range(min_side, 16384));
    }
}

void add_ring_options(CLI::App& c, int& rings, float& max_range) {
    c.add_option("--rings", rings, "number of error ranges (rings of eccentricity)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c.add_option("--max-range", max_range, "fraction of the largest eccentricity covered")
        ->check(CLI::Range(1e-6, 1.0))
        ->capture_default_str();
}

void add_scene_load_options(CLI::App& c, bool with_camera) {
    SceneLoadOptions& o = cli_scene_options();
    c.add_flag("--strict-obj", o.strict_obj,
               "OBJ quirks (an undefined material, a missing MTL file or texture, blanks in "
               "material names, backslashes in paths) are errors instead of warnings "
               "(docs/obj-quirks.md)");
    if (with_camera)
        c.add_option("--camera", o.camera_file,
                     "JSON camera file ({\"camera\": {...}} or the camera object, as in a scene "
                     "file) replacing the scene's camera (docs/model-files.md)")
            ->check(CLI::ExistingFile);
}

std::string data_directory() {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path executable = fs::read_symlink("/proc/self/exe", ec);
    if (!ec) {
        const fs::path installed =
            (executable.parent_path() / FOVREF_DATA_FROM_BIN).lexically_normal();
        if (fs::is_regular_file(installed / "golden" / "cases.json", ec)) return installed.string();
    }
    return FOVREF_SOURCE_DIR;
}

Scene load_cli_scene(const std::string& name_or_path, bool report) {
    namespace fs = std::filesystem;
    std::string path = name_or_path;
    std::error_code ec;
    if (!is_procedural_scene(path) && fs::path(path).is_relative() && !fs::exists(path, ec) &&
        fs::exists(fs::path(data_directory()) / path, ec))
        path = (fs::path(data_directory()) / path).string();
    Scene scene = load_scene(path, cli_scene_options());
    const SceneLoadStats& stats = scene.load_stats;
    if (!report || (stats.warnings.empty() && stats.defaulted.empty() && stats.unsupported.empty()))
        return scene;
    // One summary line on stderr, then the first few warnings; `scene info` lists them all.
    std::string summary = "fovref: scene " + name_or_path + ":";
    if (!stats.warnings.empty())
        summary += " " + std::to_string(stats.warnings.size()) + " warnings;";
    if (!stats.unsupported.empty())
        summary += " " + std::to_string(stats.unsupported.size()) + " unsupported features;";
    for (const std::string& d : stats.defaulted)
        summary += " " + d.substr(0, d.find(':')) +
                   (d.find("(--camera)") != std::string::npos ? " from --camera;" : " defaulted;");
    summary.back() = ' ';
    std::cerr << summary << "(fovref scene info " << name_or_path << " lists them)\n";
    constexpr std::size_t shown = 3;
    for (std::size_t k = 0; k < stats.warnings.size() && k < shown; ++k)
        std::cerr << "fovref: warning: " << stats.warnings[k] << "\n";
    return scene;
}

double median_of(std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

glm::vec2 parse_gaze(const std::string& text, int width, int height) {
    if (text.empty()) return {0.5f * static_cast<float>(width), 0.5f * static_cast<float>(height)};
    float xy[2] = {0, 0};
    const char* p = text.data();
    const char* end = p + text.size();
    auto r = std::from_chars(p, end, xy[0]);
    if (r.ec == std::errc() && r.ptr < end && *r.ptr == ',')
        r = std::from_chars(r.ptr + 1, end, xy[1]);
    else
        r.ec = std::errc::invalid_argument;
    if (r.ec != std::errc() || r.ptr != end || !std::isfinite(xy[0]) || !std::isfinite(xy[1]))
        throw Error("--gaze '" + text + "': expected X,Y in pixels (e.g. 640,360)");
    return {xy[0], xy[1]};
}

}  // namespace fovref
