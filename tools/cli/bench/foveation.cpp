// `fovref bench foveation`: for each procedural scene at W x H with the gaze at the centre, the
// basic ray tracer and each foveated mode render 1 + repeats frames of a static camera; frame 0
// (which builds the BVH) is left out and each stage's time is its fastest over the others. Per
// mode: the buffer, the share of W x H dispatched (every texel, plus the gaze pixels traced) and
// traced (primary rays), the stage groups (trace: ray generation and tracing of the buffers;
// shade; pass 2; filters), the frame, the speed-up over basic, the target 0.8 x (basic's primary
// rays / the mode's), and the share of the frame spent in pass 2 and the filters.
#include "tools/cli/bench/foveation.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "ref/core/error.h"
#include "ref/modes/modes.h"
#include "ref/scene/procedural.h"
#include "tools/cli/bench/bench_util.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

/// The fastest time of each stage group, and of the whole frame, over the timed frames.
struct ModeTimes {
    std::map<std::string, double> group;                ///< trace, shade, pass2, filters
    std::vector<std::pair<std::string, double>> stage;  ///< each stage that ran, pipeline order
    double frame = 0.0;
    std::int64_t rays = 0, dispatched = 0, buffer_width = 0, buffer_height = 0;
    /// BVH work of the frame's rays: nodes visited plus triangles tested, primary and shadow.
    std::int64_t work = 0;
};

const char* stage_group(const std::string& stage) {
    if (stage == "primary_visibility" || stage == "lp_trace" || stage == "gaze_trace" ||
        stage == "gbuffer_raster" || stage == "lp_sample" || stage == "stereo_trace" ||
        stage == "vp_trace")
        return "trace";
    if (stage == "shade_direct" || stage == "lp_shade" || stage == "gaze_shade" ||
        stage == "stereo_shade" || stage == "vp_shade")
        return "shade";
    if (stage == "resolve") return "pass2";
    return "filters";
}

ModeTimes time_mode(const Scene& scene, const std::string& mode, const Params& params,
                    const BenchFoveationOptions& o, Progress& progress, double done, double step) {
    RenderSettings s;
    s.width = o.width;
    s.height = o.height;
    s.frame_count = 1 + o.repeats;
    s.time_step = 0.0f;  // a static camera: every frame does the same work
    s.params = params;
    if (!o.gaze_track.empty() && mode != "basic") s.params.set("gaze_track", o.gaze_track);
    s.progress = [&](double f) { progress.update(done + f * step); };
    ModeTimes t;
    t.frame = 1e300;
    render_each(&scene, mode, s, [&](FrameResult& f) {
        if (f.frame == 0) {
            t.rays = f.counters.get("rays_primary");
            t.work = f.counters.get("primary_nodes_visited") +
                     f.counters.get("primary_triangles_tested") +
                     f.counters.get("shadow_nodes_visited") +
                     f.counters.get("shadow_triangles_tested");
            t.buffer_width = f.counters.get("buffer_width");
            t.buffer_height = f.counters.get("buffer_height");
            const std::int64_t eyes = std::max<std::int64_t>(1, f.counters.get("eyes"));
            t.dispatched =
                eyes * t.buffer_width * t.buffer_height + f.counters.get("gaze_pixels_traced");
            return;
        }
        std::map<std::string, double> groups = {
            {"trace", 0.0}, {"shade", 0.0}, {"pass2", 0.0}, {"filters", 0.0}};
        double frame = 0.0;
        std::size_t k = 0;
        for (const StageRun& run : f.stages) {
            if (!run.ran) continue;
            groups[stage_group(run.name)] += run.seconds;
            frame += run.seconds;
            if (k == t.stage.size())
                t.stage.emplace_back(run.name, run.seconds);
            else
                t.stage[k].second = std::min(t.stage[k].second, run.seconds);
            ++k;
        }
        for (const auto& [name, seconds] : groups)
            t.group[name] = t.group.count(name) ? std::min(t.group[name], seconds) : seconds;
        t.frame = std::min(t.frame, frame);
    });
    return t;
}

/// The fastest of two timings of one mode (two rounds): each figure's minimum. The stages ran in
/// the same order and the counters are the same.
ModeTimes fastest(ModeTimes a, const ModeTimes& b) {
    a.frame = std::min(a.frame, b.frame);
    for (auto& [name, seconds] : a.group) seconds = std::min(seconds, b.group.at(name));
    for (std::size_t k = 0; k < a.stage.size() && k < b.stage.size(); ++k)
        a.stage[k].second = std::min(a.stage[k].second, b.stage[k].second);
    return a;
}

