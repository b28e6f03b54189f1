#include "tools/diff.h"

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
#include "tools/diff_report.h"
#include "tools/report_json.h"

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

std::string format(double v) {
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    if (std::isnan(v)) return "-";
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

std::string values_text(const std::vector<float>& values) {
    std::string out = "(";
    for (std::size_t i = 0; i < values.size(); ++i) {
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(values[i]));
        out += (i ? ", " : "") + std::string(text);
    }
    return out + ")";
}

std::string probe_command(const Manifest& m, const DiffItem& item, const PixelDifference& pixel) {
    const GoldenCase& c = m.golden_case;
    if (c.scene.empty() && c.mode.empty()) return "";
    std::string command = "fovref probe";
    if (!c.scene.empty()) command += " --scene " + c.scene;
    command += " --mode " + c.mode + " --width " + std::to_string(c.width) + " --height " +
               std::to_string(c.height);
    if (c.time_start != 0.0f) command += " --time-start " + format(c.time_start);
    if (c.frames > 1 || item.frame > 0) command += " --time-step " + format(c.time_step);
    command += " --frame " + std::to_string(item.frame) + " --pixel " + std::to_string(pixel.x) +
               "," + std::to_string(pixel.y);
    for (const auto& [key, value] : c.params.values()) command += " --param " + key + "=" + value;
    return command;
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
                  DiffItem& item, const std::string& expected_sha) {
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
    item.result = compare_buffers(item.name, item.golden, item.candidate, tolerance, options);
    if (o.flip && item.kind == "color" && item.golden.channels == 3) {
        // LDR-FLIP on what a viewer sees (SPEC §10), pixels per degree from the display model.
        FlipParams fp;
        fp.pixels_per_degree = flip_pixels_per_degree(
            distance_px > 0.0f ? distance_px : default_distance_px(item.golden.height));
        item.flip = ldr_flip(to_display(item.golden), to_display(item.candidate), fp);
    }
    item.compared = true;
    item.pass = item.result.pass;
    item.note = note;
}

