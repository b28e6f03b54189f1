// `fovref bench visual-polar` (Koskela P5: path tracing + BMFR in Visual-Polar space against
// screen space):
//   cost   for each size (1280x1440, one eye of P5's HMD, and 1280x720; or the one --width x
//          --height), renders 1 + repeats frames of `pathtrace --param denoise=bmfr` (screen
//          space), of `visual-polar` and of `log-polar-pathtrace` (P5's log-polar method; BMFR
//          on by default, gaze at the screen centre or along --gaze-track, each mode's default
//          parameters) along the scene's camera path (30 frames per second);
//          frame 0 (BVH build, no history) is not timed; each stage's time is its fastest over
//          the timed frames. Groups: path tracing = primary_visibility + pathtrace (screen),
//          vp_trace + vp_pathtrace (VP) or lp_trace + lp_pathtrace (LP); BMFR = every bmfr_* stage
//          except bmfr_output (a copy, not a phase); rest = every other stage (bmfr_output, and
//          VP's resolve and blur ramp); total = the sum of them all. Samples per frame: W x H
//          primary paths in screen space, the counter texels_traced for VP (its buffer's texels
//          less the clipped ones, outside the screen-shaped region, and those off the screen).
//          Speed-ups are screen / VP per group, next to P5's ~2.5x for path tracing and BMFR, and
//          the target (VP path tracing + BMFR >= 2x faster than screen space at 1280x1440)
//          is judged on both the path tracing + BMFR stages and the whole frame.
//   error  frames 0 .. N-1 of the moving sequence at the error size (default 320x180) with
//          screen-space BMFR, visual-polar and `linear-falloff --param denoise=bmfr`; at frames
//          K-1, 2K-1, ... each one's `final` against the pathtrace-reference of the same frame at
//          S samples per pixel, in display space (clamped, sRGB): RMSE and SSIM of luma (SPEC
//          §10), and the RMSE of each of R rings of equal eccentricity width around the screen
//          centre (ref/metrics/rings.h, the distance from the scene's display model), means over
//          the compared frames; the temporal error over all consecutive frames. Each method runs
//          with its default sample budget (printed: screen W x H, VP texels_traced, linear-falloff
//          pixels_sampled), and linear-falloff once more at VP's budget (P5's comparison): P_p
//          such that the expected count sum L(e) over the pixels (linear in P_p) equals VP's mean
//          texels_traced; P5 §4.3's log-polar method (log-polar-pathtrace) and visual-polar with
//          its buffer scaled to LP's texels_traced. VP's final image
//          includes its blur ramp, a deliberate loss of peripheral detail the reference lacks.
#include "tools/cli/bench/visual_polar.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "ref/core/error.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/rings.h"
#include "ref/metrics/ssim.h"
#include "ref/modes/modes.h"
#include "ref/scene/camera.h"
#include "ref/scene/scene.h"
#include "ref/scene/scene_file.h"
#include "ref/visual_polar/map.h"
#include "ref/visual_polar/sparse_sampling.h"
#include "tools/cli/bench/bench_util.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

using ParamMap = std::map<std::string, std::string>;

struct Size {
    int width = 0, height = 0;
    double pixels() const { return static_cast<double>(width) * height; }
};

bool is_bmfr_phase(const std::string& stage) {
    return stage.rfind("bmfr_", 0) == 0 && stage != "bmfr_output";
}

bool is_trace_stage(const std::string& stage) {
    return stage == "primary_visibility" || stage == "pathtrace" || stage == "vp_trace" ||
           stage == "vp_pathtrace" || stage == "lp_trace" || stage == "lp_pathtrace";
}

// One method at one size: each stage's fastest time over the timed frames, pipeline order, the
// group sums and the counters of the last frame.
struct MethodCost {
    std::vector<std::string> order;
    std::map<std::string, double> best;
    Counters counters;
    double trace = 0.0, bmfr = 0.0, rest = 0.0, total = 0.0;
};

/// The group sums of c's stage times (trace, BMFR, the rest, total).
void sum_groups(MethodCost& c) {
    c.trace = c.bmfr = c.rest = c.total = 0.0;
    for (const std::string& name : c.order) {
        const double t = c.best[name];
        c.total += t;
        (is_bmfr_phase(name) ? c.bmfr : is_trace_stage(name) ? c.trace : c.rest) += t;
    }
}

