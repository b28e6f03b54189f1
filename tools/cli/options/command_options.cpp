// The options of the fovref commands (tools/cli/commands, and sweep report), registered on their
// subcommands. CLI11 is header-only and costs seconds of compile time per translation unit that
// includes it, so option registration is gathered into two files: this one and bench_options.cpp
// (the benchmarks). Each command's header declares its add_*_options function and documents its
// options struct; the comment above each group names the file with the command's run function.
#include <CLI/CLI.hpp>
#include <string>

#include "ref/analysis/gain.h"
#include "tools/cli/commands/denoise.h"
#include "tools/cli/commands/density.h"
#include "tools/cli/commands/diff/diff.h"
#include "tools/cli/commands/evaluate.h"
#include "tools/cli/commands/gain.h"
#include "tools/cli/commands/golden.h"
#include "tools/cli/commands/probe.h"
#include "tools/cli/commands/rays.h"
#include "tools/cli/commands/render.h"
#include "tools/cli/commands/scene.h"
#include "tools/cli/commands/stress.h"
#include "tools/cli/commands/sweep.h"
#include "tools/cli/common/cli_common.h"

namespace fovref {

namespace {

// The SCENE argument (required) of a command that takes a scene first, and the scene load options
// (add_scene_load_options: `with_camera` false for a command with a --camera of its own).
void add_scene_argument(CLI::App& c, std::string& scene, bool with_camera = true) {
    c.add_option("SCENE", scene, scene_option_help)->required();
    add_scene_load_options(c, with_camera);
}

}  // namespace

// fovref scene info|export (tools/cli/commands/scene.cpp)
void add_scene_info_options(CLI::App& c, SceneInfoOptions& o) {
    add_scene_argument(c, o.scene);
    c.add_flag("--json", o.json, "machine-readable output");
}

void add_scene_export_options(CLI::App& c, SceneExportOptions& o) {
    add_scene_argument(c, o.scene);
    c.add_option("DIR", o.directory, "output directory (created)")->required();
}

// fovref render (tools/cli/commands/render.cpp)
void add_render_options(CLI::App& c, RenderOptions& o) {
    add_scene_options(c, o.scene);
    c.add_option("--mode", o.mode, "render mode (see `fovref modes`)")->capture_default_str();
    add_screen_options(c, o.width, o.height, " in pixels");
    c.add_option("--frames", o.frames,
                 "number of frames N, or a range A..B of frame numbers (= --first-frame A, "
                 "B - A + 1 frames)")
        ->capture_default_str();
    c.add_option("--first-frame", o.first_frame,
                 "number of the first frame (seeds rand() and the Halton index, sets the "
                 "camera-path time): render frames of a sequence alone, bit-identical to the "
                 "sequence's; with TAA give --resume")
        ->check(CLI::Range(0, 100000))
        ->capture_default_str();
    c.add_option("--resume", o.resume,
                 "a --dump (or --out with --output all) bundle that holds frame F - 1 of the same "
                 "render: the state carried into frame F = the first frame (TAA history, age, "
                 "depth; BMFR's accumulations); for pathtrace-reference, a bundle of the same "
                 "frame whose sums the run continues up to spp");
    c.add_flag("--static-camera", o.static_camera,
               "keep the camera at the path's start for every frame (= --time-step 0): the "
               "static-camera sequence");
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
    c.add_flag("--scalar", o.scalar,
               "run every pass's scalar reference code, without its SIMD path (the same bits, "
               "slower): a debugger's breakpoint in a per-pixel function then stops at every "
               "pixel (`probe --debugger` adds it)");
}

// fovref rays trace|make (tools/cli/commands/rays.cpp)
void add_rays_trace_options(CLI::App& c, RaysTraceOptions& o) {
    add_scene_argument(c, o.scene, /*with_camera=*/false);
    c.add_option("RAYS", o.rays_path, "ray file: 8 x binary32 per ray (docs/rays.md)")->required();
    c.add_option("HITS", o.hits_path, "output: 16-byte hit records, or 4-byte occlusion flags")
        ->required();
    c.add_flag("--any-hit", o.any_hit, "occlusion queries (shadow rays) instead of closest hits");
    c.add_flag("--interleave", o.interleave,
               "closest hits with 16 rays' traversals interleaved: the same hits and counts, "
               "faster for incoherent rays over a large scene, slower for coherent rays or a "
               "small scene (docs/bvh.md, \"Interleaved queries\")");
    c.add_flag("--packets", o.packets,
               "with --any-hit: consecutive rays traced 8 at a time in AVX lanes, the same answers "
               "(the traversal counts follow the packets), faster for coherent rays such as a "
               "row of pixels' shadow rays (docs/bvh.md, \"Shadow-ray packets\")");
}

void add_rays_make_options(CLI::App& c, RaysMakeOptions& o) {
    add_scene_argument(c, o.scene, /*with_camera=*/false);
    c.add_option("RAYS", o.rays_path, "output ray file")->required();
    c.add_flag("--camera", o.camera, "primary rays through every pixel centre");
    c.add_option("--width", o.width, "with --camera")->capture_default_str();
    c.add_option("--height", o.height, "with --camera")->capture_default_str();
    c.add_option("--time", o.time, "camera-path time, with --camera")->capture_default_str();
    c.add_option("--random", o.random_count,
                 "N random rays: origins in the scene bounds, uniform "
                 "directions")
        ->check(CLI::Range(1u, 100000000u));
    c.add_option("--seed", o.seed, "seed of the random rays (the rand() frame)")
        ->capture_default_str();
}

// fovref rays cull (tools/cli/commands/rays_cull.cpp)
void add_rays_cull_options(CLI::App& c, RaysCullOptions& o) {
    add_scene_argument(c, o.scene, /*with_camera=*/false);
    c.add_option("OUT_DIR", o.out_dir,
                 "the directory written: manifest.json, triangles.bin, nodes.bin, tiles.bin "
                 "(and shadow_nodes.bin, shadow_tiles.bin)")
        ->required();
    c.add_option("--width", o.width, "screen width")->capture_default_str();
    c.add_option("--height", o.height, "screen height")->capture_default_str();
    c.add_option("--time", o.time, "camera-path time")->capture_default_str();
    c.add_option("--tile-size", o.tile_size, "tile edge in pixels")
        ->check(CLI::Range(1, 4096))
        ->capture_default_str();
    c.add_option("--test", o.test, "the frustum-box test: lund or exact")
        ->check(CLI::IsMember({"lund", "exact"}))
        ->capture_default_str();
    c.add_flag("--no-trim", o.no_trim, "keep inner nodes left without children");
    c.add_flag("--no-entry", o.no_entry, "start every tree at the BVH2's root");
    c.add_flag("--no-bridge", o.no_bridge, "keep nodes left with one child (an empty slot)");
    c.add_flag("--shadow", o.shadow,
               "also each tile's shadow frustum towards a point light (its apex): the shadow "
               "rays of the tile's pixel-centre primary hits");
    c.add_option("--light", o.light,
                 "with --shadow: the point light's index (default -1: the first point light)")
        ->check(CLI::Range(-1, 1 << 20));
}

// fovref golden, golden verify|update|export (tools/cli/commands/golden.cpp)
void add_golden_options(CLI::App& c, GoldenOptions& o) {
    c.add_option("--dir", o.dir, "golden directory (default: ./golden, else the source tree's)");
}

void add_golden_cases_options(CLI::App& c, GoldenCasesOptions& o) {
    c.add_option("--case", o.cases, "only these cases");
}

void add_golden_export_options(CLI::App& c, GoldenExportOptions& o) {
    c.add_option("CASE", o.case_name, "golden case name (see `fovref golden list`)")->required();
    c.add_option("DIR", o.directory, "output directory")->required();
    c.add_option("--width", o.width, "override the case's width")->check(CLI::Range(1, 16384));
    c.add_option("--height", o.height, "override the case's height")->check(CLI::Range(1, 16384));
    c.add_option("--frames", o.frames, "override the case's frame count")
        ->check(CLI::Range(1, 16384));
    c.add_option("--param", o.params,
                 "override or add a mode parameter of the case, key=value (repeatable; "
                 "e.g. fill_rule=gl)");
    c.add_flag("--with-scene", o.with_scene,
               "also write the scene into DIR/scene (OBJ + MTL + textures + scene.json; "
               "OBJ triangle k is primitive id k), for a GPU implementation to render");
    c.add_flag("--raw-copies", o.raw_copies,
               "also write every buffer of 2 or more than 3 channels (stored as EXR) as raw "
               "binary32, interleaved, top row first (f000_NAME.f32, the manifest's raw_file), "
               "for a client without an EXR reader");
    c.add_flag("--timings", o.timings,
               "record each stage's wall time per frame in the manifest (\"seconds\"), for "
               "comparing a port's pass times with the oracle's");
}

// fovref probe (tools/cli/commands/probe.cpp)
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
                 "each pass's per-pixel function where this pixel (or --texel) is computed, in "
                 "this frame (README: Debugging one pixel)")
        ->check(CLI::IsMember({"gdb", "lldb"}));
}