json item_json(const DiffItem& item) {
    json j;
    j["frame"] = item.frame;
    j["name"] = item.name;
    j["stage"] = item.stage;
    j["kind"] = item.kind;
    j["golden_file"] = item.golden_file;
    j["candidate_file"] = item.candidate_file.empty() ? json(nullptr) : json(item.candidate_file);
    j["status"] = !item.compared ? "missing" : item.pass ? "pass" : "fail";
    if (!item.note.empty()) j["note"] = item.note;
    if (!item.compared || item.hash_only) return j;
    const BufferComparison& r = item.result;
    j["width"] = r.width;
    j["height"] = r.height;
    j["channels"] = r.channels;
    j["tolerance"] = {{"abs", r.tolerance.abs},
                      {"rel", r.tolerance.rel},
                      {"ulp", r.tolerance.ulp},
                      {"max_failing_pixels", r.tolerance.max_failing_pixels},
                      {"reason", r.tolerance.reason}};
    j["max_abs_error"] = number_json(r.max_abs);
    j["max_rel_error"] = number_json(r.max_rel);
    j["max_ulp"] = r.max_ulp;
    j["nan_mismatches"] = r.nan_mismatches;
    j["differing_elements"] = r.differing_elements;
    j["mean_abs_error"] = number_json(r.mean_abs);
    j["rmse"] = number_json(r.rmse);
    j["psnr"] = number_json(r.psnr);
    j["ssim"] = r.ssim ? number_json(*r.ssim) : json(nullptr);
    j["threshold"] = r.threshold;
    j["pixels_over_threshold"] = r.pixels_over_threshold;
    j["share_over_threshold"] =
        static_cast<double>(r.pixels_over_threshold) / static_cast<double>(r.width * r.height);
    j["failing_pixels"] = r.failing_pixels;
    auto pixel_json = [](const PixelDifference& d) {
        return json{{"x", d.x},
                    {"y", d.y},
                    {"abs_error", number_json(d.abs_error)},
                    {"golden", d.golden},
                    {"candidate", d.candidate}};
    };
    if (r.first_failing) j["first_failing_pixel"] = pixel_json(*r.first_failing);
    j["worst_pixels"] = json::array();
    for (const PixelDifference& d : r.worst) j["worst_pixels"].push_back(pixel_json(d));
    if (item.flip)
        j["flip"] = {{"mean", item.flip->mean},
                     {"weighted_median", item.flip->weighted_median},
                     {"first_quartile", item.flip->first_quartile},
                     {"third_quartile", item.flip->third_quartile},
                     {"max", item.flip->max}};
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

void print_summary(const DiffReport& report) {
    std::printf("fovref diff: golden %s%s, candidate %s\n", report.golden.c_str(),
                report.case_name.empty() ? "" : (" (case " + report.case_name + ")").c_str(),
                report.candidate.c_str());
    std::printf("%-5s %-20s %-26s %-7s %10s %9s %10s %8s %8s\n", "frame", "stage", "buffer",
                "result", "max abs", "max ulp", "fail px", "PSNR", "SSIM");
    for (const DiffItem& item : report.items) {
        const char* status = !item.compared ? "missing" : item.pass ? "pass" : "FAIL";
        if (!item.compared || item.hash_only) {
            std::printf("%-5d %-20s %-26s %-7s %s\n", item.frame, item.stage.c_str(),
                        item.name.c_str(), status, item.note.c_str());
            continue;
        }
        const BufferComparison& r = item.result;
        std::printf("%-5d %-20s %-26s %-7s %10s %9lld %10lld %8s %8s\n", item.frame,
                    item.stage.c_str(), item.name.c_str(), status, format(r.max_abs).c_str(),
                    static_cast<long long>(r.max_ulp), static_cast<long long>(r.failing_pixels),
                    format(r.psnr).c_str(), r.ssim ? format(*r.ssim).c_str() : "-");
    }
    for (const std::string& f : report.ignored)
        std::printf("ignored: %s (matches no golden buffer)\n", f.c_str());
    if (report.first_failing >= 0) {
        const DiffItem& item = report.items[static_cast<std::size_t>(report.first_failing)];
        std::printf("first failing stage: %s, buffer '%s', frame %d", item.stage.c_str(),
                    item.name.c_str(), item.frame);
        if (item.hash_only) {
            std::printf(": %s\n", item.note.c_str());
        } else {
            const BufferComparison& r = item.result;
            std::printf(
                ": %lld pixel(s) out of tolerance (abs %s, rel %s, ulp %lld, %lld allowed)\n",
                static_cast<long long>(r.failing_pixels), format(r.tolerance.abs).c_str(),
                format(r.tolerance.rel).c_str(), static_cast<long long>(r.tolerance.ulp),
                static_cast<long long>(r.tolerance.max_failing_pixels));
            if (r.first_failing)
                std::printf("  first failing pixel (%d, %d): golden %s, candidate %s\n",
                            r.first_failing->x, r.first_failing->y,
                            values_text(r.first_failing->golden).c_str(),
                            values_text(r.first_failing->candidate).c_str());
            if (!r.worst.empty())
                std::printf("  worst pixel (%d, %d): |error| %s, golden %s, candidate %s\n",
                            r.worst[0].x, r.worst[0].y, format(r.worst[0].abs_error).c_str(),
                            values_text(r.worst[0].golden).c_str(),
                            values_text(r.worst[0].candidate).c_str());
        }
        if (!report.probe_command.empty())
            std::printf("  explain it: %s\n", report.probe_command.c_str());
    }
    std::printf("RESULT: %s (%d compared, %d out of tolerance, %d missing in the candidate)\n",
                report.pass ? "PASS" : "FAIL", report.compared, report.failed, report.missing);
}

}  // namespace