MethodCost time_method(const Scene& scene, const std::string& mode, const ParamMap& params,
                       Size size, int repeats, const std::function<void(double)>& progress) {
    RenderSettings s;
    s.width = size.width;
    s.height = size.height;
    s.frame_count = 1 + repeats;
    s.params = Params(params);
    s.progress = progress;
    MethodCost c;
    render_each(&scene, mode, s, [&](FrameResult& f) {
        if (f.frame == 0) return;
        for (const StageRun& run : f.stages) {
            if (!run.ran) continue;
            if (c.best.count(run.name) == 0) {
                c.order.push_back(run.name);
                c.best[run.name] = run.seconds;
            }
            c.best[run.name] = std::min(c.best[run.name], run.seconds);
        }
        c.counters = f.counters;
    });
    sum_groups(c);
    return c;
}

/// The fastest of two rounds of one method: each stage's minimum, the groups summed again.
MethodCost fastest(MethodCost a, const MethodCost& b) {
    for (auto& [name, seconds] : a.best)
        if (b.best.count(name) != 0) seconds = std::min(seconds, b.best.at(name));
    sum_groups(a);
    return a;
}

std::string stage_list(const MethodCost& c) {
    std::string out;
    char item[96];
    for (const std::string& name : c.order) {
        std::snprintf(item, sizeof item, "%s%s %.1f", out.empty() ? "" : ", ", name.c_str(),
                      1e3 * c.best.at(name));
        out += item;
    }
    return out;
}

double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

/// One size's table: each method's samples, buffer and times, the speed-ups, every stage, and
/// the target (judged at 1280x1440 only).
void print_size_cost(const Size& size, const MethodCost& screen, const MethodCost& vp,
                     const MethodCost& lp, bool static_gaze) {
    const double pixels = size.pixels();
    const auto buffer_w = vp.counters.get("buffer_width");
    const auto buffer_h = vp.counters.get("buffer_height");
    const auto traced = vp.counters.get("texels_traced");
    const double buffer_texels = static_cast<double>(buffer_w) * static_cast<double>(buffer_h);
    const std::string buffer = std::to_string(buffer_w) + "x" + std::to_string(buffer_h);
    char clipped[32];
    std::snprintf(
        clipped, sizeof clipped, "%.1f%%",
        100.0 * ratio(static_cast<double>(vp.counters.get("texels_clipped")), buffer_texels));

    std::printf("  %dx%d (%.0f pixels)\n", size.width, size.height, pixels);
    std::printf("    %-22s %13s %7s %10s %8s %10s %12s %9s %9s %9s\n", "method", "samples/frame",
                "of WxH", "buffer", "clipped", "off-screen", "path tracing", "BMFR", "rest",
                "total");
    std::printf("    %-22s %13.0f %6.1f%% %10s %8s %10s %12.1f %9.1f %9.1f %9.1f\n",
                "screen space + BMFR", pixels, 100.0, "-", "-", "-", 1e3 * screen.trace,
                1e3 * screen.bmfr, 1e3 * screen.rest, 1e3 * screen.total);
    std::printf("    %-22s %13lld %6.1f%% %10s %8s %10lld %12.1f %9.1f %9.1f %9.1f\n",
                "Visual-Polar + BMFR", static_cast<long long>(traced),
                100.0 * static_cast<double>(traced) / pixels, buffer.c_str(), clipped,
                static_cast<long long>(vp.counters.get("texels_off_screen")), 1e3 * vp.trace,
                1e3 * vp.bmfr, 1e3 * vp.rest, 1e3 * vp.total);
    const auto lp_traced = lp.counters.get("texels_traced");
    const std::string lp_buffer = std::to_string(lp.counters.get("buffer_width")) + "x" +
                                  std::to_string(lp.counters.get("buffer_height"));
    std::printf("    %-22s %13lld %6.1f%% %10s %8s %10lld %12.1f %9.1f %9.1f %9.1f\n",
                "log-polar + BMFR", static_cast<long long>(lp_traced),
                100.0 * static_cast<double>(lp_traced) / pixels, lp_buffer.c_str(), "-",
                static_cast<long long>(lp.counters.get("texels_off_screen")), 1e3 * lp.trace,
                1e3 * lp.bmfr, 1e3 * lp.rest, 1e3 * lp.total);
    std::printf("    %-22s %13.2fx %7s %10s %8s %10s %11.2fx %8.2fx %9s %8.2fx\n",
                "speed-up screen / VP", ratio(pixels, static_cast<double>(traced)), "", "", "", "",
                ratio(screen.trace, vp.trace), ratio(screen.bmfr, vp.bmfr), "-",
                ratio(screen.total, vp.total));
    std::printf("    %-22s %13s %7s %10s %8s %10s %11.1fx %8.1fx\n", "P5 (reported)", "", "", "",
                "", "", 2.5, 2.5);
    std::printf("    stages, screen space: %s\n", stage_list(screen).c_str());
    std::printf("    stages, Visual-Polar: %s\n", stage_list(vp).c_str());
    std::printf("    stages, log-polar: %s\n", stage_list(lp).c_str());
    const double stages = ratio(screen.trace + screen.bmfr, vp.trace + vp.bmfr);
    const double whole = ratio(screen.total, vp.total);
    const bool target_size = size.width == 1280 && size.height == 1440;
    std::printf(
        "    target (issue): Visual-Polar path tracing + BMFR >= 2x faster than screen space "
        "at 1280x1440, static and moving gaze%s:\n      path tracing + BMFR stages %.2fx "
        "(%s); whole frame, VP's resolve and blur included, %.2fx (%s)\n",
        target_size ? (static_gaze ? " (this run: static)" : " (this run: moving)")
                    : " (this size is not the target's; for information)",
        stages, stages >= 2.0 ? "met" : "not met", whole, whole >= 2.0 ? "met" : "not met");
}

