// The options of the benchmarks (`fovref bench ...`, tools/cli/bench), registered on their
// subcommands. CLI11 is header-only and costs seconds of compile time per translation unit that
// includes it, so option registration is gathered into two files: this one and
// command_options.cpp (the other commands). Each benchmark's header declares its add_*_options
// function and documents its options struct; the comment above each group names the file with
// the benchmark's run function.
#include <CLI/CLI.hpp>

#include <string>

#include "tools/cli/bench/bmfr.h"
#include "tools/cli/bench/foveation.h"
#include "tools/cli/bench/frustum.h"
#include "tools/cli/bench/metrics.h"
#include "tools/cli/bench/rays.h"
#include "tools/cli/bench/temporal.h"
#include "tools/cli/bench/visual_polar.h"
#include "tools/cli/common/cli_common.h"

namespace fovref {

namespace {

// What the help of bench temporal's and bench bmfr's --repeats, --frames and --every says.
struct CostErrorHelp {
    const char* repeats;
    const char* frames;
    const char* every;
};

// The options bench temporal and bench bmfr share, in their order: the scene, the cost part's
// screen and timed frames, the error part's screen, sequence and stride.
template <class Options>
void add_cost_error_options(CLI::App& c, Options& o, const CostErrorHelp& help) {
    add_scene_options(c, o.scene)->capture_default_str();
    add_screen_options(c, o.width, o.height, " of the cost part", 16);
    c.add_option("--repeats", o.repeats, help.repeats)
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    c.add_option("--error-width", o.error_width, "screen width of the error part")
        ->check(CLI::Range(16, 16384))
        ->capture_default_str();
    c.add_option("--error-height", o.error_height, "screen height of the error part")
        ->check(CLI::Range(16, 16384))
        ->capture_default_str();
    c.add_option("--frames", o.frames, help.frames)
        ->check(CLI::Range(2, 10000))
        ->capture_default_str();
    c.add_option("--every", o.every, help.every)
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
}

// --rounds of the benches whose figures are ratios of timings made one after the other.
void add_rounds_option(CLI::App& c, int& rounds, const char* what) {
    c.add_option("--rounds", rounds,
                 std::string("time every ") + what +
                     " N times in turn and keep each figure's fastest over all rounds (on a "
                     "shared machine a slow spell then spoils one round, not one side of a ratio)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
}

}  // namespace

// fovref bench rays (tools/cli/bench/rays.cpp)
void add_bench_rays_options(CLI::App& c, BenchRaysOptions& o) {
    add_scenes_options(c, o.scenes);
    add_screen_options(c, o.width, o.height, " of the primary rays", 1);
    c.add_option("--repeats", o.repeats, "each timing is the fastest of N runs")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    add_rounds_option(c, o.rounds, "ray row's fovref and Embree timings");
    c.add_option("--explain", o.explain,
                 "list up to N hit/miss disagreements with Embree per row: the ray, both "
                 "answers, the brute force's, the distance to an edge")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
}

// fovref bench metrics (tools/cli/bench/metrics.cpp)
void add_bench_metrics_options(CLI::App& c, BenchMetricsOptions& o) {
    c.add_option("--size", o.sizes, "WxH (repeatable)")->capture_default_str();
    c.add_option("--repeats", o.repeats, "fastest of N runs")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
}

// fovref bench foveation (tools/cli/bench/foveation.cpp)
void add_bench_foveation_options(CLI::App& c, BenchFoveationOptions& o) {
    add_scenes_options(c, o.scenes);
    add_screen_options(c, o.width, o.height, "", 1);
    c.add_option("--repeats", o.repeats, "timed frames per mode (after an untimed first one)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    add_rounds_option(c, o.rounds, "row");
    c.add_option("--mode", o.modes,
                 "foveated mode (repeatable; default: fov, kfov, cfov, ckfov, kfr, stereo-lp, "
                 "visual-polar-basic (as vp-basic) and cfov with the lerp filter)");
    c.add_flag("--stages", o.stages, "also print each stage's own fastest time under its row");
    c.add_option("--gaze-track", o.gaze_track,
                 "gaze track for the foveated modes (frame,x,y per line, docs/foveation.md): a "
                 "moving gaze, whose maps and pass 2 tables are made again each frame (default: "
                 "the gaze at the centre)")
        ->check(CLI::ExistingFile);
}

// fovref bench temporal (tools/cli/bench/temporal.cpp)
void add_bench_temporal_options(CLI::App& c, BenchTemporalOptions& o) {
    add_cost_error_options(c, o,
                           {.repeats = "timed frames per row (after an untimed first one)",
                            .frames = "frames of each error sequence",
                            .every = "moving camera: compare every K-th frame"});
    c.add_flag("--no-cost", o.skip_cost, "skip the cost part");
    c.add_flag("--no-error", o.skip_error, "skip the error part");
}

// fovref bench frustum (tools/cli/bench/frustum.cpp)
void add_bench_frustum_options(CLI::App& c, BenchFrustumOptions& o) {
    c.add_option("--scene", o.scenes,
                 "procedural scenes or scene files (default: every procedural one)");
    c.add_option("--width", o.width, "screen width")
        ->check(CLI::Range(16, 16384))
        ->capture_default_str();
    c.add_option("--height", o.height, "screen height")
        ->check(CLI::Range(16, 16384))
        ->capture_default_str();
    c.add_option("--tile-size", o.tile_sizes, "tile sizes in pixels (default 16 32 64)")
        ->check(CLI::Range(1, 4096));
}

// fovref bench bmfr (tools/cli/bench/bmfr.cpp)
void add_bench_bmfr_options(CLI::App& c, BenchBmfrOptions& o) {
    add_cost_error_options(c, o,
                           {.repeats = "timed frames (after an untimed first one)",
                            .frames = "frames of the error sequence",
                            .every = "compare every K-th frame"});
    c.add_option("--reference-spp", o.reference_spp, "samples per pixel of the reference")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    c.add_flag("--no-cost", o.skip_cost, "skip the cost part");
    c.add_option("--input", o.input,
                 "time the phases on another renderer's buffers instead (the layout of `fovref "
                 "denoise bmfr`'s IN_DIR); no path tracing, no error part");
    c.add_option("--param", o.params, "with --input: BMFR parameters, as denoise bmfr takes");
    c.add_flag("--demodulated", o.demodulated,
               "with --input: the colour is already divided by albedo (as denoise bmfr)");
    c.add_flag("--no-error", o.skip_error, "skip the error part");
}

// fovref bench visual-polar (tools/cli/bench/visual_polar.cpp)
void add_bench_visual_polar_options(CLI::App& c, BenchVisualPolarOptions& o) {
    add_scene_options(c, o.scene)->capture_default_str();
    c.add_option("--width", o.width,
                 "screen width of the cost part (with --height: this one size instead of "
                 "1280x1440 and 1280x720)")
        ->check(CLI::Range(16, 16384));
    c.add_option("--height", o.height, "screen height of the cost part (with --width)")
        ->check(CLI::Range(16, 16384));
    c.add_option("--repeats", o.repeats, "timed frames (after an untimed first one)")
        ->check(CLI::Range(1, 100))
        ->capture_default_str();
    add_rounds_option(c, o.rounds, "method of the cost part");
    c.add_option("--error-size", o.error_size, "screen size WxH of the error part")
        ->capture_default_str();
    c.add_option("--frames", o.frames, "frames of the error sequence")
        ->check(CLI::Range(2, 10000))
        ->capture_default_str();
    c.add_option("--every", o.every, "compare every K-th frame")
        ->check(CLI::Range(1, 10000))
        ->capture_default_str();
    c.add_option("--spp,--reference-spp", o.reference_spp, "samples per pixel of the reference")
        ->check(CLI::Range(1, 65536))
        ->capture_default_str();
    c.add_option("--rings", o.rings, "eccentricity rings of the ring table")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c.add_option("--gaze-track", o.gaze_track,
                 "gaze track of the cost part for visual-polar and log-polar-pathtrace (frame,x,y "
                 "per line, docs/foveation.md): a moving gaze, whose maps and tables are made "
                 "again each frame (default: the gaze at the screen centre)")
        ->check(CLI::ExistingFile);
    c.add_flag("--no-cost", o.skip_cost, "skip the cost part");
    c.add_flag("--no-error", o.skip_error, "skip the error part");
}

}  // namespace fovref