void add_diff_options(CLI::App& c, DiffOptions& o) {
    c.add_option("GOLDEN", o.golden, "golden bundle directory (manifest.json) or image file")
        ->required();
    c.add_option("CANDIDATE", o.candidate,
                 "directory of buffers named as in the manifest (f000_final.pfm or final.pfm, "
                 "...) or one image file")
        ->required();
    c.add_option("--tolerance", o.tolerances,
                 "NAME:abs=X,rel=X,ulp=N,pixels=N (NAME may be '*'; repeatable)");
    c.add_option("--tolerance-file", o.tolerance_file,
                 "JSON: {\"buffer\": {\"abs\": x, \"rel\": x, \"ulp\": n, "
                 "\"max_failing_pixels\": n, \"reason\": \"...\"}}");
    c.add_option("--json", o.json_path, "write the JSON report to FILE ('-' = stdout)");
    c.add_option("--html", o.html_dir, "write a self-contained HTML report to DIR/index.html");
    c.add_option("--buffer", o.buffer,
                 "candidate is one file: the golden buffer it is compared with (default final)");
    c.add_option("--frame", o.frame, "compare only this frame")->check(CLI::Range(0, 1000000));
    c.add_option("--threshold", o.threshold,
                 "absolute error counted as 'over threshold' (default: the tolerance's abs)");
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
               "also LDR-FLIP (NVlabs v1.x) of colour buffers, in display space (slow: seconds "
               "per megapixel)");
    c.add_option("--distance-px", o.distance_px,
                 "viewing distance in pixels (default: the bundle's display model, else a 60 "
                 "degree vertical field of view)")
        ->check(CLI::Range(1e-3, 1e9));
}

