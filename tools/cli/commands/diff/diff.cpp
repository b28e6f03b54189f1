#include "tools/cli/commands/diff/diff.h"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "ref/metrics/metrics.h"
#include "tools/cli/commands/diff/report.h"
#include "tools/cli/common/number_text.h"
#include "tools/cli/report/json_values.h"

namespace fs = std::filesystem;

namespace fovref {

namespace {

using json = nlohmann::json;

// Candidate file extensions, in the order they are looked for.
const std::vector<std::string> candidate_extensions = {".pfm", ".exr", ".png",
                                                       ".raw", ".bin", ".f32"};

bool is_raw(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".raw" || ext == ".bin" || ext == ".f32";
}

// "WxH" or "WxHxC".
void parse_raw_size(const std::string& text, RawLayout& layout) {
    int values[3] = {0, 0, 1};
    int count = 0;
    const char* p = text.data();
    const char* end = text.data() + text.size();
    while (p < end && count < 3) {
        const auto r = std::from_chars(p, end, values[count]);
        if (r.ec != std::errc()) break;
        ++count;
        p = r.ptr;
        if (p < end && *p == 'x')
            ++p;
        else
            break;
    }
    if (p != end || count < 2)
        throw Error("--raw-size '" + text + "': expected WxH or WxHxC (e.g. 1280x720x3)");
    layout.width = values[0];
    layout.height = values[1];
    layout.channels = values[2];
}

RawLayout raw_layout(const DiffOptions& o, int width, int height, int channels) {
    RawLayout layout;
    layout.width = width;
    layout.height = height;
    layout.channels = channels;
    if (!o.raw_size.empty()) parse_raw_size(o.raw_size, layout);
    layout.planar = o.raw_planar;
    layout.bottom_up = o.raw_bottom_up;
    layout.big_endian = o.raw_big_endian;
    return layout;
}

// Reads a golden or candidate file. PNGs of colour buffers are sRGB-decoded (SPEC §11) unless
// --png-linear; an RGBA file compared with an RGB buffer loses its alpha channel (noted).
Image load_image(const DiffOptions& o, const std::string& path, const std::string& kind, int width,
                 int height, int channels, std::string* note) {
    Image image;
    if (is_raw(path)) {
        if (o.raw_size.empty() && width == 0)
            throw Error(path + ": a raw binary32 file needs --raw-size WxH[xC]");
        image = read_raw(path, raw_layout(o, width, height, channels));
    } else if (lower_extension(path) == ".png") {
        image = read_png(path, !o.png_linear && kind == "color");
    } else {
        image = read_image(path);
    }
    if (channels == 3 && image.channels == 4) {
        Image rgb(image.width, image.height, 3);
        for (std::size_t p = 0; p < image.pixel_count(); ++p)
            for (std::size_t c = 0; c < 3; ++c) rgb.data[p * 3 + c] = image.data[p * 4 + c];
        image = std::move(rgb);
        if (note) *note = "the candidate's alpha channel was dropped";
    }
    return image;
}

std::string shape(int w, int h, int c) {
    return std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(c);
}

// Default viewing distance without a scene: the display subtends a 60 degree vertical field of
// view (docs/diff.md).
float default_distance_px(int height) {
    return 0.5f * static_cast<float>(height) / dm::tan(dm::radians(30.0f));
}

/// How the pooled FLIP values are accumulated (printed with them; docs/flip.md).
constexpr const char* flip_pooling_note =
    "binary64 sums (mean in row-major order; weighted percentiles over the values sorted "
    "ascending); NVlabs's tool sums in binary32, so its mean can differ in the 5th decimal";

std::string values_text(const std::vector<float>& values) {
    std::string out = "(";
    for (std::size_t i = 0; i < values.size(); ++i) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(values[i]));
        out += (i ? ", " : "") + std::string(text);
    }
    return out + ")";
}

// The probe's point for element (x, y) of buffer item.name: a log-polar buffer's texel
// (--texel I,J; in stereo the eye from the half it lies in), a gaze-buffer pixel moved by the
// buffer's window on the screen (the frame's gaze_window_* counters), otherwise a screen pixel.
std::string probe_point(const Manifest& m, const DiffItem& item, int x, int y) {
    const bool known_frame =
        item.frame >= 0 && item.frame < static_cast<int>(m.frame_counters.size());
    const Counters none;
    const Counters& counters =
        known_frame ? m.frame_counters[static_cast<std::size_t>(item.frame)] : none;
    if (item.name.rfind("lp_", 0) == 0) {
        const auto w = counters.get("buffer_width");
        if (counters.get("eyes") == 2 && w > 0) {
            const auto eye = x >= w ? 1 : 0;
            return " --texel " + std::to_string(x - eye * w) + "," + std::to_string(y) + "," +
                   std::to_string(eye);
        }
        return " --texel " + std::to_string(x) + "," + std::to_string(y);
    }
    if (item.name.rfind("gaze_", 0) == 0) {
        x += static_cast<int>(counters.get("gaze_window_x0"));
        y += static_cast<int>(counters.get("gaze_window_y0"));
    }
    return " --pixel " + std::to_string(x) + "," + std::to_string(y);
}

