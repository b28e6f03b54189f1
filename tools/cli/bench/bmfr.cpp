// `fovref bench bmfr`:
//   --input DIR  the phases' times on another renderer's buffers (denoise bmfr's IN_DIR), the
//          fastest of each over the frames after the first; nothing else.
//   cost   renders 1 + repeats frames of `pathtrace --param denoise=bmfr` at W x H along the
//          scene's camera path (30 frames per second); frame 0 (BVH build, no history) is not
//          timed; each stage's time is its fastest over the timed frames. BMFR = every bmfr_*
//          stage except bmfr_output (the linear copy of the result for `final`, not a phase).
//   error  frames 0 .. N-1 of the moving sequence at the error size; at frames K-1, 2K-1, ...
//          the noisy image (`radiance`) and the denoised one (`final`) against the reference of
//          the same frame at S samples per pixel, in display space (clamped, sRGB): RMSE and
//          SSIM (SPEC §10) of BMFR as SPEC §9, with bmfr_emission=separate and with
//          bmfr_block=64; the temporal error over all consecutive frames.
#include "tools/cli/bench/bmfr.h"

#include <algorithm>
#include <cstdio>
#include <map>

#include "ref/core/error.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/ssim.h"
#include "ref/modes/modes.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/commands/denoise.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

bool is_bmfr_phase(const std::string& stage) {
    return stage.rfind("bmfr_", 0) == 0 && stage != "bmfr_output";
}

// The fastest time of each stage that ran, over the frames handed to `add`.
struct StageTimes {
    std::vector<std::string> order;
    std::map<std::string, double> best;
    void add(const FrameResult& f) {
        for (const StageRun& run : f.stages) {
            if (!run.ran) continue;
            if (best.count(run.name) == 0) {
                order.push_back(run.name);
                best[run.name] = run.seconds;
            }
            best[run.name] = std::min(best[run.name], run.seconds);
        }
    }
    // Each stage, the BMFR phases' sum against the 720p targets (<= 300 ms, <= 1.25x the path
    // tracer's own time: primary visibility + paths) and the frame's sum; `previous_ms`: issue
    // 33's figure for the same storage (the first machine's, before its speed-ups), as a ratio.
    void print(double previous_ms = 0.0) const {
        double bmfr = 0.0, total = 0.0, tracer = 0.0;
        for (const std::string& name : order) {
            total += best.at(name);
            if (is_bmfr_phase(name)) bmfr += best.at(name);
            if (name == "primary_visibility" || name == "pathtrace") tracer += best.at(name);
            std::printf("    %-28s %9.1f ms\n", name.c_str(), 1e3 * best.at(name));
        }
        std::printf("    %-28s %9.1f ms  %s\n    %-28s %9.1f ms\n", "BMFR (all phases)", 1e3 * bmfr,
                    bmfr <= 0.3 ? "meets the target" : "misses the target", "frame", 1e3 * total);
        if (tracer > 0.0)
            std::printf("    %-28s %9.2fx  %s (path tracer %.1f ms; target <= 1.25x)\n",
                        "BMFR / path tracer", bmfr / tracer,
                        bmfr / tracer <= 1.25 ? "meets the target" : "misses the target",
                        1e3 * tracer);
        if (previous_ms > 0.0 && bmfr > 0.0)
            std::printf(
                "    %-28s %9.2fx  (issue 33's %.0f ms, measured on another machine before the "
                "fit's and the display's speed-ups)\n",
                "previous / now", previous_ms / (1e3 * bmfr), previous_ms);
        std::fflush(stdout);
    }
};

void print_cost(const Scene& scene, const BenchBmfrOptions& o, Progress& progress) {
    std::printf(
        "\ncost: %s %dx%d, one thread, fastest of %d frames after an untimed first, camera "
        "moving along the path; targets: BMFR <= 300 ms per 720p frame and <= 1.25x the path "
        "tracer's own time\n",
        o.scene.c_str(), o.width, o.height, o.repeats);
    for (const char* storage : {"half", "float"}) {
        RenderSettings s;
        s.width = o.width;
        s.height = o.height;
        s.frame_count = 1 + o.repeats;
        s.params = Params(
            std::map<std::string, std::string>{{"denoise", "bmfr"}, {"bmfr_storage", storage}});
        s.progress = [&](double f) { progress.update(f); };
        StageTimes times;
        render_each(&scene, "pathtrace", s, [&](FrameResult& f) {
            if (f.frame > 0) times.add(f);
        });
        progress.clear();
        std::printf("  bmfr_storage=%s\n", storage);
        times.print(std::string(storage) == "half" ? 540.0 : 380.0);
    }
}

// --input DIR: the phases on another renderer's buffers (`denoise bmfr`'s input), fastest over
// every frame after the first (which has no history); load_inputs (reading the files) is not a
// phase.
void print_external_cost(const BenchBmfrOptions& o, Progress& progress) {
    DenoiseOptions d;
    d.input = o.input;
    d.params = o.params;
    d.demodulated = o.demodulated;
    StageTimes times;
    const DenoiseRun run = denoise_each(
        d, {"final"}, [&](double f) { progress.update(f); },
        [&](FrameResult& f) {
            if (f.frame > 0) times.add(f);
        });
    progress.clear();
    if (times.order.empty())
        throw Error("bench bmfr --input " + o.input +
                    ": one frame only; the timed frames are the "
                    "ones after the first (it has no history)");
    std::printf(
        "\ncost: %s, %dx%d, frames 1 .. %d (fastest), one thread; target: BMFR <= 300 ms "
        "per 720p frame\n",
        o.input.c_str(), run.width, run.height, run.last);
    times.print();
}