// fovref evaluate (tools/cli/commands/evaluate.cpp)
void add_evaluate_options(CLI::App& c, EvaluateOptions& o) {
    add_scene_options(c, o.scene)->required();
    c.add_option("--mode", o.modes,
                 "mode to evaluate, optionally with parameters: basic or basic:primary=raster "
                 "(repeatable, or comma-separated)")
        ->delimiter(',');
    c.add_option("--frames-dir", o.frame_dirs,
                 "evaluate already rendered frames: a directory with f000_final.pfm/.exr/.png, "
                 "... (e.g. a GPU implementation's output; repeatable)");
    c.add_option("--reference", o.reference_mode, "the reference mode")->capture_default_str();
    c.add_option("--reference-dir", o.reference_dir,
                 "read the reference frames from DIR when it holds them for these settings, "
                 "else render them and store them there (f000_final.pfm, ..., reference.json)");
    c.add_option("--param", o.params, "key=value for every mode that has the parameter");
    add_screen_options(c, o.width, o.height, "", 11);
    c.add_option("--frames", o.frames, "frames along the camera path")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    c.add_option("--repeats", o.repeats,
                 "render each mode N times: stage times are the medians (the images must be the "
                 "same bits every time)")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c.add_option("--every", o.every, "evaluate every k-th frame (Lund §5.3.4)")
        ->check(CLI::Range(1, 100000))
        ->capture_default_str();
    c.add_option("--time-start", o.time_start, "camera-path time of frame 0")
        ->capture_default_str();
    c.add_option("--time-step", o.time_step, "camera-path time between frames")
        ->capture_default_str();
    c.add_option("--gaze", o.gaze,
                 "gaze point X,Y in pixels, of the error ranges and of the foveated modes "
                 "(default: the centre)");
    add_ring_options(c, o.rings, o.max_range);
    c.add_flag("--linear", o.linear, "compare stored linear values (default: display space)");
    c.add_flag("--flip", o.flip, "also LDR-FLIP of every evaluated frame (display space)");
    c.add_option("--out", o.out_dir,
                 "output directory (rings.csv, frames.csv, summary.json, "
                 "rings.svg, heatmaps)")
        ->required();
}

