// fovref: the command-line tool of the reference renderer. This file builds the command line and
// dispatches; each command (or command group) is a module of its own, with its options and its
// run function:
//   tools/cli/commands/  scene, modes, render, rays, golden, probe, evaluate, sweep, stress, diff
//                        (diff/: input, compare, probe_hint, console, json, html), gain,
//                        density, denoise
//   tools/cli/bench/     rays (and embree, its peer), metrics, foveation, temporal, bmfr,
//                        visual_polar
//   tools/cli/report/    JSON values, SVG plots, the sweep report
//   tools/cli/options/   the registration of every command's options (command_options.cpp) and
//                        every benchmark's (bench_options.cpp): the only files besides this one
//                        and common/cli_common.cpp that include CLI11 (seconds of compile time
//                        per file)
//   tools/cli/common/    what they share: exit codes, option groups, the resolved case, number
//                        formatting, progress
// Exit codes: 0 ok, 1 a check failed (golden verify, diff), 2 usage or input error.
#include <CLI/CLI.hpp>
#include <climits>
#include <cstdio>
#include <exception>
#include <functional>
#include <string>
#include <utility>
#include <vector>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "tools/cli/bench/bmfr.h"
#include "tools/cli/bench/foveation.h"
#include "tools/cli/bench/frustum.h"
#include "tools/cli/bench/metrics.h"
#include "tools/cli/bench/rays.h"
#include "tools/cli/bench/temporal.h"
#include "tools/cli/bench/visual_polar.h"
#include "tools/cli/commands/denoise.h"
#include "tools/cli/commands/density.h"
#include "tools/cli/commands/diff/diff.h"
#include "tools/cli/commands/evaluate.h"
#include "tools/cli/commands/gain.h"
#include "tools/cli/commands/golden.h"
#include "tools/cli/commands/modes.h"
#include "tools/cli/commands/probe.h"
#include "tools/cli/commands/rays.h"
#include "tools/cli/commands/render.h"
#include "tools/cli/commands/scene.h"
#include "tools/cli/commands/stress.h"
#include "tools/cli/commands/sweep.h"
#include "tools/cli/common/cli_common.h"

using namespace fovref;