struct ModeRow {
    std::string label, mode;
    Params params;
};

// The rows of the table: basic, then the modes asked for (by default every foveated mode).
std::vector<ModeRow> bench_rows(const BenchFoveationOptions& o) {
    std::vector<ModeRow> rows = {{"basic", "basic", {}}};
    if (o.modes.empty()) {
        for (const std::string m : {"fov", "kfov", "cfov", "ckfov", "kfr", "stereo-lp"})
            rows.push_back({m, m, {}});
        rows.push_back({"vp-basic", "visual-polar-basic", {}});
        rows.push_back(
            {"cfov+lerp", "cfov", Params(std::map<std::string, std::string>{{"filters", "lerp"}})});
        return rows;
    }
    for (const std::string& m : o.modes) {
        if (m == "basic") continue;
        find_mode(m);  // an unknown mode is an error before any work
        rows.push_back({m, m, {}});
    }
    return rows;
}

// Lund's Table 5.3 for his four presets: the share of the screen's pixels dispatched and traced
// (his resolution and viewing distance are not stated); "-" for the other rows.
struct LundRow {
    const char* mode;
    double traced, dispatched;
};
constexpr LundRow lund_table_5_3[] = {
    {"fov", 154.0, 162.0}, {"kfov", 65.7, 75.4}, {"cfov", 37.5, 48.3}, {"ckfov", 37.7, 47.6}};

// "154.0%" for a Lund preset run with its own parameters, else "-".
std::string lund_share(const ModeRow& row, bool traced) {
    if (row.params.values().size() > 0) return "-";
    for (const LundRow& l : lund_table_5_3)
        if (row.mode == l.mode) {
            char text[16];
            std::snprintf(text, sizeof text, "%.1f%%", traced ? l.traced : l.dispatched);
            return text;
        }
    return "-";
}

void print_header(const BenchFoveationOptions& o) {
    const std::string gaze =
        o.gaze_track.empty() ? "gaze at the centre" : "gaze moving along " + o.gaze_track;
    std::printf(
        "fovref bench foveation: %dx%d, %s, one thread; each stage the fastest of %d frames (the "
        "first frame, which builds the BVH, is not timed)%s\n",
        o.width, o.height, gaze.c_str(), o.repeats * o.rounds,
        rounds_note(o.rounds, ", over ", " rounds (every row timed in turn in each)").c_str());
    std::printf(
        "trace = ray generation + tracing of the buffers; target = 0.8 x (basic's primary "
        "rays / the mode's); pass 2 + filters share: target <= 15%% (issue 33: <= 12%% for "
        "cfov and ckfov, flagged '12%% share'); issue 33: kfr and vp-basic >= 1.5x basic "
        "(flagged '1.5x basic')\n"
        "work = BVH nodes visited + triangles tested by all rays (primary and shadow), %% of "
        "basic's; w-target = 0.8 x (basic's work / the mode's): rays differ in cost (those near "
        "the gaze may hit more), which the ray-count target does not see\n"
        "Lund tr./disp.: Lund's Table 5.3 shares for his presets. Traced agrees within 3 "
        "points at 1280x720 (his resolution and viewing distance are not stated, ours are the "
        "camera's); dispatched differs more: Lund dispatches the gaze buffer's whole square "
        "((2 r_G)^2) and the texels that map off screen, ours the texels and the gaze pixels "
        "traced (docs/foveation.md, \"Rays traced against Lund Table 5.3\")\n");
}