std::string probe_command(const Manifest& m, const DiffItem& item, int x, int y) {
    const GoldenCase& c = m.golden_case;
    if (c.scene.empty() && c.mode.empty()) return "";
    std::string command = "fovref probe";
    if (!c.scene.empty()) command += " --scene " + c.scene;
    command += " --mode " + c.mode + " --width " + std::to_string(c.width) + " --height " +
               std::to_string(c.height);
    if (c.time_start != 0.0f) command += " --time-start " + number_text(c.time_start, "%.4g", "-");
    if (c.frames > 1 || item.frame > 0)
        command += " --time-step " + number_text(c.time_step, "%.4g", "-");
    command += " --frame " + std::to_string(item.frame) + probe_point(m, item, x, y);
    for (const auto& [key, value] : c.params.values()) command += " --param " + key + "=" + value;
    return command;
}

// Edit distance (insert, delete, substitute), to suggest the buffer a misnamed file was meant to
// be.
std::size_t edit_distance(const std::string& a, const std::string& b) {
    std::vector<std::size_t> row(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        std::size_t diagonal = row[0];
        row[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t above = row[j];
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// Candidate files of a directory, sorted by name (a fixed order).
std::vector<std::string> list_files(const std::string& directory) {
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(directory))
        if (entry.is_regular_file()) files.push_back(entry.path().filename().string());
    std::sort(files.begin(), files.end());
    return files;
}

void compare_item(const DiffOptions& o, const ToleranceTable& tolerances, float distance_px,
                  DiffItem& item, const std::string& expected_sha,
                  const std::vector<std::uint8_t>* mask) {
    const Tolerance& tolerance = tolerances.for_buffer(item.name);
    std::string note;
    if (item.hash_only) {
        // The golden keeps only a hash (buffers too large for the repository): bit-exact or not.
        item.candidate = load_image(o, item.candidate_file, item.kind, 0, 0, 0, &note);
        item.compared = true;
        item.pass = canonical_sha256(item.candidate) == expected_sha;
        item.note = item.pass ? "golden stores only a hash: the candidate matches it bit for bit"
                              : "golden stores only a hash, which the candidate does not match; "
                                "`fovref golden export` writes a bundle with every buffer's "
                                "values";
        return;
    }
    item.candidate = load_image(o, item.candidate_file, item.kind, item.golden.width,
                                item.golden.height, item.golden.channels, &note);
    if (!item.golden.same_shape(item.candidate))
        throw Error(item.candidate_file + ": size mismatch: buffer '" + item.name + "' is " +
                    shape(item.golden.width, item.golden.height, item.golden.channels) +
                    ", the candidate is " +
                    shape(item.candidate.width, item.candidate.height, item.candidate.channels));
    if (item.is_id) {
        item.ids = compare_id_buffers(item.name, item.golden, item.candidate, tolerance, o.worst);
        item.compared = true;
        item.pass = item.ids.pass;
        item.note = note;
        return;
    }
    const bool image_like = (item.golden.channels == 1 || item.golden.channels == 3) &&
                            item.golden.width >= 11 && item.golden.height >= 11;
    if (image_like) {
        RingSettings rs;
        rs.count = o.rings;
        rs.max_range = o.max_range;
        item.rings = ring_layout(
            item.golden.width, item.golden.height,
            parse_gaze(o.gaze, item.golden.width, item.golden.height),
            distance_px > 0.0f ? distance_px : default_distance_px(item.golden.height), rs);
    }
    CompareOptions options;
    options.threshold = o.threshold;
    options.worst_pixels = o.worst;
    options.rings = item.rings ? &*item.rings : nullptr;
    options.mask = mask;
    item.result = compare_buffers(item.name, item.golden, item.candidate, tolerance, options);
    if (item.result.nonfinite_mismatches > 0)
        note += std::string(note.empty() ? "" : "; ") +
                std::to_string(item.result.nonfinite_mismatches) +
                " value(s) non-finite on one side only: a convention mismatch? fovref writes 0 "
                "depth, 0 attributes and id -1 on background, never inf or NaN (docs/diff.md)";
    if (o.flip && item.kind == "color" && item.golden.channels == 3) {
        // LDR-FLIP on what a viewer sees (SPEC §10), pixels per degree from the display model.
        // Without a display model (two plain images): NVlabs's default observer, not the 60
        // degree field of view the error ranges assume (docs/diff.md).
        FlipParams fp;
        if (distance_px > 0.0f) {
            fp.pixels_per_degree = flip_pixels_per_degree(distance_px);
            item.flip_observer =
                "display model, viewing distance " + number_text(distance_px, "%.4g", "-") + " px";
        } else {
            item.flip_observer =
                "NVlabs default observer: 0.7 m from a 0.7 m wide 3840-pixel monitor";
        }
        item.flip_ppd = fp.pixels_per_degree;
        item.flip = ldr_flip(to_display(item.golden), to_display(item.candidate), fp);
    }
    item.compared = true;
    item.pass = item.result.pass;
    item.note = note;
}

json tolerance_json(const Tolerance& t, bool is_id) {
    if (is_id)
        return {{"edge_mismatch_share", t.max_edge_mismatch_share},
                {"interior_mismatches", t.max_interior_mismatches},
                {"reason", t.reason}};
    return {{"abs", t.abs},
            {"rel", t.rel},
            {"ulp", t.ulp},
            {"max_failing_pixels", t.max_failing_pixels},
            {"reason", t.reason}};
}

json item_json(const DiffItem& item) {
    json j;
    j["frame"] = item.frame;
    j["name"] = item.name;
    j["stage"] = item.stage;
    j["kind"] = item.kind;
    j["golden_file"] = item.golden_file;
    j["candidate_file"] = item.candidate_file.empty() ? json(nullptr) : json(item.candidate_file);
    j["status"] = !item.compared ? (item.required ? "missing-required" : "missing")
                  : item.pass    ? "pass"
                                 : "fail";
    j["compared_as"] = item.is_id ? "ids" : "values";
    if (!item.note.empty()) j["note"] = item.note;
    if (!item.compared || item.hash_only) return j;
    auto pixel_json = [](const PixelDifference& d) {
        return json{{"x", d.x},
                    {"y", d.y},
                    {"abs_error", number_json(d.abs_error)},
                    {"golden", d.golden},
                    {"candidate", d.candidate}};
    };
    if (item.is_id) {
        const IdComparison& r = item.ids;
        j["width"] = r.width;
        j["height"] = r.height;
        j["channels"] = r.channels;
        j["tolerance"] = tolerance_json(r.tolerance, true);
        j["edge_pixels"] = r.edge_pixels;
        j["edge_mismatches"] = r.edge_mismatches;
        j["allowed_edge_mismatches"] = r.allowed_edge_mismatches;
        j["interior_mismatches"] = r.interior_mismatches;
        j["mismatches"] = json::array();
        for (const IdMismatch& m : r.mismatches)
            j["mismatches"].push_back({{"x", m.x},
                                       {"y", m.y},
                                       {"edge", m.edge},
                                       {"golden", m.golden},
                                       {"candidate", m.candidate}});
        return j;
    }
    const BufferComparison& r = item.result;
    j["width"] = r.width;
    j["height"] = r.height;
    j["channels"] = r.channels;
    j["tolerance"] = tolerance_json(r.tolerance, false);
    if (!item.masked_by.empty()) {
        j["masked_by"] = item.masked_by;
        j["masked_pixels"] = r.masked_pixels;
    }
    j["max_abs_error"] = number_json(r.max_abs);
    j["max_rel_error"] = number_json(r.max_rel);
    j["max_ulp"] = r.max_ulp;
    j["nan_mismatches"] = r.nan_mismatches;
    j["nonfinite_mismatches"] = r.nonfinite_mismatches;
    j["differing_elements"] = r.differing_elements;
    j["mean_abs_error"] = number_json(r.mean_abs);
    j["rmse"] = number_json(r.rmse);
    j["psnr"] = number_json(r.psnr);
    j["ssim"] = r.ssim ? number_json(*r.ssim) : json(nullptr);
    if (r.threshold >= 0.0) j["threshold"] = r.threshold;
    j["pixels_over_threshold"] = r.pixels_over_threshold;
    j["failing_pixels"] = r.failing_pixels;
    if (r.first_failing) j["first_failing_pixel"] = pixel_json(*r.first_failing);
    j["worst_pixels"] = json::array();
    for (const PixelDifference& d : r.worst) j["worst_pixels"].push_back(pixel_json(d));
    if (item.flip)
        j["flip"] = {{"mean", item.flip->mean},
                     {"weighted_median", item.flip->weighted_median},
                     {"first_quartile", item.flip->first_quartile},
                     {"third_quartile", item.flip->third_quartile},
                     {"min", item.flip->min},
                     {"max", item.flip->max},
                     {"pixels_per_degree", item.flip_ppd},
                     {"observer", item.flip_observer},
                     {"pooling", flip_pooling_note}};
    if (!r.rings.empty()) {
        json rings = json::array();
        for (const RingStats& s : r.rings) rings.push_back(ring_json(s));
        j["rings"] = rings;
        j["ring_layout"] = {{"gaze", {item.rings->gaze.x, item.rings->gaze.y}},
                            {"distance_px", item.rings->distance_px},
                            {"max_eccentricity_deg", item.rings->max_eccentricity_deg},
                            {"outer_deg", item.rings->outer_deg}};
    }
    return j;
}

std::string percent(std::int64_t part, std::int64_t whole) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g%%",
                  whole > 0 ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0);
    return text;
}