namespace {

const char* const app_description =
    "fovref: deterministic reference renderer for foveated ray and path tracing.\n"
    "Exit codes: 0 ok, 1 a check failed, 2 usage or input error.\n"
    "Input limits (file size, image pixels, rays; raise them with FOVREF_MAX_* environment "
    "variables): docs/limits.md.";

const char* const app_footer =
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
    "  fovref rays cull SCENE DIR [--tile-size N] [--shadow]   each tile's culled BVH2, for a GPU\n"
    "  fovref bench rays [--scene S] [--width W --height H]   BVH and ray throughput (vs "
    "Embree)\n"
    "  fovref bench metrics [--size WxH]      metric times (vs scikit-image's SSIM)\n"
    "  fovref bench foveation [--scene S]     foveated modes' stage times vs basic, rays traced\n"
    "  fovref bench frustum [--scene S]       tile frustum culling: cull time, traversal, hits "
    "lost\n"
    "  fovref bench temporal [--scene S]      TAA cost per frame; errors and flicker with and "
    "without TAA\n"
    "  fovref bench bmfr [--scene S]          path tracer + BMFR phase times; error before/after "
    "denoising\n"
    "  fovref bench visual-polar [--scene S]  path tracing + BMFR in screen vs Visual-Polar "
    "space: cost, error\n"
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
    "  fovref sweep plan FILE OUT | run OUT [--jobs N] | merge OUT | report OUT --html DIR\n"
    "               | export OUT --format parallel|slurm|k8s\n"
    "                                         run time against error over a grid\n"
    "  fovref stress [--fast] [--case G]      numerical stress suite\n"
    "  fovref diff GOLDEN CANDIDATE [--tolerance N:abs=X] [--json F] [--html DIR]\n"
    "                                         compare a GPU's buffers with a golden bundle\n"
    "  fovref gain [--fov-deg W[,H] --max-cpd C] [--json]\n"
    "                                         theoretical gain of foveation (Koskela P1)\n"
    "  fovref density MODE [--scene S --gaze X,Y --param k=v] [--out DIR]\n"
    "                                         rays per pixel per error ring vs acuity\n"
    "  fovref denoise bmfr IN_DIR OUT_DIR [--demodulated] [--frames A..B] [--output a,b]\n"
    "                [--param k=v]             BMFR on another renderer's buffers, every phase\n"
    "SCENE is a procedural scene name (see `scene list`) or a scene file or directory.\n"
    "Run `fovref COMMAND --help` for each command's options.";

// Every command's options; only those of the command the command line names are read.
struct Options {
    bool quiet = false;  ///< -q, global: copied into the command's options after parsing
    SceneInfoOptions scene_info;
    SceneExportOptions scene_export;
    RenderOptions render;
    RaysTraceOptions rays_trace;
    RaysMakeOptions rays_make;
    RaysCullOptions rays_cull;
    BenchRaysOptions bench_rays;
    BenchMetricsOptions bench_metrics;
    BenchFoveationOptions bench_foveation;
    BenchTemporalOptions bench_temporal;
    BenchFrustumOptions bench_frustum;
    BenchBmfrOptions bench_bmfr;
    BenchVisualPolarOptions bench_visual_polar;
    GoldenOptions golden;
    GoldenCasesOptions golden_verify, golden_update;
    GoldenExportOptions golden_export;
    ProbeOptions probe;
    EvaluateOptions evaluate;
    DiffOptions diff;
    GainOptions gain;
    DensityOptions density;
    DenoiseOptions denoise;
    SweepOptions sweep;
    StressOptions stress;
};

// -q applies to every command that prints progress or lines (bench metrics prints its figures
// either way).
void share_quiet(Options& o) {
    o.scene_export.quiet = o.render.quiet = o.rays_trace.quiet = o.rays_make.quiet =
        o.rays_cull.quiet = o.bench_rays.quiet = o.density.quiet = o.bench_foveation.quiet =
            o.bench_temporal.quiet = o.bench_frustum.quiet = o.bench_bmfr.quiet =
                o.bench_visual_polar.quiet = o.golden.quiet = o.probe.quiet = o.evaluate.quiet =
                    o.diff.quiet = o.denoise.quiet = o.sweep.quiet = o.stress.quiet = o.quiet;
}

// The commands that do the work (no subcommands of their own), each with its run function.
using Commands = std::vector<std::pair<const CLI::App*, std::function<int()>>>;

// A group of subcommands (scene, rays, bench, golden): exactly one of them, and the options of
// the group and the global ones may follow it.
CLI::App* add_group(CLI::App& app, const std::string& name, const std::string& description) {
    CLI::App* group = app.add_subcommand(name, description);
    group->require_subcommand(1);
    group->fallthrough();
    return group;
}

void add_scene_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* scene = add_group(app, "scene", "inspect, list and export scenes");
    CLI::App* info = scene->add_subcommand(
        "info",
        "triangles, lights, bounds, materials, camera, and what the loader dropped or repaired");
    add_scene_info_options(*info, o.scene_info);
    CLI::App* exporter = scene->add_subcommand(
        "export", "write any scene (procedural ones too) as OBJ + MTL + textures + scene.json");
    add_scene_export_options(*exporter, o.scene_export);
    CLI::App* list = scene->add_subcommand("list", "the procedural scenes");
    commands.emplace_back(info, [&o] { return run_scene_info(o.scene_info); });
    commands.emplace_back(exporter, [&o] { return run_scene_export(o.scene_export); });
    commands.emplace_back(list, [] { return run_scene_list(); });
}

void add_render_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* render =
        app.add_subcommand("render", "render frames of a mode and write its buffers");
    add_render_options(*render, o.render);
    CLI::App* modes = app.add_subcommand("modes", "list render modes and their parameters");
    commands.emplace_back(render, [&o] { return run_render(o.render); });
    commands.emplace_back(modes, [] { return run_modes(); });
}

