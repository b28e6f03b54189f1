#include "tools/cli/commands/golden.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/modes/modes.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

namespace fs = std::filesystem;

namespace fovref {

namespace {

// The largest golden kept in the repository (golden update refuses larger cases).
constexpr int golden_max_width = 320, golden_max_height = 180;

// The golden directory as an absolute, normalised path without a trailing separator; its parent
// is the repository root that relative scene paths in cases.json are resolved against.
std::string golden_directory(const GoldenOptions& o) {
    fs::path dir = !o.dir.empty()                    ? fs::path(o.dir)
                   : fs::exists("golden/cases.json") ? fs::path("golden")
                                                     : fs::path(data_directory()) / "golden";
    dir = fs::absolute(dir).lexically_normal();
    if (dir.filename().empty()) dir = dir.parent_path();
    return dir.string();
}

std::string repository_root(const std::string& golden_dir) {
    return fs::path(golden_dir).parent_path().string();
}

std::vector<GoldenCase> selected_cases(const GoldenCasesOptions& o,
                                       const std::vector<GoldenCase>& all) {
    if (o.cases.empty()) return all;
    std::vector<GoldenCase> chosen;
    for (const std::string& name : o.cases) chosen.push_back(find_golden_case(all, name));
    return chosen;
}

// Recomputes case `c` and compares it with its bundle. Returns the lines to print: "FAIL ..."
// first when it fails, "ok ..." (unless quiet) when it matches.
std::vector<std::string> verify_case(const GoldenCase& c, const std::string& dir,
                                     SceneCache& scenes, bool quiet) {
    const std::string bundle = dir + "/" + c.name;
    std::vector<std::string> report;
    if (!fs::exists(bundle + "/manifest.json")) {
        report.push_back("FAIL " + c.name + ": no bundle at " + bundle +
                         " (run `fovref golden update --case " + c.name + "`)");
        return report;
    }
    const Manifest manifest = read_manifest(bundle);
    if (!(manifest.golden_case == c)) {
        report.push_back("FAIL " + c.name +
                         ": the bundle was made for a different case definition (run `fovref "
                         "golden update --case " +
                         c.name + "`)");
        return report;
    }
    const std::vector<FrameResult> frames = render_golden_case(c, scenes.get(c.scene), {"all"});
    const std::vector<GoldenDifference> differences = compare_with_bundle(bundle, manifest, frames);
    std::size_t buffers = 0;
    for (const FrameResult& f : frames) buffers += f.buffers.size();
    if (differences.empty()) {
        char line[160];
        std::snprintf(line, sizeof line, "ok   %-34s %zu buffers, %d frame(s)", c.name.c_str(),
                      buffers, c.frames);
        if (!quiet) report.push_back(line);
    } else {
        report.push_back("FAIL " + c.name + ": " + std::to_string(differences.size()) +
                         " difference(s); first in pipeline order:");
        for (const GoldenDifference& d : differences)
            report.push_back("     frame " + std::to_string(d.frame) + ", buffer " + d.buffer +
                             ": " + d.what);
    }
    return report;
}

// Bundles whose case is gone from cases.json are stale: removed in name order.
void remove_stale_bundles(const std::string& dir, const std::vector<GoldenCase>& all, bool quiet) {
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
        say(quiet, "removed " + name + ": no longer in cases.json");
    }
}

}  // namespace

int run_golden_list(const GoldenOptions& o) {
    const std::string dir = golden_directory(o);
    const std::vector<GoldenCase> cases = load_golden_cases(dir + "/cases.json");
    // Columns as wide as their longest entry
    int name_width = 4, mode_width = 4, scene_width = 5;
    for (const GoldenCase& c : cases) {
        name_width = std::max(name_width, static_cast<int>(c.name.size()));
        mode_width = std::max(mode_width, static_cast<int>(c.mode.size()));
        scene_width = std::max(scene_width, static_cast<int>(c.scene.size()));
    }
    for (const GoldenCase& c : cases)
        std::printf("%-*s %-*s %-*s %dx%d x%d  %s\n", name_width, c.name.c_str(), mode_width,
                    c.mode.c_str(), scene_width, c.scene.empty() ? "-" : c.scene.c_str(), c.width,
                    c.height, c.frames, c.description.c_str());
    return exit_ok;
}

int run_golden_verify(const GoldenOptions& o, const GoldenCasesOptions& selection) {
    const std::string dir = golden_directory(o);
    const std::vector<GoldenCase> cases =
        selected_cases(selection, load_golden_cases(dir + "/cases.json"));
    SceneCache scenes(repository_root(dir));
    int failed = 0;
    Progress progress("golden verify", o.quiet);
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const GoldenCase& c = cases[k];
        std::vector<std::string> report;  // printed after the progress line is cleared
        try {
            report = verify_case(c, dir, scenes, o.quiet);
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

int run_golden_update(const GoldenOptions& o, const GoldenCasesOptions& selection) {
    const std::string dir = golden_directory(o);
    const std::vector<GoldenCase> all = load_golden_cases(dir + "/cases.json");
    const std::vector<GoldenCase> cases = selected_cases(selection, all);
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
                say(o.quiet, "  " + c.name + " frame " + std::to_string(d.frame) + " " + d.buffer +
                                 ": " + d.what);
        }
        write_bundle(bundle, c, frames, options);
        say(o.quiet, "updated " + c.name + ": " + status);
    }
    if (selection.cases.empty()) remove_stale_bundles(dir, all, o.quiet);
    return exit_ok;
}

int run_golden_export(const GoldenOptions& o, const GoldenExportOptions& e) {
    const std::string dir = golden_directory(o);
    GoldenCase c = find_golden_case(load_golden_cases(dir + "/cases.json"), e.case_name);
    if (e.width) c.width = *e.width;
    if (e.height) c.height = *e.height;
    if (e.frames) c.frames = *e.frames;
    // --param replaces the case's value of a key (each key given once)
    const Params given = Params::from_assignments(e.params);
    for (const auto& [key, value] : given.values()) c.params.set(key, value);
    c.files = "all";  // an export writes every frame's files
    SceneCache scenes(repository_root(dir));
    const Scene* scene = scenes.get(c.scene);
    if (e.with_scene && !scene) throw Error("--with-scene: case '" + c.name + "' has no scene");
    BundleOptions options;
    options.previews_for_all = true;
    options.raw_copies = e.raw_copies;
    options.include_timings = e.timings;
    for (const ParamSpec& spec : find_mode(c.mode).params)
        options.effective_params[spec.name] =
            c.params.given(spec.name) ? c.params.values().at(spec.name) : spec.default_value;
    BundleWriter writer(e.directory, c, options);
    if (e.with_scene) writer.add_scene(*scene, "scene");
    Progress progress("golden export " + c.name, o.quiet);
    render_each(scene, c.mode, case_settings(c, {"all"}, [&](double f) { progress.update(f); }),
                [&](FrameResult& frame) { writer.add_frame(frame); });
    progress.finish();
    writer.commit();
    say(o.quiet, "exported " + c.name + " at " + std::to_string(c.width) + "x" +
                     std::to_string(c.height) + ", " + std::to_string(c.frames) + " frame(s), to " +
                     e.directory);
    return exit_ok;
}

}  // namespace fovref