void print_cost(const Scene& scene, const BenchVisualPolarOptions& o,
                const std::vector<Size>& sizes) {
    Progress progress("bench visual-polar (cost)", o.quiet);
    const std::string gaze =
        o.gaze_track.empty() ? "gaze at the screen centre" : "gaze moving along " + o.gaze_track;
    std::printf(
        "\ncost: %s, one thread, fastest of %d frames after an untimed first%s, camera moving "
        "along the path, %s; times in ms per frame\n",
        o.scene.c_str(), o.repeats * o.rounds,
        rounds_note(o.rounds, " (", " rounds, the methods in turn)").c_str(), gaze.c_str());
    double all_pixels = 0.0;
    for (const Size& size : sizes) all_pixels += size.pixels();
    double done = 0.0;
    for (const Size& size : sizes) {
        const double parts = 3.0 * o.rounds;
        const auto part = [&](double offset) {
            return [&, offset](double f) {
                progress.update((done + size.pixels() * (offset + f) / parts) / all_pixels);
            };
        };
        ParamMap gaze_params;
        if (!o.gaze_track.empty()) gaze_params["gaze_track"] = o.gaze_track;
        // The three methods in turn, once per round; each stage's fastest over the rounds
        MethodCost screen, vp, lp;
        for (int round = 0; round < o.rounds; ++round) {
            const double at = 3.0 * round;
            const MethodCost s =
                time_method(scene, "pathtrace", {{"denoise", "bmfr"}}, size, o.repeats, part(at));
            const MethodCost v =
                time_method(scene, "visual-polar", gaze_params, size, o.repeats, part(at + 1.0));
            const MethodCost l = time_method(scene, "log-polar-pathtrace", gaze_params, size,
                                             o.repeats, part(at + 2.0));
            screen = round == 0 ? s : fastest(screen, s);
            vp = round == 0 ? v : fastest(vp, v);
            lp = round == 0 ? l : fastest(lp, l);
        }
        done += size.pixels();
        progress.clear();

        print_size_cost(size, screen, vp, lp, o.gaze_track.empty());
        std::fflush(stdout);
    }
    progress.finish();
}