void print_summary(const DiffReport& report) {
    std::printf("fovref diff: golden %s%s, candidate %s, profile %s\n", report.golden.c_str(),
                report.case_name.empty() ? "" : (" (case " + report.case_name + ")").c_str(),
                report.candidate.c_str(), report.profile.c_str());
    std::printf("%-5s %-20s %-26s %-7s %10s %9s %10s %8s %8s\n", "frame", "stage", "buffer",
                "result", "max abs", "max ulp", "fail px", "PSNR", "SSIM");
    for (const DiffItem& item : report.items) {
        const std::string status = item.status();
        if (!item.compared || item.hash_only) {
            std::printf("%-5d %-20s %-26s %-7s %s\n", item.frame, item.stage.c_str(),
                        item.name.c_str(), status.c_str(), item.note.c_str());
            continue;
        }
        if (item.is_id) {
            const IdComparison& r = item.ids;
            std::printf(
                "%-5d %-20s %-26s %-7s ids: %lld interior, %lld edge (%s of %lld edge "
                "px, %lld allowed)\n",
                item.frame, item.stage.c_str(), item.name.c_str(), status.c_str(),
                static_cast<long long>(r.interior_mismatches),
                static_cast<long long>(r.edge_mismatches),
                percent(r.edge_mismatches, r.edge_pixels).c_str(),
                static_cast<long long>(r.edge_pixels),
                static_cast<long long>(r.allowed_edge_mismatches));
            continue;
        }
        const BufferComparison& r = item.result;
        std::string masked;
        if (r.masked_pixels > 0)
            masked = "  (" + std::to_string(r.masked_pixels) + " px where ids differ left out)";
        if (r.nonfinite_mismatches > 0) masked += "  convention mismatch: see note";
        std::printf("%-5d %-20s %-26s %-7s %10s %9lld %10lld %8s %8s%s\n", item.frame,
                    item.stage.c_str(), item.name.c_str(), status.c_str(),
                    number_text(r.max_abs, "%.4g", "-").c_str(), static_cast<long long>(r.max_ulp),
                    static_cast<long long>(r.failing_pixels),
                    r.nonfinite_mismatches > 0 ? "-" : number_text(r.psnr, "%.4g", "-").c_str(),
                    r.ssim ? number_text(*r.ssim, "%.4g", "-").c_str() : "-", masked.c_str());
        if (item.flip)
            std::printf(
                "      LDR-FLIP mean %.6f, weighted median %.6f, quartiles %.6f / %.6f, "
                "max %.6f; %.4g pixels per degree (%s)\n",
                item.flip->mean, item.flip->weighted_median, item.flip->first_quartile,
                item.flip->third_quartile, static_cast<double>(item.flip->max),
                static_cast<double>(item.flip_ppd), item.flip_observer.c_str());
    }
    if (std::any_of(report.items.begin(), report.items.end(),
                    [](const DiffItem& item) { return item.flip.has_value(); }))
        std::printf("LDR-FLIP pooling: %s\n", flip_pooling_note);
    for (std::size_t k = 0; k < report.ignored.size(); ++k)
        std::printf("ignored: %s (matches no golden buffer%s)\n", report.ignored[k].c_str(),
                    report.ignored_hint[k].empty()
                        ? ""
                        : ("; did you mean " + report.ignored_hint[k] + "?").c_str());
    if (report.first_failing >= 0) {
        const DiffItem& item = report.items[static_cast<std::size_t>(report.first_failing)];
        std::printf("first failing stage: %s, buffer '%s', frame %d", item.stage.c_str(),
                    item.name.c_str(), item.frame);
        if (!item.compared) {
            std::printf(": required, missing in the candidate\n");
        } else if (item.hash_only) {
            std::printf(": %s\n", item.note.c_str());
        } else if (item.is_id) {
            const IdComparison& r = item.ids;
            std::printf(
                ": %lld interior and %lld edge id mismatches (%lld and %lld allowed); "
                "later buffers are compared only where the ids agree\n",
                static_cast<long long>(r.interior_mismatches),
                static_cast<long long>(r.edge_mismatches),
                static_cast<long long>(r.tolerance.max_interior_mismatches),
                static_cast<long long>(r.allowed_edge_mismatches));
            for (const IdMismatch& m : r.mismatches) {
                std::printf("  %s mismatch (%d, %d): golden %s, candidate %s\n",
                            m.edge ? "edge" : "interior", m.x, m.y, values_text(m.golden).c_str(),
                            values_text(m.candidate).c_str());
                if (!m.edge) break;  // the first interior one is what explains the failure
            }
        } else {
            const BufferComparison& r = item.result;
            std::printf(
                ": %lld pixel(s) out of tolerance (abs %s, rel %s, ulp %lld, %lld allowed)\n",
                static_cast<long long>(r.failing_pixels),
                number_text(r.tolerance.abs, "%.4g", "-").c_str(),
                number_text(r.tolerance.rel, "%.4g", "-").c_str(),
                static_cast<long long>(r.tolerance.ulp),
                static_cast<long long>(r.tolerance.max_failing_pixels));
            if (r.first_failing)
                std::printf("  first failing pixel (%d, %d): golden %s, candidate %s\n",
                            r.first_failing->x, r.first_failing->y,
                            values_text(r.first_failing->golden).c_str(),
                            values_text(r.first_failing->candidate).c_str());
            if (!r.worst.empty())
                std::printf("  worst pixel (%d, %d): |error| %s, golden %s, candidate %s\n",
                            r.worst[0].x, r.worst[0].y,
                            number_text(r.worst[0].abs_error, "%.4g", "-").c_str(),
                            values_text(r.worst[0].golden).c_str(),
                            values_text(r.worst[0].candidate).c_str());
            if (r.nonfinite_mismatches > 0) std::printf("  note: %s\n", item.note.c_str());
        }
        if (!report.probe_command.empty())
            std::printf("  explain it: %s\n", report.probe_command.c_str());
    }
    std::printf("RESULT: %s (%d compared, %d out of tolerance, %d missing in the candidate%s%s)\n",
                report.pass ? "PASS" : "FAIL", report.compared,
                report.failed - report.missing_required, report.missing,
                report.missing_required > 0
                    ? (", " + std::to_string(report.missing_required) + " of them required").c_str()
                    : "",
                report.ignored.empty()
                    ? ""
                    : (", " + std::to_string(report.ignored.size()) + " file(s) ignored").c_str());
}

}  // namespace