void add_rays_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* rays =
        add_group(app, "rays", "trace ray files (check a GPU traversal) and make them");
    CLI::App* trace = rays->add_subcommand("trace",
                                           "closest hits (t, primitive, u, v; miss = -1) or, with "
                                           "--any-hit, occlusion of every ray in RAYS");
    add_rays_trace_options(*trace, o.rays_trace);
    CLI::App* make =
        rays->add_subcommand("make", "write a camera's primary rays or fixed-seed random rays");
    add_rays_make_options(*make, o.rays_make);
    CLI::App* cull = rays->add_subcommand(
        "cull",
        "write each screen tile's frustum-culled BVH2 (Lund's or the exact test; optionally the "
        "shadow frusta towards a point light) for a GPU to load, traverse or diff: "
        "docs/frustum.md");
    add_rays_cull_options(*cull, o.rays_cull);
    commands.emplace_back(trace, [&o] { return run_rays_trace(o.rays_trace); });
    commands.emplace_back(make, [&o] { return run_rays_make(o.rays_make); });
    commands.emplace_back(cull, [&o] { return run_rays_cull(o.rays_cull); });
}

void add_bench_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* bench = add_group(app, "bench", "benchmarks (figures, not tests)");
    CLI::App* rays = bench->add_subcommand("rays",
                                           "BVH build, Mrays/s for primary, incoherent and shadow "
                                           "rays, G-buffer pass times; with Embree installed, the "
                                           "same rays through Embree in the same run");
    add_bench_rays_options(*rays, o.bench_rays);
    CLI::App* metrics = bench->add_subcommand(
        "metrics",
        "time of each metric at 1280x720 and 3840x2160; with python3-skimage installed, "
        "scikit-image's SSIM on the same images in the same run");
    add_bench_metrics_options(*metrics, o.bench_metrics);
    commands.emplace_back(rays, [&o] { return run_bench_rays(o.bench_rays); });
    commands.emplace_back(metrics, [&o] { return run_bench_metrics(o.bench_metrics); });
    CLI::App* foveation = bench->add_subcommand(
        "foveation",
        "stage times of the foveated modes against basic in the same run, with the rays traced "
        "and the speed-up target (0.8 x the ray-count ratio)");
    add_bench_foveation_options(*foveation, o.bench_foveation);
    commands.emplace_back(foveation, [&o] { return run_bench_foveation(o.bench_foveation); });
    CLI::App* temporal = bench->add_subcommand(
        "temporal",
        "TAA's cost per frame relative to the rest of the frame, and the ring and temporal "
        "errors of moving and static sequences with and without TAA, depth vs clamping");
    add_bench_temporal_options(*temporal, o.bench_temporal);
    commands.emplace_back(temporal, [&o] { return run_bench_temporal(o.bench_temporal); });
    CLI::App* frustum = bench->add_subcommand(
        "frustum",
        "Lund's tile frustum culling on the CPU: culling time, culled trees, primary-ray "
        "traversal through them against the unculled BVH, hits lost (docs/frustum.md)");
    add_bench_frustum_options(*frustum, o.bench_frustum);
    commands.emplace_back(frustum, [&o] { return run_bench_frustum(o.bench_frustum); });
    CLI::App* bmfr = bench->add_subcommand(
        "bmfr",
        "path tracer and BMFR phase times per 720p frame, and the error before and after "
        "denoising against the converged reference on a moving sequence (Koskela P2 style)");
    add_bench_bmfr_options(*bmfr, o.bench_bmfr);
    commands.emplace_back(bmfr, [&o] { return run_bench_bmfr(o.bench_bmfr); });
    CLI::App* visual_polar = bench->add_subcommand(
        "visual-polar",
        "path tracing + BMFR in screen space vs Visual-Polar space (Koskela P5): stage times "
        "and speed-ups at 1280x1440 and 1280x720, and the errors (RMSE, SSIM, per ring, "
        "temporal) of both and of linear-falloff against the converged reference");
    add_bench_visual_polar_options(*visual_polar, o.bench_visual_polar);
    commands.emplace_back(visual_polar,
                          [&o] { return run_bench_visual_polar(o.bench_visual_polar); });
}