// One row: the mode's buffer, shares of rays and work, stage-group times, speed-up against
// basic and whether it meets its targets.
void print_row(const BenchFoveationOptions& o, const ModeRow& row, const ModeTimes& t,
               const ModeTimes& basic) {
    const double pixels = static_cast<double>(o.width) * o.height;
    const std::string buffer =
        t.buffer_width > 0 ? std::to_string(t.buffer_width) + "x" + std::to_string(t.buffer_height)
                           : "-";
    const double dispatched = row.mode == "basic" ? pixels : static_cast<double>(t.dispatched);
    const double speedup = basic.frame / t.frame;
    const double target = 0.8 * static_cast<double>(basic.rays) /
                          static_cast<double>(std::max<std::int64_t>(t.rays, 1));
    const double share = (t.group.at("pass2") + t.group.at("filters")) / t.frame;
    // A mode without primary rays (the deferred kfr) has no ray-count target.
    char target_text[16] = "-";
    if (row.mode == "basic")
        std::snprintf(target_text, sizeof target_text, "1.00x");
    else if (t.rays > 0)
        std::snprintf(target_text, sizeof target_text, "%.2fx", target);
    const double work_target = 0.8 * static_cast<double>(basic.work) /
                               static_cast<double>(std::max<std::int64_t>(t.work, 1));
    std::string verdict;
    if (row.mode != "basic") {
        std::vector<std::string> missed;
        if (t.rays > 0 && speedup < target) missed.push_back("ray target");
        if (t.rays > 0 && speedup < work_target) missed.push_back("work target");
        if (share > 0.15) missed.push_back("share");
        // issue 33's targets
        const bool composite = row.label == "cfov" || row.label == "ckfov";
        if (composite && share > 0.12 && share <= 0.15) missed.push_back("12% share");
        if ((row.mode == "kfr" || row.mode == "visual-polar-basic") && speedup < 1.5)
            missed.push_back("1.5x basic");
        verdict = "  ok";
        for (std::size_t k = 0; k < missed.size(); ++k)
            verdict = (k == 0 ? "  misses " : verdict + ", ") + missed[k];
    }
    char work_target_text[16] = "-";
    if (row.mode == "basic" || t.rays > 0)
        std::snprintf(work_target_text, sizeof work_target_text, "%.2fx",
                      row.mode == "basic" ? 1.0 : work_target);
    std::printf(
        "  %-10s %-10s %7.1f%% %7.1f%% %9s %10s %6.1f%% %9.2f %9.2f %9.2f %9.2f %9.2f %7.2fx "
        "%7s %8s %8.1f%%%s\n",
        row.label.c_str(), buffer.c_str(), 100.0 * dispatched / pixels,
        100.0 * static_cast<double>(t.rays) / pixels, lund_share(row, true).c_str(),
        lund_share(row, false).c_str(),
        100.0 * static_cast<double>(t.work) /
            static_cast<double>(std::max<std::int64_t>(basic.work, 1)),
        1e3 * t.group.at("trace"), 1e3 * t.group.at("shade"), 1e3 * t.group.at("pass2"),
        1e3 * t.group.at("filters"), 1e3 * t.frame, speedup, target_text, work_target_text,
        100.0 * share, verdict.c_str());
    if (o.stages)
        for (const auto& [stage, seconds] : t.stage)
            std::printf("    %-24s %9.2f ms\n", stage.c_str(), 1e3 * seconds);
    std::fflush(stdout);
}

}  // namespace

int run_bench_foveation(const BenchFoveationOptions& o) {
    if (o.repeats < 1 || o.rounds < 1)
        throw Error("bench foveation: --repeats and --rounds must be at least 1");
    std::vector<std::string> scenes = o.scenes;
    if (scenes.empty())
        for (const ProceduralSceneInfo& info : procedural_scenes()) scenes.push_back(info.name);
    std::map<std::string, Scene> files;  // the scene files, loaded once
    for (const std::string& name : scenes)
        if (!is_procedural_scene(name))
            files.emplace(name, load_cli_scene(name));  // a file must load before the table
    const std::vector<ModeRow> rows = bench_rows(o);
    print_header(o);
    Progress progress("bench foveation", o.quiet);
    const double step = 1.0 / static_cast<double>(scenes.size() * rows.size() * o.rounds);
    double done = 0.0;
    for (const std::string& name : scenes) {
        // Procedural scenes are made here, one at a time; the files were loaded above.
        auto file = files.find(name);
        if (file == files.end()) file = files.emplace(name, load_cli_scene(name, false)).first;
        const Scene scene = std::move(file->second);
        files.erase(file);
        std::printf("\n%s\n", name.c_str());
        std::printf("  %-10s %-10s %8s %8s %9s %10s %7s %9s %9s %9s %9s %9s %8s %7s %8s %9s\n",
                    "mode", "buffer", "dispatch", "traced", "Lund tr.", "Lund disp.", "work",
                    "trace ms", "shade ms", "pass2 ms", "filt. ms", "frame ms", "speed-up",
                    "target", "w-target", "p2+f share");
        // Every row once per round, in turn; a row is printed once its last round is timed.
        std::vector<ModeTimes> times(rows.size());
        for (int round = 0; round < o.rounds; ++round)
            for (std::size_t r = 0; r < rows.size(); ++r) {
                const ModeTimes t =
                    time_mode(scene, rows[r].mode, rows[r].params, o, progress, done, step);
                done += step;
                times[r] = round == 0 ? t : fastest(times[r], t);
                if (round + 1 < o.rounds) continue;
                progress.clear();
                print_row(o, rows[r], times[r], times[0]);  // rows[0] is basic
            }
    }
    progress.finish();
    return 0;
}

}  // namespace fovref