void add_diff_options(CLI::App& c, DiffOptions& o) {
    c.add_option("GOLDEN", o.golden, "golden bundle directory (manifest.json) or image file")
        ->required();
    c.add_option("CANDIDATE", o.candidate,
                 "directory of buffers named as in the manifest (f000_final.pfm or final.pfm, "
                 "...) or one image file")
        ->required();
    c.add_option("--profile", o.profile,
                 "tolerance profile: bit-exact (0 everywhere), gpu-raster (a correct GPU "
                 "rasterizer's G-buffer), gpu-rt (a correct GPU ray tracer); the tolerance file "
                 "and --tolerance override it per buffer (docs/diff.md)")
        ->capture_default_str();
    c.add_option("--tolerance", o.tolerances,
                 "NAME:abs=X,rel=X,ulp=N,pixels=N; for id buffers edge=SHARE,interior=N (NAME "
                 "may be '*'; repeatable)");
    c.add_option("--tolerance-file", o.tolerance_file,
                 "JSON: {\"buffer\": {\"abs\": x, \"rel\": x, \"ulp\": n, "
                 "\"max_failing_pixels\": n, \"edge_mismatch_share\": x, "
                 "\"interior_mismatches\": n, \"reason\": \"...\"}}");
    c.add_option("--require", o.require,
                 "'all' or a comma-separated list of buffer names that must be in the candidate "
                 "(a missing one fails)");
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
    c.add_option("--rings", o.rings, "number of error ranges")
        ->check(CLI::Range(1, 1000))
        ->capture_default_str();
    c.add_option("--max-range", o.max_range, "fraction of the largest eccentricity covered")
        ->check(CLI::Range(1e-6, 1.0))
        ->capture_default_str();
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

std::string DiffItem::status() const {
    if (!compared) return required ? "MISSING" : "missing";
    return pass ? "pass" : "FAIL";
}

bool DiffItem::focus_pixel(int& x, int& y) const {
    if (!compared || hash_only) return false;
    if (is_id) {
        if (ids.mismatches.empty()) return false;
        x = ids.mismatches[0].x;  // interior mismatches are listed first
        y = ids.mismatches[0].y;
        return true;
    }
    if (result.worst.empty()) return false;
    x = result.worst[0].x;
    y = result.worst[0].y;
    return true;
}

namespace {

// Manifest buffers in comparison order: frame by frame, stage by stage in pipeline order, and
// within a stage the id buffers first (SPEC §11: ids before the channels they select).
std::vector<const ManifestBuffer*> comparison_order(const Manifest& manifest) {
    // Group = position of the first buffer of the same frame and stage; ids first in a group.
    std::vector<std::pair<std::size_t, const ManifestBuffer*>> keyed;
    for (std::size_t i = 0; i < manifest.buffers.size(); ++i) {
        const ManifestBuffer& b = manifest.buffers[i];
        std::size_t group = i;
        for (std::size_t k = 0; k < i; ++k)
            if (manifest.buffers[k].frame == b.frame && manifest.buffers[k].stage == b.stage) {
                group = k;
                break;
            }
        keyed.emplace_back(group, &b);
    }
    std::stable_sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) {
        if (a.first != b.first) return a.first < b.first;
        return a.second->kind == "id" && b.second->kind != "id";
    });
    std::vector<const ManifestBuffer*> order;
    for (const auto& entry : keyed) order.push_back(entry.second);
    return order;
}