struct Method {
    const char* label;  ///< column label
    const char* name;   ///< full name
    const char* mode;
    ParamMap params;
    const char* samples;  ///< the counter of samples per frame; "" = W x H
    /// At VP's sample budget: linear fall-off with falloff_min solved, or (`reduced`) the screen
    /// space path tracer at a resolution of VP's samples, upscaled bilinearly to W x H
    bool equal_budget = false;
    bool reduced = false;
    /// Visual-Polar at LP's budget (P5 §4.3: as many texels as the log-polar method): the
    /// preset's buffer scaled by sqrt(LP's samples / VP's)
    bool vp_at_lp = false;
};

std::vector<Method> error_methods() {
    return {
        {"screen",
         "screen space + BMFR (pathtrace denoise=bmfr)",
         "pathtrace",
         {{"denoise", "bmfr"}},
         ""},
        {"VP", "Visual-Polar + BMFR (visual-polar)", "visual-polar", {}, "texels_traced"},
        {"LF",
         "linear-falloff + BMFR (linear-falloff denoise=bmfr)",
         "linear-falloff",
         {{"denoise", "bmfr"}},
         "pixels_sampled"},
        // P_p set below so that the expected samples equal VP's (P5: equal sample budgets)
        {"LF=VP",
         "linear-falloff + BMFR at VP's budget (falloff_min solved)",
         "linear-falloff",
         {{"denoise", "bmfr"}},
         "pixels_sampled",
         true},
        {"LFb=VP",
         "linear-falloff + BMFR + P5's blur ramp at VP's budget",
         "linear-falloff",
         {{"denoise", "bmfr"}, {"blur", "on"}},
         "pixels_sampled",
         true},
        {"Cart=VP",
         "screen space + BMFR at VP's budget (fewer pixels, bilinear up)",
         "pathtrace",
         {{"denoise", "bmfr"}},
         "",
         true,
         true},
        // P5 §4.3's log-polar method (Meng's sigma = 1.8, alpha = 4), and Visual-Polar given as
        // many texels, as P5 did
        {"LP",
         "log-polar + BMFR (log-polar-pathtrace)",
         "log-polar-pathtrace",
         {},
         "texels_traced"},
        {"VP=LP",
         "Visual-Polar + BMFR at LP's budget (buffer scaled)",
         "visual-polar",
         {},
         "texels_traced",
         false,
         false,
         true},
    };
}

// `image` (w x h) upscaled to W x H bilinearly: pixel centres at + 1/2, the source point
// ((x + 1/2) w / W - 1/2, (y + 1/2) h / H - 1/2) clamped to the source's pixel centres.
Image upscale_bilinear(const Image& image, int width, int height) {
    Image out(width, height, image.channels);
    const auto source = [](int x, int to, int from) {
        const double s = (x + 0.5) * from / to - 0.5;
        return std::clamp(s, 0.0, static_cast<double>(from - 1));
    };
    for (int y = 0; y < height; ++y) {
        const double sy = source(y, height, image.height);
        const int y0 = static_cast<int>(sy), y1 = std::min(y0 + 1, image.height - 1);
        const double fy = sy - y0;
        for (int x = 0; x < width; ++x) {
            const double sx = source(x, width, image.width);
            const int x0 = static_cast<int>(sx), x1 = std::min(x0 + 1, image.width - 1);
            const double fx = sx - x0;
            for (int c = 0; c < image.channels; ++c) {
                const double top = image.at(x0, y0, c) * (1 - fx) + image.at(x1, y0, c) * fx;
                const double bottom = image.at(x0, y1, c) * (1 - fx) + image.at(x1, y1, c) * fx;
                out.at(x, y, c) = static_cast<float>(top * (1 - fy) + bottom * fy);
            }
        }
    }
    return out;
}

// P_p of linear fall-off whose expected samples equal `samples` (E[samples] = A + B P_p: L is
// linear in P_p), clamped to [0, 1].
double equal_budget_probability(const Scene& scene, Size size, double samples) {
    const float d_px = display_distance_px(scene.display, size.width, size.height,
                                           camera_at(scene, 0.0f).vfov_deg);
    const glm::vec2 centre{static_cast<float>(size.width) * 0.5f,
                           static_cast<float>(size.height) * 0.5f};
    LinearFalloff falloff;
    falloff.periphery_probability = 0.0f;
    const double a = linear_falloff_expected(falloff, size.width, size.height, centre,
                                             EccentricityModel{true, d_px});
    falloff.periphery_probability = 1.0f;
    const double b = linear_falloff_expected(falloff, size.width, size.height, centre,
                                             EccentricityModel{true, d_px}) -
                     a;
    return std::clamp((samples - a) / b, 0.0, 1.0);
}