void add_golden_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* golden = add_group(app, "golden", "verify, update, list and export golden bundles");
    add_golden_options(*golden, o.golden);
    CLI::App* verify = golden->add_subcommand("verify",
                                              "recompute every golden and compare bit-exactly; "
                                              "names the first differing buffer and pixel");
    add_golden_cases_options(*verify, o.golden_verify);
    CLI::App* update =
        golden->add_subcommand("update", "recompute and rewrite goldens, saying what changed");
    add_golden_cases_options(*update, o.golden_update);
    CLI::App* list = golden->add_subcommand("list", "the golden cases");
    CLI::App* exporter = golden->add_subcommand(
        "export", "write a full bundle (every buffer of every frame) of a case at any size");
    add_golden_export_options(*exporter, o.golden_export);
    commands.emplace_back(verify, [&o] { return run_golden_verify(o.golden, o.golden_verify); });
    commands.emplace_back(update, [&o] { return run_golden_update(o.golden, o.golden_update); });
    commands.emplace_back(list, [&o] { return run_golden_list(o.golden); });
    commands.emplace_back(exporter, [&o] { return run_golden_export(o.golden, o.golden_export); });
}

// probe, evaluate and diff: a mode's pixel explained, ring errors, a GPU's buffers compared.
void add_check_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* probe = app.add_subcommand(
        "probe",
        "explain one screen pixel of a mode and frame stage by stage: buffer coordinates, ray, "
        "hit, texels and their lerps, shading inputs, light samples, every buffer's value; exit 1 "
        "if the recomputation differs from the rendered buffer");
    add_probe_options(*probe, o.probe);
    CLI::App* evaluate = app.add_subcommand(
        "evaluate",
        "render modes (or read rendered frames) along the camera path and compute error ranges "
        "against the ground truth every k-th frame: CSV, JSON, SVG plot, heatmaps");
    add_evaluate_options(*evaluate, o.evaluate);
    CLI::App* diff = app.add_subcommand(
        "diff",
        "compare a candidate (a GPU implementation's buffers or one image) with a golden bundle "
        "or image: per-buffer errors, worst pixels, error ranges, pass/fail by tolerance; exit 0 "
        "pass, 1 out of tolerance, 2 usage or input error");
    add_diff_options(*diff, o.diff);
    commands.emplace_back(probe, [&o] { return run_probe(o.probe); });
    commands.emplace_back(evaluate, [&o] { return run_evaluate(o.evaluate); });
    commands.emplace_back(diff, [&o] { return run_diff(o.diff); });
}

// gain: an analysis of the acuity model alone, no scene or frame.
void add_analysis_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* gain = app.add_subcommand(
        "gain",
        "theoretical gain of foveated rendering for a display (Koskela P1 §4): 1 - integral of "
        "the eye's acuity V over the FOV / (the display's maximum c/deg * area), gaze at the FOV "
        "centre; without --fov-deg, P1's three cases next to the figures the sources quote");
    add_gain_options(*gain, o.gain);
    commands.emplace_back(gain, [&o] { return run_gain(o.gain); });
    CLI::App* density = app.add_subcommand(
        "density",
        "rays per pixel of a log-polar mode along the radius and the circle at each error "
        "ring's middle (Lund's mid_range_res), with the relative visual acuity: table, CSV, SVG");
    add_density_options(*density, o.density);
    commands.emplace_back(density, [&o] { return run_density(o.density); });
}

// denoise: the reference's BMFR on buffers another renderer wrote.
void add_denoise_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* denoise = add_group(app, "denoise", "denoise buffers written by another renderer");
    CLI::App* bmfr = denoise->add_subcommand(
        "bmfr",
        "BMFR (Koskela P2; docs/bmfr.md) on per-frame radiance, albedo, normal and world "
        "position buffers with per-frame camera matrices; writes every phase as a bundle");
    add_denoise_options(*bmfr, o.denoise);
    commands.emplace_back(bmfr, [&o] { return run_denoise(o.denoise); });
}