// The names --require asks for; an unknown name is an input error.
std::vector<std::string> required_names(const std::string& text, const Manifest& manifest) {
    std::vector<std::string> names;
    if (text.empty()) return names;
    if (text == "all") {
        for (const ManifestBuffer& b : manifest.buffers)
            if (std::find(names.begin(), names.end(), b.name) == names.end())
                names.push_back(b.name);
        return names;
    }
    std::size_t start = 0;
    while (start <= text.size()) {
        const std::size_t comma = text.find(',', start);
        const std::string name =
            text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        bool known = false;
        for (const ManifestBuffer& b : manifest.buffers) known = known || b.name == name;
        if (!known) {
            std::string list;
            for (const ManifestBuffer& b : manifest.buffers)
                if (b.frame == manifest.buffers.front().frame) list += " " + b.name;
            throw Error("--require: the golden has no buffer '" + name + "' (it has:" + list + ")");
        }
        names.push_back(name);
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return names;
}

// The closest candidate file name of a golden buffer (for "did you mean"), or "".
std::string closest_buffer_file(const std::string& file, const Manifest& manifest) {
    const std::string stem = fs::path(file).stem().string();
    std::string best;
    std::size_t best_distance = std::max<std::size_t>(4, stem.size() / 3) + 1;
    for (const ManifestBuffer& b : manifest.buffers) {
        char prefix[16];
        std::snprintf(prefix, sizeof prefix, "f%03d_", b.frame);
        for (const std::string& name : {prefix + b.name, b.name}) {
            const std::size_t d = edit_distance(stem, name);
            if (d < best_distance) {
                best_distance = d;
                best = name + fs::path(file).extension().string();
            }
        }
    }
    return best;
}

// What the comparison needs beside the report's items, per item: the SHA-256 of a golden buffer
// kept only as a hash, and the golden's viewing distance (0: none).
struct ItemInputs {
    std::vector<std::string> expected_sha;
    std::vector<float> distances;
};

// The candidate file of golden buffer `b` in the candidate directory's `files` (f000_name.ext,
// or name.ext for a bundle of one frame or the --frame asked for; extensions in
// candidate_extensions order), marked used; "" when there is none.
std::string find_candidate_file(const DiffOptions& o, const ManifestBuffer& b, int frames,
                                const std::vector<std::string>& files, std::vector<bool>& used) {
    std::string found;
    char prefix[16];
    std::snprintf(prefix, sizeof prefix, "f%03d_", b.frame);
    std::vector<std::string> stems = {prefix + b.name};
    if (frames <= 1 || o.frame >= 0) stems.push_back(b.name);
    for (const std::string& stem : stems) {
        for (const std::string& ext : candidate_extensions)
            for (std::size_t k = 0; k < files.size(); ++k)
                if (!used[k] && files[k].size() == stem.size() + ext.size() &&
                    files[k].compare(0, stem.size(), stem) == 0 &&
                    lower_extension(files[k]) == ext && found.empty()) {
                    found = (fs::path(o.candidate) / files[k]).string();
                    used[k] = true;
                }
    }
    return found;
}

// The items of a golden bundle in comparison order, each with its candidate file (a directory's
// files, or the one candidate file as --buffer of --frame); candidate files that match no buffer
// go to report.ignored.
void collect_bundle_items(const DiffOptions& o, const Manifest& manifest, bool candidate_dir,
                          DiffReport& report, ItemInputs& inputs) {
    report.case_name = manifest.golden_case.name;
    report.mode = manifest.golden_case.mode;
    report.scene = manifest.golden_case.scene;
    const std::vector<std::string> required = required_names(o.require, manifest);
    std::vector<std::string> files;
    if (candidate_dir) files = list_files(o.candidate);
    std::vector<bool> used(files.size(), false);
    const int frames = static_cast<int>(manifest.frame_counters.size());
    const int single_frame = o.frame >= 0 ? o.frame : 0;
    bool found_buffer = false;
    for (const ManifestBuffer* buffer : comparison_order(manifest)) {
        const ManifestBuffer& b = *buffer;
        if (o.frame >= 0 && b.frame != o.frame) continue;
        DiffItem item;
        item.frame = b.frame;
        item.name = b.name;
        item.stage = b.stage;
        item.kind = b.kind;
        item.is_id = b.kind == "id";
        item.golden_file = b.file.empty() ? "" : (fs::path(o.golden) / b.file).string();
        item.hash_only = b.file.empty();
        item.required = std::find(required.begin(), required.end(), b.name) != required.end();
        if (candidate_dir) {
            item.candidate_file = find_candidate_file(o, b, frames, files, used);
        } else if (b.frame == single_frame && b.name == (o.buffer.empty() ? "final" : o.buffer)) {
            item.candidate_file = o.candidate;
            found_buffer = true;
        } else {
            continue;  // one candidate file: only its buffer is listed
        }
        const auto f = static_cast<std::size_t>(b.frame);
        inputs.distances.push_back(
            f < manifest.display_distance_px.size() ? manifest.display_distance_px[f] : 0.0f);
        inputs.expected_sha.push_back(b.sha256);
        if (!item.hash_only && !item.candidate_file.empty())
            item.golden =
                load_image(o, item.golden_file, b.kind, b.width, b.height, b.channels, nullptr);
        report.items.push_back(std::move(item));
    }
    if (!candidate_dir && !found_buffer)
        throw Error(o.golden + ": has no buffer '" + (o.buffer.empty() ? "final" : o.buffer) +
                    "' in frame " + std::to_string(single_frame) + " (see --buffer, --frame)");
    for (std::size_t k = 0; k < files.size(); ++k)
        if (!used[k]) {
            report.ignored.push_back(files[k]);
            report.ignored_hint.push_back(closest_buffer_file(files[k], manifest));
        }
}

// A golden image: one item, the candidate image.
void collect_image_item(const DiffOptions& o, bool candidate_dir, DiffReport& report,
                        ItemInputs& inputs) {
    if (candidate_dir)
        throw Error("a golden image (" + o.golden +
                    ") is compared with one candidate image, not a directory");
    if (!o.require.empty()) throw Error("--require needs a golden bundle directory");
    DiffItem item;
    item.name = fs::path(o.golden).stem().string();
    item.stage = "-";
    item.golden_file = o.golden;
    item.candidate_file = o.candidate;
    // Both sides are read alike: PNGs sRGB-decoded unless --png-linear.
    item.kind = o.png_linear ? "scalar" : "color";
    item.golden = load_image(o, o.golden, item.kind, 0, 0, 0, nullptr);
    inputs.distances.push_back(o.distance_px);
    inputs.expected_sha.push_back("");
    report.items.push_back(std::move(item));
}

// The mask of value buffer `item` among items [first, end) of one frame: the pixels where every
// compared id buffer of its size agrees (empty: none, or --no-id-mask); names them in
// item.masked_by.
std::vector<std::uint8_t> id_mask(const DiffOptions& o, DiffReport& report, std::size_t first,
                                  std::size_t end, DiffItem& item) {
    std::vector<std::uint8_t> mask;
    if (o.no_id_mask || item.hash_only || item.candidate_file.empty()) return mask;
    for (std::size_t i = first; i < end; ++i) {
        const DiffItem& ids = report.items[i];
        if (!ids.is_id || !ids.compared || ids.hash_only || ids.golden.width != item.golden.width ||
            ids.golden.height != item.golden.height)
            continue;
        if (mask.empty()) mask.assign(ids.ids.agree.size(), 1);
        for (std::size_t p = 0; p < mask.size(); ++p) mask[p] &= ids.ids.agree[p];
        item.masked_by.push_back(ids.name);
    }
    return mask;
}

// Compares frame by frame: the id buffers of a frame first, then its other buffers where the
// ids agree (unless --no-id-mask), each group in comparison order.
void compare_items(const DiffOptions& o, const ToleranceTable& tolerances, const ItemInputs& inputs,
                   DiffReport& report) {
    auto compare_at = [&](std::size_t k, const std::vector<std::uint8_t>* mask) {
        DiffItem& item = report.items[k];
        if (item.candidate_file.empty()) {
            ++report.missing;
            item.note = item.required ? "missing in the candidate, and required (--require)"
                                      : "missing in the candidate: not compared";
            if (item.required) {
                item.pass = false;
                ++report.missing_required;
            }
            return;
        }
        compare_item(o, tolerances, o.distance_px > 0.0f ? o.distance_px : inputs.distances[k],
                     item, inputs.expected_sha[k], mask);
        ++report.compared;
    };
    for (std::size_t first = 0; first < report.items.size();) {
        std::size_t end = first;
        while (end < report.items.size() && report.items[end].frame == report.items[first].frame)
            ++end;
        for (std::size_t k = first; k < end; ++k)
            if (report.items[k].is_id) compare_at(k, nullptr);
        for (std::size_t k = first; k < end; ++k) {
            if (report.items[k].is_id) continue;
            const std::vector<std::uint8_t> mask = id_mask(o, report, first, end, report.items[k]);
            compare_at(k, mask.empty() ? nullptr : &mask);
        }
        first = end;
    }
}

json report_json(const DiffOptions& o, const DiffReport& report) {
    json j;
    j["golden"] = o.golden;
    j["candidate"] = o.candidate;
    if (!report.case_name.empty()) j["case"] = report.case_name;
    j["profile"] = report.profile;
    j["pass"] = report.pass;
    j["compared"] = report.compared;
    j["failed"] = report.failed;
    j["missing"] = report.missing;
    j["missing_required"] = report.missing_required;
    j["ignored_files"] = report.ignored;
    if (report.first_failing >= 0) {
        const DiffItem& f = report.items[static_cast<std::size_t>(report.first_failing)];
        j["first_failing"] = {{"frame", f.frame}, {"buffer", f.name}, {"stage", f.stage}};
        if (!report.probe_command.empty()) j["probe_command"] = report.probe_command;
    }
    j["buffers"] = json::array();
    for (const DiffItem& item : report.items) j["buffers"].push_back(item_json(item));
    return j;
}

}  // namespace