// Every method's frames in display space and its samples per frame.
struct MethodRuns {
    std::vector<std::vector<Image>> finals;
    std::vector<double> samples;
    double periphery_probability = 0.0;  ///< LF=VP's P_p
    Size reduced{0, 0};                  ///< Cart=VP's screen
    Size vp_buffer{0, 0};                ///< VP=LP's buffer
};

MethodRuns render_methods(const Scene& scene, const RenderSettings& s, Size size,
                          std::vector<Method>& methods, Progress& progress, double units) {
    MethodRuns runs;
    runs.finals.resize(methods.size());
    runs.samples.assign(methods.size(), 0.0);
    for (std::size_t m = 0; m < methods.size(); ++m) {
        RenderSettings r = s;
        if (methods[m].equal_budget && !methods[m].reduced) {
            runs.periphery_probability = equal_budget_probability(scene, size, runs.samples[1]);
            char value[32];
            std::snprintf(value, sizeof value, "%.6f", runs.periphery_probability);
            methods[m].params["falloff_min"] = value;
        } else if (methods[m].vp_at_lp) {
            // the preset's buffer (round(W / 1.5) x round(H / 1.5)) scaled so that VP traces
            // about as many texels as LP (index 6) did
            const glm::ivec2 preset = visual_polar_buffer_size(size.width, size.height);
            const double scale = std::sqrt(runs.samples[6] / runs.samples[1]);
            runs.vp_buffer = {std::max(8, static_cast<int>(std::lround(preset.x * scale))),
                              std::max(8, static_cast<int>(std::lround(preset.y * scale)))};
            methods[m].params["buffer_width"] = std::to_string(runs.vp_buffer.width);
            methods[m].params["buffer_height"] = std::to_string(runs.vp_buffer.height);
        } else if (methods[m].reduced) {
            // W' x H' = VP's samples, the screen's aspect kept (to a pixel)
            const double scale = std::sqrt(runs.samples[1] / size.pixels());
            r.width = std::max(16, static_cast<int>(std::lround(size.width * scale)));
            r.height = std::max(16, static_cast<int>(std::lround(size.height * scale)));
            runs.reduced = {r.width, r.height};
        }
        r.params = Params(methods[m].params);
        render_each(&scene, methods[m].mode, r, [&](FrameResult& f) {
            const Image& final_image = f.find("final")->image;
            runs.finals[m].push_back(to_display(
                methods[m].reduced ? upscale_bilinear(final_image, size.width, size.height)
                                   : final_image));
            runs.samples[m] += *methods[m].samples == '\0'
                                   ? static_cast<double>(r.width) * r.height
                                   : static_cast<double>(f.counters.get(methods[m].samples));
            progress.update((static_cast<double>(m) * s.frame_count + f.frame + 1) / units);
        });
        runs.samples[m] /= s.frame_count;
    }
    return runs;
}

void print_budgets(const BenchVisualPolarOptions& o, Size size, float distance,
                   const std::vector<Method>& methods, const MethodRuns& runs) {
    std::printf(
        "\nerror: %s %dx%d, %d frames moving, every %dth frame against pathtrace-reference at %d "
        "spp (display space); gaze at the screen centre, display distance %.1f px\n",
        o.scene.c_str(), size.width, size.height, o.frames, o.every, o.reference_spp, distance);
    const std::vector<double>& samples = runs.samples;
    for (std::size_t m = 0; m < methods.size(); ++m)
        std::printf("  %-7s %-58s %9.0f samples/frame (%5.1f%% of WxH)\n", methods[m].label,
                    methods[m].name, samples[m], 100.0 * samples[m] / size.pixels());
    std::printf(
        "  budgets: VP traces %.2fx the samples of screen space; linear-falloff with its defaults "
        "%.2fx; LF=VP is linear-falloff with P_p = %.4f, so that its expected samples equal VP's "
        "(P5's comparison at equal sample budget): measured %.3fx VP's (LFb=VP the same with the "
        "blur ramp); Cart=VP renders %dx%d (%.3fx VP's samples) and upscales bilinearly; LP "
        "traces %.2fx VP's samples, and VP=LP is visual-polar with a %dx%d buffer: %.3fx LP's "
        "(P5 §4.3 gave Visual-Polar the log-polar method's texel count)\n",
        samples[1] / samples[0], samples[2] / samples[0], runs.periphery_probability,
        samples[3] / samples[1], runs.reduced.width, runs.reduced.height, samples[5] / samples[1],
        samples[6] / samples[1], runs.vp_buffer.width, runs.vp_buffer.height,
        samples[7] / samples[6]);
}

