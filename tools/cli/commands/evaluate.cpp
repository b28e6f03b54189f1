#include "tools/cli/commands/evaluate.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>

#include <unistd.h>

#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "ref/metrics/flip.h"
#include "ref/metrics/heatmap.h"
#include "ref/metrics/metrics.h"
#include "ref/metrics/rings.h"
#include "ref/metrics/ssim.h"
#include "ref/modes/modes.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/number_text.h"
#include "tools/cli/common/output_dir.h"
#include "tools/cli/common/progress.h"
#include "tools/cli/report/json_values.h"
#include "tools/cli/report/svg_plot.h"

namespace fs = std::filesystem;

namespace fovref {

namespace {

using json = nlohmann::json;

// One compared sequence: a render mode (with its parameters) or a directory of frames.
struct Candidate {
    std::string label;
    std::string mode;                ///< "" for a directory of frames
    const ModeInfo* info = nullptr;  ///< the mode, looked up once
    std::string directory;
    Params params;
    std::vector<std::vector<RingStats>> rings;   ///< per evaluated frame
    std::vector<std::vector<double>> ring_flip;  ///< --flip: per evaluated frame, each ring's mean
    std::vector<json> frame_rows;
    std::vector<Image> display_frames;  ///< evaluated frames, for the temporal error
    Image last_error;                   ///< squared-error map of the last evaluated frame
};

// "basic" or "basic:primary=raster:key=value".
Candidate parse_mode(const std::string& text, const std::vector<std::string>& shared_params) {
    Candidate c;
    c.label = text;
    std::size_t start = 0;
    std::vector<std::string> parts;
    while (true) {
        const auto colon = text.find(':', start);
        parts.push_back(text.substr(start, colon - start));
        if (colon == std::string::npos) break;
        start = colon + 1;
    }
    c.mode = parts[0];
    c.info = &find_mode(c.mode);
    const ModeInfo& mode = *c.info;
    const Params shared = Params::from_assignments(shared_params);
    for (const auto& [key, value] : shared.values())
        for (const ParamSpec& spec : mode.params)
            if (spec.name == key) c.params.set(key, value);
    // The mode's own parameters (MODE:k=v:...) replace the shared ones, each key given once
    const Params own = Params::from_assignments({parts.begin() + 1, parts.end()});
    for (const auto& [key, value] : own.values()) c.params.set(key, value);
    c.params.check_known(mode.params, c.mode);
    return c;
}

Image final_image(const FrameResult& frame) {
    const Buffer* b = frame.find("final");
    if (!b) throw Error("the mode has no 'final' buffer to evaluate");
    if (b->image.channels != 3) throw Error("the mode's 'final' buffer is not RGB");
    return b->image;
}

// A frame of a directory of rendered frames: f000_final.pfm / .exr / .png (bundle naming).
Image read_frame(const std::string& directory, int frame) {
    char stem[32];
    std::snprintf(stem, sizeof stem, "f%03d_final", frame);
    for (const char* ext : {".pfm", ".exr", ".png"}) {
        const fs::path path = fs::path(directory) / (std::string(stem) + ext);
        if (fs::exists(path)) return read_image(path.string());
    }
    throw Error(directory + ": no " + stem + ".pfm/.exr/.png for frame " + std::to_string(frame));
}

std::string csv_number(double v) { return number_text(v, "%.9g", ""); }

// Lund §5.3.4: each ring's statistic averaged over the evaluated frames.
std::vector<RingStats> average_rings(const std::vector<std::vector<RingStats>>& frames) {
    std::vector<RingStats> mean = frames.front();
    for (std::size_t k = 0; k < mean.size(); ++k) {
        double mse = 0, rmse = 0, psnr_sum = 0, ssim = 0, sd = 0;
        for (const auto& f : frames) {
            mse += f[k].mse;
            rmse += f[k].rmse;
            psnr_sum += f[k].psnr;
            ssim += f[k].ssim;
            sd += f[k].sd;
        }
        const auto n = static_cast<double>(frames.size());
        mean[k].mse = mse / n;
        mean[k].rmse = rmse / n;
        mean[k].psnr = psnr_sum / n;
        mean[k].ssim = ssim / n;
        mean[k].sd = sd / n;
    }
    return mean;
}

// What every comparison of a run shares: the screen, the ring layout around the gaze, the
// evaluated frames and the reference images at them.
struct Evaluation {
    Evaluation(const EvaluateOptions& o, const Scene& s)
        : options(o), scene(s), reference_mode(&find_mode(o.reference_mode)) {}