// fovref diff (tools/cli/commands/diff/diff.cpp)
void add_diff_options(CLI::App& c, DiffOptions& o) {
    c.add_option("GOLDEN", o.golden, "golden bundle directory (manifest.json) or image file")
        ->required();
    c.add_option("CANDIDATE", o.candidate,
                 "directory of buffers named as in the manifest (f000_final.pfm or final.pfm, "
                 "...) or one image file")
        ->required();
    c.add_option("--profile", o.profile,
                 "tolerance profile: bit-exact (0 everywhere), gpu-raster (a correct GPU port "
                 "with a hardware rasterizer), gpu-rt (with GPU ray tracing); each covers every "
                 "buffer family (G-buffers, foveation buffers, filters, TAA, BMFR, Visual-Polar); "
                 "the tolerance file and --tolerance override it per buffer (docs/diff.md)")
        ->capture_default_str();
    c.add_option("--tolerance", o.tolerances,
                 "NAME:abs=X,rel=X,ulp=N,pixels=N,share=X; edge=SHARE,interior=N compare as "
                 "integers (ids, masks, counts); NAME is a buffer or a pattern ('lp_*', '*'), "
                 "which must match a buffer of the golden; repeatable");
    c.add_option("--tolerance-file", o.tolerance_file,
                 "JSON: {\"buffer\": {\"abs\": x, \"rel\": x, \"ulp\": n, "
                 "\"max_failing_pixels\": n, \"max_failing_share\": x, "
                 "\"edge_mismatch_share\": x, \"interior_mismatches\": n, \"integer\": b, "
                 "\"reason\": \"...\"}} (keys: buffers or patterns)");
    c.add_option("--require", o.require,
                 "'all' or a comma-separated list of buffer names or patterns ('bmfr_*') that "
                 "must be in the candidate (a missing one fails)");
    c.add_flag("--no-id-mask", o.no_id_mask,
               "compare depth, position, ... everywhere, not only where the frame's id buffers "
               "agree");
    c.add_option("--json", o.json_path, "write the JSON report to FILE ('-' = stdout)");
    c.add_option("--html", o.html_dir, "write a self-contained HTML report to DIR/index.html");
    c.add_option("--buffer", o.buffer,
                 "candidate is one file: the golden buffer it is compared with (default final)");
    c.add_option("--frame", o.frame, "compare only this frame")->check(CLI::Range(0, 1000000));
    c.add_option("--threshold", o.threshold,
                 "count the pixels whose error exceeds this absolute value (default: count the "
                 "pixels out of the buffer's tolerance)");
    c.add_option("--margin", o.margin,
                 "leave out the value buffers' pixels within N of the border (a port with other "
                 "border handling, e.g. BMFR's mirrored blocks); the reports say how many")
        ->check(CLI::Range(0, 100000));
    c.add_option("--worst", o.worst, "worst pixels to list per buffer")
        ->check(CLI::Range(0, 1000))
        ->capture_default_str();
    c.add_option("--raw-size", o.raw_size,
                 "size of raw binary32 files WxH[xC] (default: the golden buffer's)");
    c.add_flag("--raw-planar", o.raw_planar, "raw files store channel planes, not interleaved");
    c.add_flag("--raw-bottom-up", o.raw_bottom_up, "raw files store the bottom row first");
    c.add_flag("--raw-big-endian", o.raw_big_endian, "raw files are big-endian");
    c.add_flag("--png-linear", o.png_linear,
               "use PNG values / 255 as they are (default: sRGB-decode colour buffers)");
    c.add_option("--gaze", o.gaze,
                 "gaze point X,Y in pixels for the error ranges (default: "
                 "the centre)");
    add_ring_options(c, o.rings, o.max_range);
    c.add_flag("--flip", o.flip,
               "also LDR-FLIP (NVlabs v1.x) of colour buffers, in display space (about 0.25 s "
               "per 1280x720 pair); pixels per degree from the display model, else NVlabs's "
               "default observer (67.02)");
    c.add_option("--distance-px", o.distance_px,
                 "viewing distance in pixels (default: the bundle's display model, else a 60 "
                 "degree vertical field of view for the error ranges and NVlabs's default "
                 "observer for --flip)")
        ->check(CLI::Range(1e-3, 1e9));
}