int run_diff(const DiffOptions& o) {
    ToleranceTable tolerances;
    if (!o.tolerance_file.empty()) tolerances = read_tolerance_file(o.tolerance_file);
    for (const std::string& t : o.tolerances) parse_tolerance_option(t, tolerances);
    if (!fs::exists(o.golden)) throw Error(o.golden + ": no such file or directory");
    if (!fs::exists(o.candidate)) throw Error(o.candidate + ": no such file or directory");

    DiffReport report;
    report.golden = o.golden;
    report.candidate = o.candidate;
    const bool golden_bundle = fs::is_directory(o.golden);
    const bool candidate_dir = fs::is_directory(o.candidate);
    Manifest manifest;
    std::vector<std::string> expected_sha;  // per item, for hash-only golden buffers
    std::vector<float> distances;           // per item

    if (golden_bundle) {
        manifest = read_manifest(o.golden);
        report.case_name = manifest.golden_case.name;
        report.mode = manifest.golden_case.mode;
        report.scene = manifest.golden_case.scene;
        std::vector<std::string> files;
        if (candidate_dir) files = list_files(o.candidate);
        std::vector<bool> used(files.size(), false);
        const int frames = static_cast<int>(manifest.frame_counters.size());
        const int single_frame = o.frame >= 0 ? o.frame : 0;
        bool found_buffer = false;
        for (const ManifestBuffer& b : manifest.buffers) {
            if (o.frame >= 0 && b.frame != o.frame) continue;
            DiffItem item;
            item.frame = b.frame;
            item.name = b.name;
            item.stage = b.stage;
            item.kind = b.kind;
            item.golden_file = b.file.empty() ? "" : (fs::path(o.golden) / b.file).string();
            item.hash_only = b.file.empty();
            if (candidate_dir) {
                // f000_name.ext, or name.ext for a bundle of one frame / the --frame asked for.
                char prefix[16];
                std::snprintf(prefix, sizeof prefix, "f%03d_", b.frame);
                std::vector<std::string> stems = {prefix + b.name};
                if (frames <= 1 || o.frame >= 0) stems.push_back(b.name);
                for (const std::string& stem : stems) {
                    for (const std::string& ext : candidate_extensions)
                        for (std::size_t k = 0; k < files.size(); ++k)
                            if (!used[k] && files[k].size() == stem.size() + ext.size() &&
                                files[k].compare(0, stem.size(), stem) == 0 &&
                                lower_extension(files[k]) == ext && item.candidate_file.empty()) {
                                item.candidate_file = (fs::path(o.candidate) / files[k]).string();
                                used[k] = true;
                            }
                }
            } else if (b.frame == single_frame &&
                       b.name == (o.buffer.empty() ? "final" : o.buffer)) {
                item.candidate_file = o.candidate;
                found_buffer = true;
            } else {
                continue;  // one candidate file: only its buffer is listed
            }
            const auto f = static_cast<std::size_t>(b.frame);
            distances.push_back(
                f < manifest.display_distance_px.size() ? manifest.display_distance_px[f] : 0.0f);
            expected_sha.push_back(b.sha256);
            if (!item.hash_only && !item.candidate_file.empty())
                item.golden =
                    load_image(o, item.golden_file, b.kind, b.width, b.height, b.channels, nullptr);
            report.items.push_back(std::move(item));
        }
        if (!candidate_dir && !found_buffer)
            throw Error(o.golden + ": has no buffer '" + (o.buffer.empty() ? "final" : o.buffer) +
                        "' in frame " + std::to_string(single_frame) + " (see --buffer, --frame)");
        for (std::size_t k = 0; k < files.size(); ++k)
            if (!used[k]) report.ignored.push_back(files[k]);
    } else {
        if (candidate_dir)
            throw Error("a golden image (" + o.golden +
                        ") is compared with one candidate image, not a directory");
        DiffItem item;
        item.name = fs::path(o.golden).stem().string();
        item.stage = "-";
        item.golden_file = o.golden;
        item.candidate_file = o.candidate;
        // Both sides are read alike: PNGs sRGB-decoded unless --png-linear.
        item.kind = o.png_linear ? "scalar" : "color";
        item.golden = load_image(o, o.golden, item.kind, 0, 0, 0, nullptr);
        distances.push_back(o.distance_px);
        expected_sha.push_back("");
        report.items.push_back(std::move(item));
    }

    for (std::size_t k = 0; k < report.items.size(); ++k) {
        DiffItem& item = report.items[k];
        if (item.candidate_file.empty()) {
            ++report.missing;
            item.note = "missing in the candidate: not compared";
            continue;
        }
        compare_item(o, tolerances, o.distance_px > 0.0f ? o.distance_px : distances[k], item,
                     expected_sha[k]);
        ++report.compared;
        if (!item.pass) {
            ++report.failed;
            if (report.first_failing < 0) report.first_failing = static_cast<int>(k);
        }
    }
    if (report.compared == 0)
        throw Error("nothing to compare: no file in " + o.candidate +
                    " is named like a buffer of " + o.golden +
                    " (expected e.g. f000_final.pfm or final.pfm; see `fovref diff --help`)");
    report.pass = report.failed == 0;
    if (report.first_failing >= 0 && golden_bundle) {
        const DiffItem& item = report.items[static_cast<std::size_t>(report.first_failing)];
        if (!item.hash_only && !item.result.worst.empty())
            report.probe_command = probe_command(manifest, item, item.result.worst[0]);
    }

    // Reports.
    if (!o.json_path.empty()) {
        json j;
        j["golden"] = o.golden;
        j["candidate"] = o.candidate;
        if (!report.case_name.empty()) j["case"] = report.case_name;
        j["pass"] = report.pass;
        j["compared"] = report.compared;
        j["failed"] = report.failed;
        j["missing"] = report.missing;
        j["ignored_files"] = report.ignored;
        if (report.first_failing >= 0) {
            const DiffItem& f = report.items[static_cast<std::size_t>(report.first_failing)];
            j["first_failing"] = {{"frame", f.frame}, {"buffer", f.name}, {"stage", f.stage}};
            if (!report.probe_command.empty()) j["probe_command"] = report.probe_command;
        }
        j["buffers"] = json::array();
        for (const DiffItem& item : report.items) j["buffers"].push_back(item_json(item));
        const std::string text = j.dump(1) + "\n";
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