    const EvaluateOptions& options;
    const Scene& scene;
    const ModeInfo* reference_mode;  ///< looked up once (an unknown mode fails before any work)
    RenderSettings base;             ///< size and camera-path times of every render
    glm::vec2 gaze;
    float distance = 0.0f;  ///< viewing distance in pixels (the scene's display model)
    RingLayout layout;
    std::vector<int> evaluated;            ///< frame numbers: 0, every, 2 every, ... below frames
    std::map<int, Image> reference;        ///< per evaluated frame, in the compared space
    std::vector<Image> reference_display;  ///< in evaluated order, for the temporal error

    /// Display space (SPEC §10), or the stored values with --linear.
    Image space(const Image& image) const { return options.linear ? image : to_display(image); }
};

// The --mode and --frames-dir candidates, in that order.
std::vector<Candidate> make_candidates(const EvaluateOptions& o) {
    std::vector<Candidate> candidates;
    // --gaze is the gaze of the error ranges and of every foveated mode evaluated.
    std::vector<std::string> shared = o.params;
    if (!o.gaze.empty()) {
        for (const std::string& p : o.params)
            if (p.rfind("gaze=", 0) == 0)
                throw Error("evaluate: --gaze and --param gaze=... both given; give --gaze");
        shared.push_back("gaze=" + o.gaze);
    }
    for (const std::string& m : o.modes) candidates.push_back(parse_mode(m, shared));
    for (const std::string& d : o.frame_dirs) {
        if (!fs::is_directory(d)) throw Error(d + ": not a directory of frames");
        Candidate c;
        c.label = fs::path(d).filename().string().empty() ? d : fs::path(d).filename().string();
        c.directory = d;
        candidates.push_back(std::move(c));
    }
    return candidates;
}

// The screen, the gaze, the viewing distance (checked for FLIP) and the ring layout.
void set_up_rings(Evaluation& e) {
    const EvaluateOptions& o = e.options;
    e.base.width = o.width;
    e.base.height = o.height;
    e.base.time_start = o.time_start;
    e.base.time_step = o.time_step;
    validate_settings(e.base);
    RingSettings ring_settings;
    ring_settings.count = o.rings;
    ring_settings.max_range = o.max_range;
    e.gaze = parse_gaze(o.gaze, o.width, o.height);
    e.distance = display_distance_px(e.scene.display, o.width, o.height,
                                     camera_at(e.scene, o.time_start).vfov_deg);
    if (o.flip)
        check_flip_viewing_distance(e.distance, "the scene's display model (viewing distance " +
                                                    std::to_string(e.distance) + " px)");
    e.layout = ring_layout(o.width, o.height, e.gaze, e.distance, ring_settings);
}

// What a stored reference (--reference-dir) must match: the scene (and its file's contents), the
// reference mode, the screen, the camera-path times, the evaluated frames and the version.
json reference_key(const Evaluation& e) {
    const EvaluateOptions& o = e.options;
    json key = {{"scene", o.scene},           {"reference", o.reference_mode},
                {"width", o.width},           {"height", o.height},
                {"time_start", o.time_start}, {"time_step", o.time_step},
                {"frames", e.evaluated},      {"fovref_version", fovref_version()}};
    if (fs::is_regular_file(o.scene)) {
        const std::string text = read_file(o.scene);
        key["scene_sha256"] = sha256_hex(text.data(), text.size());
    }
    return key;
}

std::string reference_frame_file(const std::string& dir, int frame) {
    char name[32];
    std::snprintf(name, sizeof name, "f%03d_final.pfm", frame);
    return (fs::path(dir) / name).string();
}

// Reads the stored reference frames (linear binary32) when the directory holds them for these
// settings; false when there is no reference.json; throws when it holds another reference.
bool read_stored_reference(const std::string& dir, const json& key, std::vector<Image>& frames,
                           const std::vector<int>& evaluated) {
    const fs::path key_file = fs::path(dir) / "reference.json";
    if (!fs::exists(key_file)) return false;
    json stored;
    try {
        stored = json::parse(read_file(key_file.string()));
    } catch (const json::exception& err) {
        throw Error(key_file.string() + ": not a reference key (" + err.what() + ")");
    }
    if (stored != key)
        throw Error(dir + ": holds a reference for other settings (" + stored.dump() +
                    "), this run needs " + key.dump() + "; give another --reference-dir");
    for (int frame : evaluated) frames.push_back(read_image(reference_frame_file(dir, frame)));
    return true;
}

// Stores the reference frames: written into a temporary directory next to `dir`, which is then
// renamed, so that a concurrent job sees the whole reference or none; if another job stored it
// first, its copy (the same bits) is kept.
void store_reference(const std::string& dir, const json& key, const std::vector<Image>& frames,
                     const std::vector<int>& evaluated) {
    const fs::path target(dir);
    if (target.has_parent_path()) fs::create_directories(target.parent_path());
    const fs::path temporary =
        target.string() + ".tmp-" + std::to_string(static_cast<long long>(::getpid()));
    fs::remove_all(temporary);
    fs::create_directories(temporary);
    for (std::size_t i = 0; i < frames.size(); ++i)
        write_pfm(reference_frame_file(temporary.string(), evaluated[i]), frames[i]);
    write_file_atomic((temporary / "reference.json").string(), key.dump(1) + "\n");
    std::error_code error;
    fs::rename(temporary, target, error);
    if (error) {
        fs::remove_all(temporary);
        if (!fs::exists(target / "reference.json"))
            throw Error(dir + ": cannot store the reference (" + error.message() + ")");
    }
}

// The reference at the evaluated frames (one frame each: the reference mode keeps no state
// between frames, and its frame number seeds rand() exactly as in a full sequence), from
// --reference-dir when it holds them.
void render_reference(Evaluation& e, Progress& progress, double total) {
    const std::string& dir = e.options.reference_dir;
    const json key = dir.empty() ? json() : reference_key(e);
    std::vector<Image> linear;
    if (dir.empty() || !read_stored_reference(dir, key, linear, e.evaluated)) {
        for (std::size_t i = 0; i < e.evaluated.size(); ++i) {
            RenderSettings s = e.base;
            s.first_frame = e.evaluated[i];
            s.progress = [&](double f) {
                progress.update((static_cast<double>(i) + f) /
                                static_cast<double>(e.evaluated.size()) / total);
            };
            for (const FrameResult& f : render(&e.scene, *e.reference_mode, s))
                linear.push_back(final_image(f));
        }
        if (!dir.empty()) store_reference(dir, key, linear, e.evaluated);
    }
    for (std::size_t i = 0; i < e.evaluated.size(); ++i) {
        e.reference[e.evaluated[i]] = e.space(linear[i]);
        // The temporal error is measured in display space, also with --linear.
        const Image& reference = e.reference[e.evaluated[i]];
        e.reference_display.push_back(e.options.linear ? to_display(reference) : reference);
    }
}

// Compares one frame of a candidate with the reference when it is an evaluated one: its ring
// errors, a row of frames.csv (with the render's counters and stage time when it has them), the
// frame for the temporal error and its squared-error map.
void evaluate_frame(const Evaluation& e, Candidate& c, int frame, const Image& image,
                    const Counters* counters, const std::map<std::string, double>* stage_times) {
    const EvaluateOptions& o = e.options;
    if (frame % o.every != 0) return;
    const Image& ref = e.reference.at(frame);
    const Image test = e.space(image);
    if (!test.same_shape(ref))
        throw Error(c.label + ": frame " + std::to_string(frame) + " is " +
                    std::to_string(test.width) + "x" + std::to_string(test.height) +
                    ", the reference " + std::to_string(ref.width) + "x" +
                    std::to_string(ref.height));
    const SsimMap map = ssim_map(luma(ref), luma(test));
    c.rings.push_back(ring_errors(ref, test, e.layout, &map));
    const double m = mse(ref, test);
    json row = {{"frame", frame}, {"mse", m}, {"psnr", number_json(psnr(m))}, {"ssim", map.mean}};
    if (o.flip) {
        FlipParams fp;
        fp.pixels_per_degree = flip_pixels_per_degree(e.distance);
        const FlipResult flip =
            o.linear ? ldr_flip(to_display(ref), to_display(test), fp) : ldr_flip(ref, test, fp);
        row["flip_mean"] = flip.mean;
        c.ring_flip.push_back(ring_means(flip.error_map, e.layout));
    }
    if (counters) {
        std::int64_t rays = 0;
        for (const auto& [name, value] : counters->values)
            if (name.rfind("rays_", 0) == 0) rays += value;
        row["rays_traced"] = rays;
        row["rays_percent_of_pixels"] =
            100.0 * static_cast<double>(rays) / (static_cast<double>(o.width) * o.height);
        row["pixels_shaded"] = counters->get("pixels_shaded");
        // TAA's decisions (ghosting and flicker compared between settings).
        for (const auto& [name, value] : counters->values)
            if (name.rfind("taa_", 0) == 0 && name != "taa_jitter_index") row[name] = value;
        double seconds = 0.0;
        json times = json::object();
        for (const auto& [name, t] : *stage_times) {
            seconds += t;
            times[name] = t;
        }
        row["stage_seconds"] = seconds;
        row["stage_times"] = times;
        json all = json::object();  // every counter of the render, the work skipped included
        for (const auto& [name, value] : counters->values) all[name] = value;
        row["counters"] = all;
    }
    c.frame_rows.push_back(row);
    c.display_frames.push_back(o.linear ? to_display(test) : test);
    c.last_error = squared_error_map(ref, test);
}

// Each candidate: every frame in order (modes may carry state from frame to frame), the
// evaluated ones compared. `index` places it in the progress bar after the reference.
void evaluate_candidate(const Evaluation& e, Candidate& c, std::size_t index, Progress& progress,
                        double total) {
    const auto done = [&](double f) {
        progress.update((static_cast<double>(index + 1) + f) / total);
    };
    if (!c.mode.empty()) {
        RenderSettings s = e.base;
        s.frame_count = e.options.frames;
        s.params = c.params;
        // --repeats: the extra renders first, for their stage times and their images' hashes.
        std::map<int, std::map<std::string, std::vector<double>>> times;
        std::map<int, std::string> hashes;
        for (int r = 1; r < e.options.repeats; ++r)
            render_each(&e.scene, *c.info, s, [&](FrameResult& f) {
                for (const StageRun& run : f.stages)
                    if (run.ran) times[f.frame][run.name].push_back(run.seconds);
                const std::string hash = canonical_sha256(final_image(f));
                if (!hashes.emplace(f.frame, hash).second && hashes[f.frame] != hash)
                    throw Error(c.label + ": frame " + std::to_string(f.frame) +
                                " differs between repeats (not deterministic)");
            });
        s.progress = done;
        render_each(&e.scene, *c.info, s, [&](FrameResult& f) {
            if (!hashes.empty() && hashes.at(f.frame) != canonical_sha256(final_image(f)))
                throw Error(c.label + ": frame " + std::to_string(f.frame) +
                            " differs between repeats (not deterministic)");
            std::map<std::string, double> medians;
            for (const StageRun& run : f.stages) {
                if (!run.ran) continue;
                std::vector<double> t = times[f.frame][run.name];
                t.push_back(run.seconds);
                medians[run.name] = median_of(t);
            }
            evaluate_frame(e, c, f.frame, final_image(f), &f.counters, &medians);
        });
    } else {
        for (std::size_t i = 0; i < e.evaluated.size(); ++i) {
            evaluate_frame(e, c, e.evaluated[i], read_frame(c.directory, e.evaluated[i]), nullptr,
                           nullptr);
            done(static_cast<double>(i + 1) / static_cast<double>(e.evaluated.size()));
        }
    }
}

// summary.json without the candidates: the run's settings, the ring layout and the reference's
// temporal error.
json summary_json(const Evaluation& e) {
    const EvaluateOptions& o = e.options;
    json summary;
    summary["scene"] = o.scene;
    summary["reference"] = o.reference_mode;
    summary["width"] = o.width;
    summary["height"] = o.height;
    summary["frames"] = o.frames;
    summary["repeats"] = o.repeats;
    summary["evaluated_frames"] = e.evaluated;
    summary["space"] = o.linear ? "linear" : "display";
    summary["ring_layout"] = {{"gaze", {e.gaze.x, e.gaze.y}},
                              {"distance_px", e.distance},
                              {"max_eccentricity_deg", e.layout.max_eccentricity_deg},
                              {"outer_deg", e.layout.outer_deg},
                              {"rings", o.rings}};
    summary["reference_temporal_error"] = temporal_error(e.reference_display);
    return summary;
}

std::string rings_csv_row(const std::string& label, const RingStats& ring) {
    return label + "," + std::to_string(ring.ring) + "," + csv_number(ring.inner_deg) + "," +
           csv_number(ring.outer_deg) + "," + std::to_string(ring.pixels) + "," +
           csv_number(ring.mse) + "," + csv_number(ring.rmse) + "," + csv_number(ring.psnr) + "," +
           csv_number(ring.ssim) + "," + csv_number(ring.sd) + "\n";
}

// The candidate's rows of frames.csv (a field the row lacks is left empty).
std::string frames_csv_rows(const Candidate& c) {
    std::string rows;
    for (const json& row : c.frame_rows) {
        auto field = [&](const char* key) -> std::string {
            if (!row.contains(key)) return "";
            const json& v = row[key];
            if (v.is_string()) return v.get<std::string>();
            if (v.is_number_integer()) return std::to_string(v.get<std::int64_t>());
            return csv_number(v.get<double>());
        };
        rows += c.label + "," + field("frame") + "," + field("mse") + "," + field("psnr") + "," +
                field("ssim") + "," + field("flip_mean") + "," + field("rays_traced") + "," +
                field("rays_percent_of_pixels") + "," + field("pixels_shaded") + "," +
                field("stage_seconds") + "," + field("taa_history_kept") + "," +
                field("taa_history_rejected") + "," + field("taa_history_clamped") + "," +
                field("taa_periphery_kept") + "," + field("taa_reprojection_skipped") + "\n";
    }
    return rows;
}

// heatmap_LABEL.png: the squared error of the candidate's last evaluated frame with the rings.
void write_heatmap(const Evaluation& e, const Candidate& c, OutputDirectory& out) {
    HeatmapSettings hs;
    hs.rings = &e.layout;
    std::string file = "heatmap_" + c.label + ".png";
    for (char& ch : file)
        if (ch == ':' || ch == '=' || ch == '/' || ch == ' ') ch = '_';
    write_png(out.file(file), heatmap(c.last_error, hs));
}

// SSIM, PSNR and RMSE against eccentricity side by side, one line per candidate.
std::string rings_svg(const Evaluation& e, const std::vector<PlotSeries>& ssim_plot,
                      const std::vector<PlotSeries>& psnr_plot,
                      const std::vector<PlotSeries>& rmse_plot) {
    const std::string title_suffix =
        " (" + std::to_string(e.evaluated.size()) + " frames averaged)";
    const std::string x_label = "eccentricity (degrees)";
    std::string svg = "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"1290\" height=\"320\">\n";
    const std::string plots[3] = {
        svg_line_plot({"SSIM" + title_suffix, x_label, "SSIM", ssim_plot}),
        svg_line_plot({"PSNR" + title_suffix, x_label, "dB", psnr_plot}),
        svg_line_plot({"RMSE" + title_suffix, x_label, "RMSE", rmse_plot})};
    for (int k = 0; k < 3; ++k)
        svg +=
            "<g transform=\"translate(" + std::to_string(430 * k) + " 0)\">" + plots[k] + "</g>\n";
    svg += "</svg>\n";
    return svg;
}

// rings.csv, frames.csv, summary.json, rings.svg and a heatmap per candidate in --out.
void write_outputs(const Evaluation& e, const std::vector<Candidate>& candidates,
                   OutputDirectory& out) {
    std::string rings_csv = "label,ring,inner_deg,outer_deg,pixels,mse,rmse,psnr,ssim,sd\n";
    std::string frames_csv =
        "label,frame,mse,psnr,ssim,flip_mean,rays_traced,rays_percent_of_pixels,"
        "pixels_shaded,stage_seconds,taa_history_kept,taa_history_rejected,taa_history_clamped,"
        "taa_periphery_kept,taa_reprojection_skipped\n";
    json summary = summary_json(e);
    std::vector<PlotSeries> ssim_plot, psnr_plot, rmse_plot;
    for (const Candidate& c : candidates) {
        const std::vector<RingStats> mean = average_rings(c.rings);
        json jc;
        jc["label"] = c.label;
        jc["temporal_error"] = temporal_error(c.display_frames);
        if (!c.ring_flip.empty()) {  // each ring's mean FLIP, averaged over the frames
            json flip_rings = json::array();
            for (std::size_t k = 0; k < c.ring_flip.front().size(); ++k) {
                double sum = 0.0;
                for (const std::vector<double>& frame : c.ring_flip) sum += frame[k];
                flip_rings.push_back(number_json(sum / static_cast<double>(c.ring_flip.size())));
            }
            jc["ring_flip_mean"] = flip_rings;
        }
        jc["rings"] = json::array();
        PlotSeries s{c.label, {}, {}}, p{c.label, {}, {}}, r{c.label, {}, {}};
        for (const RingStats& ring : mean) {
            jc["rings"].push_back(ring_json(ring));
            rings_csv += rings_csv_row(c.label, ring);
            const double mid = 0.5 * (static_cast<double>(ring.inner_deg) + ring.outer_deg);
            s.x.push_back(mid);
            p.x.push_back(mid);
            r.x.push_back(mid);
            s.y.push_back(ring.ssim);
            p.y.push_back(ring.psnr);
            r.y.push_back(ring.rmse);
        }
        ssim_plot.push_back(s);
        psnr_plot.push_back(p);
        rmse_plot.push_back(r);
        jc["frames"] = c.frame_rows;
        frames_csv += frames_csv_rows(c);
        summary["candidates"].push_back(jc);
        write_heatmap(e, c, out);
    }
    const std::string svg = rings_svg(e, ssim_plot, psnr_plot, rmse_plot);
    write_file_atomic(out.file("rings.svg"), svg);
    write_file_atomic(out.file("rings.csv"), rings_csv);
    write_file_atomic(out.file("frames.csv"), frames_csv);
    write_file_atomic(out.file("summary.json"), summary.dump(1) + "\n");
    out.commit();
}

// The text summary on stdout: every fifth ring and the last of each candidate.
void print_rings(const Evaluation& e, const std::vector<Candidate>& candidates) {
    const EvaluateOptions& o = e.options;
    std::printf("evaluate: %s, %dx%d, %zu of %d frames vs %s, %d rings to %.3g deg (%s space)\n",
                o.scene.c_str(), o.width, o.height, e.evaluated.size(), o.frames,
                o.reference_mode.c_str(), o.rings, static_cast<double>(e.layout.outer_deg),
                o.linear ? "linear" : "display");
    std::printf("%-24s %6s %10s %12s %12s\n", "candidate", "ring", "outer deg", "PSNR", "SSIM");
    for (const Candidate& c : candidates) {
        const std::vector<RingStats> mean = average_rings(c.rings);
        for (const RingStats& r : mean)
            if (r.ring % 5 == 0 || r.ring == o.rings - 1)
                std::printf("%-24s %6d %10.3g %12s %12s\n", c.label.c_str(), r.ring,
                            static_cast<double>(r.outer_deg), csv_number(r.psnr).c_str(),
                            csv_number(r.ssim).c_str());
    }
    // The temporal error (SPEC §10): flicker and ghosting; the reference's changes with the
    // camera alone.
    std::printf("%-24s %s\n", "candidate",
                o.every == 1
                    ? "temporal error (mean |luma(t) - luma(t-1)|, display space)"
                    : ("temporal error (mean |luma(t) - luma(t-" + std::to_string(o.every) +
                       ")| over the evaluated frames, display space)")
                          .c_str());
    std::printf("%-24s %.6g\n", ("reference " + o.reference_mode).c_str(),
                temporal_error(e.reference_display));
    for (const Candidate& c : candidates)
        std::printf("%-24s %.6g\n", c.label.c_str(), temporal_error(c.display_frames));
    std::printf("wrote %s/{rings.csv,frames.csv,summary.json,rings.svg,heatmap_*.png}\n",
                o.out_dir.c_str());
}

}  // namespace

int run_evaluate(const EvaluateOptions& o) {
    if (o.modes.empty() && o.frame_dirs.empty())
        throw Error("evaluate: give --mode and/or --frames-dir");
    OutputDirectory out("--out", o.out_dir);  // checked before any work
    check_separate_outputs({{"--out", o.out_dir}, {"--reference-dir", o.reference_dir}});
    const Scene scene = load_cli_scene(o.scene);
    std::vector<Candidate> candidates = make_candidates(o);
    Evaluation e(o, scene);
    set_up_rings(e);
    for (int f = 0; f < o.frames; f += o.every) e.evaluated.push_back(f);
    Progress progress("evaluate", o.quiet);
    const double total = static_cast<double>(candidates.size() + 1);
    render_reference(e, progress, total);
    for (std::size_t ci = 0; ci < candidates.size(); ++ci)
        evaluate_candidate(e, candidates[ci], ci, progress, total);
    progress.finish();

    write_outputs(e, candidates, out);
    if (!o.quiet) print_rings(e, candidates);
    return 0;
}

void store_evaluation_reference(const EvaluateOptions& o) {
    if (o.reference_dir.empty()) throw Error("store_evaluation_reference: no reference directory");
    const Scene scene = load_cli_scene(o.scene);
    Evaluation e(o, scene);
    set_up_rings(e);
    for (int f = 0; f < o.frames; f += o.every) e.evaluated.push_back(f);
    Progress progress("reference", o.quiet);
    render_reference(e, progress, 1.0);
    progress.finish();
}

}  // namespace fovref