// fovref gain (tools/cli/commands/gain.cpp)
void add_gain_options(CLI::App& c, GainOptions& o) {
    c.add_option("--shape", o.shape,
                 "disc or ellipse (default: disc for one --fov-deg value, ellipse for two)")
        ->check(CLI::IsMember({"disc", "ellipse"}));
    c.add_option("--fov-deg", o.fov_deg,
                 "the FOV in degrees (planar): W, a disc's diameter, or W,H, an ellipse's full "
                 "horizontal and vertical axes; without it, P1's three cases")
        ->delimiter(',');
    c.add_option_function<double>(
        "--max-cpd",
        [&o](const double& v) {
            o.max_cpd = v;
            o.max_cpd_given = true;
        },
        "the display's maximum c/deg: V is clamped to it and the gain measured against it "
        "[60]");
    c.add_option("--angle-steps", o.angle_steps,
                 "quadrature nodes per quadrant for an ellipse (docs/gain.md)")
        ->capture_default_str()
        ->check(CLI::Range(1, gain_max_angle_steps));
    c.add_flag("--json", o.json, "machine-readable output");
    c.footer(
        "Examples:\n"
        "  fovref gain                               P1's three cases (93.8%, 70.3%, 94.6%)\n"
        "  fovref gain --fov-deg 160,135             an ellipse, full axes, at 60 c/deg\n"
        "  fovref gain --fov-deg 110 --max-cpd 15.3  a disc of 110 deg diameter (HTC Vive)\n"
        "Model: " +
        std::string(gain_model_line) + ".\nNote: " + gain_density_note +
        ". docs/gain.md has the details.");
}

// fovref density (tools/cli/commands/density.cpp)
void add_density_options(CLI::App& c, DensityOptions& o) {
    o.scene = "cornell";
    o.width = 1280;
    o.height = 720;
    c.add_option("mode", o.mode, "a log-polar mode: fov, kfov, cfov, ckfov, kfr")->required();
    add_scene_options(c, o.scene, "scene whose camera and display model give d_px")
        ->capture_default_str();
    add_screen_options(c, o.width, o.height);
    c.add_option("--param", o.params, "mode parameter key=value (repeatable)");
    add_gaze_option(c, o);
    add_ring_options(c, o.rings, o.max_range);
    c.add_option("--out", o.out_dir, "write density.csv and density.svg here");
}