// sweep: run time against error over a grid of configurations (docs/sweeps.md).
void add_sweep_commands(CLI::App& app, Options& o, Commands& commands) {
    CLI::App* sweep = add_group(
        app, "sweep",
        "run time against error over a grid of scenes, modes, parameters, resolutions and gazes: "
        "plan, run (here, GNU parallel, Slurm or Kubernetes), merge");
    CLI::App* plan = sweep->add_subcommand(
        "plan", "expand a sweep file into jobs (OUT/plan.json), each one fovref evaluate run");
    add_sweep_plan_options(*plan, o.sweep);
    CLI::App* job = sweep->add_subcommand(
        "job", "run one job of a plan; skipped when its result is there for the same inputs");
    add_sweep_job_options(*job, o.sweep);
    CLI::App* run = sweep->add_subcommand(
        "run", "run every job as a separate single-threaded process, references first");
    add_sweep_run_options(*run, o.sweep);
    CLI::App* merge = sweep->add_subcommand(
        "merge", "collect the results into OUT/results.csv and OUT/results.json");
    add_sweep_merge_options(*merge, o.sweep);
    CLI::App* exporter = sweep->add_subcommand(
        "export",
        "write job lists and scripts for GNU parallel, a Slurm array or a Kubernetes "
        "Indexed Job");
    add_sweep_export_options(*exporter, o.sweep);
    CLI::App* report = sweep->add_subcommand(
        "report",
        "an HTML page (and SVG/PNG plots) of the merged results: Pareto fronts of time "
        "and rays against error per scene, ring-error curves, dominated configurations");
    add_sweep_report_options(*report, o.sweep);
    commands.emplace_back(report, [&o] { return run_sweep_report(o.sweep); });
    commands.emplace_back(plan, [&o] { return run_sweep_plan(o.sweep); });
    commands.emplace_back(job, [&o] { return run_sweep_job(o.sweep); });
    commands.emplace_back(run, [&o] { return run_sweep_run(o.sweep); });
    commands.emplace_back(merge, [&o] { return run_sweep_merge(o.sweep); });
    commands.emplace_back(exporter, [&o] { return run_sweep_export(o.sweep); });
}

// Steady state, as a renderer that keeps its buffers from frame to frame: glibc's malloc serves
// large blocks (image buffers) from mappings of their own, unmapped when freed, and trims the
// heap's top, so the next frame's buffers fault in and zero their pages again (about 16,000 page
// faults per 1280x720 frame of `basic`). The heap alone, and freed memory kept for the next
// frame: none after the first frame (docs/speed.md). For every command (the benches did it for
// themselves before). Changes no value; the process keeps its largest footprint until it exits.
void keep_freed_memory() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, INT_MAX);
#endif
}

}  // namespace

int main(int argc, char** argv) {
    keep_freed_memory();
    Options o;
    CLI::App app{app_description};
    app.set_version_flag("--version", std::function<std::string()>([] {
                             return "fovref " + fovref_version() + "\ndata   " + data_directory();
                         }));
    app.add_flag("-q,--quiet", o.quiet, "print only errors and failures, no progress bar");
    app.require_subcommand(1);
    app.fallthrough();  // global options (--quiet) may follow a subcommand
    app.failure_message([](const CLI::App*, const CLI::Error& e) {
        return std::string("fovref: ") + e.what() + " (see --help)\n";
    });
    Commands commands;
    add_scene_commands(app, o, commands);
    add_render_commands(app, o, commands);
    add_rays_commands(app, o, commands);
    add_bench_commands(app, o, commands);
    add_golden_commands(app, o, commands);
    add_check_commands(app, o, commands);
    add_analysis_commands(app, o, commands);
    add_denoise_commands(app, o, commands);
    app.footer(app_footer);  // after the commands: a subcommand copies its parent's footer
    add_sweep_commands(app, o, commands);
    CLI::App* stress = app.add_subcommand(
        "stress",
        "the numerical stress suite: extreme fields of view, screen sizes, gazes, parameters, "
        "scene scales and positions, non-finite inputs; per case finite, deterministic, error "
        "against binary64 (docs/stress.md); exit 1 when a case fails");
    add_stress_options(*stress, o.stress);
    commands.emplace_back(stress, [&o] { return run_stress(o.stress); });

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int code = app.exit(e);
        return code == 0 ? exit_ok : exit_usage;
    }
    share_quiet(o);
    try {
        for (const auto& [command, run] : commands)
            if (command->parsed()) return run();
    } catch (const Error& e) {
        std::fprintf(stderr, "fovref: %s\n", e.what());
        return exit_usage;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "fovref: unexpected error: %s\n", e.what());
        return exit_usage;
    }
    return exit_usage;
}