// The errors summed over the compared frames, per method (and per ring).
struct ErrorSums {
    std::vector<double> rmse, ssim;
    std::vector<std::vector<double>> rings;
    std::vector<std::int64_t> ring_pixels;
};

// Frame f of every method against the reference: a row of RMSE and SSIM, added to the sums.
void compare_frame(int f, const Image& reference, double standard_error, const MethodRuns& runs,
                   const RingLayout& layout, ErrorSums& sums) {
    const std::size_t m_count = runs.finals.size();
    const Image reference_luma = luma(reference);
    std::vector<double> rmse(m_count), ssim_value(m_count);
    for (std::size_t m = 0; m < m_count; ++m) {
        const Image& image = runs.finals[m][static_cast<std::size_t>(f)];
        rmse[m] = std::sqrt(mse(reference, image));
        ssim_value[m] = ssim(reference_luma, luma(image));
        sums.rmse[m] += rmse[m];
        sums.ssim[m] += ssim_value[m];
        for (const RingStats& ring : ring_errors(reference, image, layout, nullptr)) {
            const auto k = static_cast<std::size_t>(ring.ring);
            sums.rings[m][k] += ring.rmse;
            sums.ring_pixels[k] = ring.pixels;
        }
    }
    std::printf("  %6d", f);
    for (std::size_t m = 0; m < m_count; ++m) std::printf(" %12.5f", rmse[m]);
    for (std::size_t m = 0; m < m_count; ++m) std::printf(" %12.4f", ssim_value[m]);
    std::printf(" %14.5f\n", standard_error);
    std::fflush(stdout);
}

void print_ring_table(const BenchVisualPolarOptions& o, const RingLayout& layout,
                      const std::vector<Method>& methods, const ErrorSums& sums, double n) {
    std::printf(
        "  RMSE per ring (mean over the compared frames): %d rings of %.2f deg around the gaze, "
        "out to the farthest corner (%.2f deg)\n",
        o.rings, layout.ring_width_deg, layout.outer_deg);
    std::printf("  %6s %17s %9s", "ring", "eccentricity", "pixels");
    for (const Method& m : methods) std::printf("  RMSE %-6s", m.label);
    std::printf("\n");
    for (int k = 0; k < o.rings; ++k) {
        const auto index = static_cast<std::size_t>(k);
        char range[40];
        std::snprintf(range, sizeof range, "%.1f-%.1f deg", layout.inner(k), layout.outer(k));
        std::printf("  %6d %17s %9lld", k + 1, range,
                    static_cast<long long>(sums.ring_pixels[index]));
        for (std::size_t m = 0; m < methods.size(); ++m)
            std::printf(" %12.5f", sums.rings[m][index] / n);
        std::printf("\n");
    }
}