// fovref denoise bmfr (tools/cli/commands/denoise.cpp)
void add_denoise_options(CLI::App& c, DenoiseOptions& o) {
    c.add_option("IN_DIR", o.input,
                 "per-frame buffers fNNN_radiance, fNNN_gbuffer_albedo, "
                 "fNNN_gbuffer_shading_normal, fNNN_gbuffer_world_position (.pfm or .exr; "
                 "fNNN_emission with bmfr_emission=separate) and cameras.json (per frame "
                 "\"view_projection\" or \"camera\", optionally \"pixel_offset\": [x, y]; at the "
                 "top optionally \"position_limit_squared\", \"normal_limit_squared\"), or a "
                 "fovref bundle's manifest.json (docs/bmfr.md)")
        ->required();
    c.add_option("OUT_DIR", o.output,
                 "the bundle written (every phase of every frame unless --output/--frames say)")
        ->required();
    c.add_option("--param", o.params,
                 "bmfr_storage=half|float, bmfr_position_limit_squared=V, "
                 "bmfr_normal_limit_squared=V, bmfr_emission=separate|include, "
                 "bmfr_block=32|64, bmfr_noise_hash=jenkins|wang, bmfr_sums=binary64|workgroup, "
                 "bmfr_gamma=0.454545|1/2.2, bmfr_remodulate=floor|albedo, "
                 "bmfr_behind_camera=reject|project (`fovref modes`; docs/bmfr.md)");
    c.add_flag("--demodulated", o.demodulated,
               "fNNN_radiance already holds colour / max(albedo, 0.01), as the BMFR authors' "
               "input does: it is taken as the illumination (not divided again)");
    c.add_option("--frames", o.frames,
                 "N (frames 0 .. N-1) or A..B (frames A .. B written; 0 .. B run, BMFR's history "
                 "needs them); default: every frame of cameras.json");
    c.add_option("--output", o.outputs,
                 "comma-separated buffers to write (e.g. final,bmfr_fitted), or all (default)")
        ->delimiter(',');
    c.add_flag("--previews", o.previews, "also a PNG preview of every buffer written");
}

// fovref sweep plan|job|run|merge|export (tools/cli/commands/sweep.cpp)
void add_sweep_plan_options(CLI::App& c, SweepOptions& o) {
    c.add_option("FILE", o.file, "the sweep file (JSON; docs/sweeps.md)")->required();
    c.add_option("OUT", o.out, "the sweep directory (plan.json, jobs.txt, results/)")->required();
}

void add_sweep_job_options(CLI::App& c, SweepOptions& o) {
    c.add_option("OUT", o.out, "the sweep directory")->required();
    c.add_option("INDEX", o.job, "the job's index in plan.json (0-based)")
        ->required()
        ->check(CLI::NonNegativeNumber);
}

void add_sweep_run_options(CLI::App& c, SweepOptions& o) {
    c.add_option("OUT", o.out, "the sweep directory")->required();
    c.add_option("--jobs,-j", o.jobs, "jobs at a time (each single-threaded)")
        ->check(CLI::Range(1, 1024))
        ->capture_default_str();
}

void add_sweep_merge_options(CLI::App& c, SweepOptions& o) {
    c.add_option("OUT", o.out, "the sweep directory")->required();
}

void add_sweep_export_options(CLI::App& c, SweepOptions& o) {
    c.add_option("OUT", o.out, "the sweep directory")->required();
    c.add_option("--format", o.format, "parallel (GNU parallel), slurm or k8s")
        ->required()
        ->check(CLI::IsMember({"parallel", "slurm", "k8s"}));
    c.add_option("--fovref", o.fovref, "the fovref command where the jobs run")
        ->capture_default_str();
    c.add_option("--image", o.image, "k8s: the container image holding fovref")
        ->capture_default_str();
}

// fovref sweep report (tools/cli/report/sweep_report.cpp)
void add_sweep_report_options(CLI::App& c, SweepOptions& o) {
    c.add_option("OUT", o.out, "the sweep directory (after fovref sweep merge)")->required();
    c.add_option("--html", o.html, "output directory (index.html, plots/*.svg, *.png)")->required();
    c.add_option("--metric", o.metric, "the error of the Pareto fronts")
        ->check(CLI::IsMember({"psnr", "ssim", "flip", "temporal"}))
        ->capture_default_str();
}

// fovref stress (tools/cli/commands/stress.cpp)
void add_stress_options(CLI::App& c, StressOptions& o) {
    c.add_flag("--fast", o.fast, "only the fast cases (what CI runs, a few seconds)");
    c.add_option("--case", o.filter, "only the groups whose name contains this text");
    c.add_option("--json", o.json, "also write every row as JSON to this file");
}

}  // namespace fovref