// BMFR as SPEC §9 (the whole radiance demodulated), with the emission seen directly kept out of
// the fit (bmfr_emission=separate), and with P2's 64 x 64 blocks (bmfr_block=64)
struct Variant {
    const char* label;
    std::map<std::string, std::string> params;
    std::vector<Image> frames;  ///< final, display space
};

// Renders every variant's sequence with `s`; `noisy` gets the first one's 1-spp radiance.
void render_variants(const Scene& scene, RenderSettings s, std::vector<Variant>& variants,
                     std::vector<Image>& noisy, Progress& progress) {
    for (std::size_t v = 0; v < variants.size(); ++v) {
        std::map<std::string, std::string> params = variants[v].params;
        params["denoise"] = "bmfr";
        s.params = Params(params);
        render_each(&scene, "pathtrace", s, [&](FrameResult& f) {
            if (v == 0) noisy.push_back(to_display(f.find("radiance")->image));
            variants[v].frames.push_back(to_display(f.find("final")->image));
            progress.update(
                0.05 * (static_cast<double>(v) + static_cast<double>(f.frame + 1) / s.frame_count));
        });
    }
}

void print_errors(const Scene& scene, const BenchBmfrOptions& o, Progress& progress) {
    RenderSettings s;
    s.width = o.error_width;
    s.height = o.error_height;
    s.frame_count = o.frames;
    std::vector<Variant> variants = {{"BMFR", {}, {}},
                                     {"BMFR+E", {{"bmfr_emission", "separate"}}, {}},
                                     {"BMFR 64", {{"bmfr_block", "64"}}, {}}};
    std::vector<Image> noisy;
    render_variants(scene, s, variants, noisy, progress);
    progress.clear();
    std::printf(
        "\nerror: %s %dx%d, %d frames moving, every %dth frame against pathtrace-reference at "
        "%d spp (display space); BMFR as SPEC §9, BMFR+E with bmfr_emission=separate, BMFR 64 "
        "with bmfr_block=64 (P2 §6.1)\n",
        o.scene.c_str(), o.error_width, o.error_height, o.frames, o.every, o.reference_spp);
    std::printf("  %6s %11s", "frame", "RMSE noisy");
    for (const Variant& v : variants)
        std::printf(" %11s", ("RMSE " + std::string(v.label)).c_str());
    std::printf(" %11s", "SSIM noisy");
    for (const Variant& v : variants)
        std::printf(" %11s", ("SSIM " + std::string(v.label)).c_str());
    std::printf(" %14s\n", "ref. std. err.");
    const std::size_t columns = 2 * (1 + variants.size());
    std::vector<double> sums(columns, 0.0);
    int count = 0;
    std::vector<int> compared;
    for (int f = o.every - 1; f < o.frames; f += o.every) compared.push_back(f);
    for (std::size_t i = 0; i < compared.size(); ++i) {
        const int f = compared[i];
        RenderSettings r = s;
        r.first_frame = f;
        r.frame_count = 1;
        r.params =
            Params(std::map<std::string, std::string>{{"spp", std::to_string(o.reference_spp)}});
        r.progress = [&](double x) {
            progress.update(0.15 + 0.85 * (static_cast<double>(i) + x) /
                                       static_cast<double>(compared.size()));
        };
        Image reference;
        double standard_error = 0.0;
        render_each(&scene, "pathtrace-reference", r, [&](FrameResult& fr) {
            reference = to_display(fr.find("final")->image);
            standard_error =
                1e-9 * static_cast<double>(fr.counters.get("reference_mean_standard_error_e9"));
        });
        progress.clear();
        const auto index = static_cast<std::size_t>(f);
        // RMSE of the noisy image and each variant, then their SSIM
        std::vector<double> e = {std::sqrt(mse(reference, noisy[index]))};
        for (const Variant& v : variants) e.push_back(std::sqrt(mse(reference, v.frames[index])));
        e.push_back(ssim(luma(reference), luma(noisy[index])));
        for (const Variant& v : variants) e.push_back(ssim(luma(reference), luma(v.frames[index])));
        for (std::size_t k = 0; k < columns; ++k) sums[k] += e[k];
        ++count;
        std::printf("  %6d", f);
        for (std::size_t k = 0; k < columns; ++k)
            std::printf(k < columns / 2 ? " %11.5f" : " %11.4f", e[k]);
        std::printf(" %14.5f\n", standard_error);
        std::fflush(stdout);
    }
    if (count > 0) {
        std::printf("  %6s", "mean");
        for (std::size_t k = 0; k < columns; ++k)
            std::printf(k < columns / 2 ? " %11.5f" : " %11.4f", sums[k] / count);
        std::printf("\n");
    }
    std::printf("  temporal error (mean |luma(t) - luma(t-1)|): noisy %.5f", temporal_error(noisy));
    for (const Variant& v : variants) std::printf(", %s %.5f", v.label, temporal_error(v.frames));
    std::printf("\n");
}

}  // namespace

int run_bench_bmfr(const BenchBmfrOptions& o) {
    if (o.every > o.frames)
        throw Error("--every " + std::to_string(o.every) + " is more than --frames " +
                    std::to_string(o.frames) + ": no frame would be compared");
    Progress progress("bench bmfr", o.quiet);
    if (!o.input.empty()) {  // another renderer's buffers: the cost of the phases only
        std::printf("fovref bench bmfr: BMFR (SPEC §9) on the buffers of %s, one thread\n",
                    o.input.c_str());
        print_external_cost(o, progress);
        progress.finish();
        return 0;
    }
    const Scene scene = load_cli_scene(o.scene);
    std::printf("fovref bench bmfr: path tracing + BMFR (SPEC §8-9), one thread\n");
    if (!o.skip_cost) print_cost(scene, o, progress);
    if (!o.skip_error) print_errors(scene, o, progress);
    progress.finish();
    return 0;
}

}  // namespace fovref