void print_errors(const Scene& scene, const BenchVisualPolarOptions& o, Size size) {
    Progress progress("bench visual-polar (error)", o.quiet);
    std::vector<Method> methods = error_methods();
    const std::size_t m_count = methods.size();
    std::vector<int> compared;
    for (int f = o.every - 1; f < o.frames; f += o.every) compared.push_back(f);
    // progress in units of one 1-spp frame: the methods' frames, then spp per reference frame
    const double units = static_cast<double>(m_count) * o.frames +
                         static_cast<double>(compared.size()) * o.reference_spp;
    RenderSettings s;
    s.width = size.width;
    s.height = size.height;
    s.frame_count = o.frames;
    const MethodRuns runs = render_methods(scene, s, size, methods, progress, units);
    progress.clear();

    const float distance = display_distance_px(scene.display, size.width, size.height,
                                               camera_at(scene, 0.0f).vfov_deg);
    const glm::vec2 gaze{static_cast<float>(size.width) * 0.5f,
                         static_cast<float>(size.height) * 0.5f};
    RingSettings ring_settings;
    ring_settings.count = o.rings;
    const RingLayout layout = ring_layout(size.width, size.height, gaze, distance, ring_settings);
    print_budgets(o, size, distance, methods, runs);

    std::printf("  %6s", "frame");
    for (const char* what : {"RMSE", "SSIM"})
        for (const Method& m : methods) std::printf(" %5s %-6s", what, m.label);
    std::printf(" %14s\n", "ref. std. err.");
    ErrorSums sums{std::vector<double>(m_count, 0.0), std::vector<double>(m_count, 0.0),
                   std::vector<std::vector<double>>(
                       m_count, std::vector<double>(static_cast<std::size_t>(o.rings))),
                   std::vector<std::int64_t>(static_cast<std::size_t>(o.rings), 0)};
    double done = static_cast<double>(m_count) * o.frames;
    for (const int f : compared) {
        RenderSettings r = s;
        r.first_frame = f;
        r.frame_count = 1;
        r.params = Params(ParamMap{{"spp", std::to_string(o.reference_spp)}});
        r.progress = [&](double x) { progress.update((done + x * o.reference_spp) / units); };
        Image reference;
        double standard_error = 0.0;
        render_each(&scene, "pathtrace-reference", r, [&](FrameResult& fr) {
            reference = to_display(fr.find("final")->image);
            standard_error =
                1e-9 * static_cast<double>(fr.counters.get("reference_mean_standard_error_e9"));
        });
        done += o.reference_spp;
        progress.clear();
        compare_frame(f, reference, standard_error, runs, layout, sums);
    }
    const double n = static_cast<double>(compared.size());
    std::printf("  %6s", "mean");
    for (std::size_t m = 0; m < m_count; ++m) std::printf(" %12.5f", sums.rmse[m] / n);
    for (std::size_t m = 0; m < m_count; ++m) std::printf(" %12.4f", sums.ssim[m] / n);
    std::printf("\n");
    print_ring_table(o, layout, methods, sums, n);
    std::printf("  temporal error (mean |luma(t) - luma(t-1)|):");
    for (std::size_t m = 0; m < m_count; ++m)
        std::printf(" %s %.5f%s", methods[m].label, temporal_error(runs.finals[m]),
                    m + 1 < m_count ? "," : "\n");
    std::fflush(stdout);
    progress.finish();
}

Size parse_size(const std::string& text, const std::string& option) {
    int w = 0, h = 0;
    char tail = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &w, &h, &tail) != 2 || w < 16 || h < 16 || w > 16384 ||
        h > 16384)
        throw Error(option + " '" + text + "': expected WxH with 16 <= W, H <= 16384");
    return {w, h};
}

}  // namespace

int run_bench_visual_polar(const BenchVisualPolarOptions& o) {
    if (o.repeats < 1 || o.rounds < 1)
        throw Error("bench visual-polar: --repeats and --rounds must be at least 1");
    if ((o.width == 0) != (o.height == 0))
        throw Error("--width and --height go together (one size for the cost part)");
    if (o.every > o.frames)
        throw Error("--every " + std::to_string(o.every) + " is more than --frames " +
                    std::to_string(o.frames) + ": no frame would be compared");
    const Size error_size = parse_size(o.error_size, "--error-size");
    const std::vector<Size> sizes = o.width > 0 ? std::vector<Size>{{o.width, o.height}}
                                                : std::vector<Size>{{1280, 1440}, {1280, 720}};
    const Scene scene = load_cli_scene(o.scene);
    std::printf(
        "fovref bench visual-polar: path tracing + BMFR in screen space vs Visual-Polar space "
        "(Koskela P5), one thread\n");
    if (!o.skip_cost) print_cost(scene, o, sizes);
    if (!o.skip_error) print_errors(scene, o, error_size);
    return 0;
}

}  // namespace fovref