int run_diff(const DiffOptions& o) {
    if (o.flip && o.distance_px > 0.0f) {
        char text[48];
        std::snprintf(text, sizeof text, "--distance-px %g", static_cast<double>(o.distance_px));
        check_flip_viewing_distance(o.distance_px, text);
    }
    ToleranceTable tolerances = tolerance_profile(o.profile);
    if (!o.tolerance_file.empty()) read_tolerance_file(o.tolerance_file, tolerances);
    for (const std::string& t : o.tolerances) parse_tolerance_option(t, tolerances);
    if (!fs::exists(o.golden)) throw Error(o.golden + ": no such file or directory");
    if (!fs::exists(o.candidate)) throw Error(o.candidate + ": no such file or directory");

    DiffReport report;
    report.golden = o.golden;
    report.candidate = o.candidate;
    report.profile = o.profile;
    const bool golden_bundle = fs::is_directory(o.golden);
    const bool candidate_dir = fs::is_directory(o.candidate);
    Manifest manifest;
    ItemInputs inputs;
    if (golden_bundle) {
        manifest = read_manifest(o.golden);
        collect_bundle_items(o, manifest, candidate_dir, report, inputs);
    } else {
        collect_image_item(o, candidate_dir, report, inputs);
    }

    compare_items(o, tolerances, inputs, report);
    for (std::size_t k = 0; k < report.items.size(); ++k)
        if (!report.items[k].pass) {
            ++report.failed;
            if (report.first_failing < 0) report.first_failing = static_cast<int>(k);
        }
    if (report.compared == 0)
        throw Error("nothing to compare: no file in " + o.candidate +
                    " is named like a buffer of " + o.golden +
                    " (expected e.g. f000_final.pfm or final.pfm; see `fovref diff --help`)");
    report.pass = report.failed == 0;
    if (report.first_failing >= 0 && golden_bundle) {
        const DiffItem& item = report.items[static_cast<std::size_t>(report.first_failing)];
        int x = 0, y = 0;
        if (item.focus_pixel(x, y)) report.probe_command = probe_command(manifest, item, x, y);
    }

    // Reports.
    if (!o.json_path.empty()) {
        const std::string text = report_json(o, report).dump(1) + "\n";
        if (o.json_path == "-")
            std::cout << text;
        else
            write_file_atomic(o.json_path, text);
    }
    if (!o.html_dir.empty()) write_diff_html(report, o.html_dir);
    if (!o.quiet && o.json_path != "-") print_summary(report);
    return report.pass ? 0 : 1;
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
