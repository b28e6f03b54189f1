#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>

#include "ref/core/error.h"
#include "ref/image/image_io.h"
#include "tools/cli/commands/diff/internal.h"

namespace fs = std::filesystem;

namespace fovref {

namespace {

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

}  // namespace

std::vector<std::string> nearest_names(const std::string& name,
                                       const std::vector<std::string>& names, std::size_t count) {
    std::vector<std::pair<std::size_t, std::size_t>> ranked;  // (distance, index)
    for (std::size_t k = 0; k < names.size(); ++k)
        ranked.emplace_back(edit_distance(name, names[k]), k);
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<std::string> out;
    for (std::size_t k = 0; k < ranked.size() && out.size() < count; ++k)
        out.push_back(names[ranked[k].second]);
    return out;
}

namespace {

// A GPU client's port.json as "key: value" lines (strings as they are, other values as JSON); a
// file that is not a JSON object gives one line saying so (the record is informative only).
std::vector<std::string> port_lines(const std::string& path) {
    std::vector<std::string> lines;
    try {
        const nlohmann::json j = nlohmann::json::parse(read_file(path));
        if (!j.is_object()) return {path + ": not a JSON object (ignored)"};
        for (auto it = j.begin(); it != j.end(); ++it)
            lines.push_back(
                it.key() + ": " +
                (it.value().is_string() ? it.value().get<std::string>() : it.value().dump()));
    } catch (const std::exception& e) {
        lines = {path + ": not valid JSON (ignored): " + e.what()};
    }
    return lines;
}

// Candidate files of a directory, sorted by name (a fixed order).
std::vector<std::string> list_files(const std::string& directory) {
    std::vector<std::string> files;
    for (const auto& entry : fs::directory_iterator(directory))
        if (entry.is_regular_file()) files.push_back(entry.path().filename().string());
    std::sort(files.begin(), files.end());
    return files;
}

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
        // A name, or a pattern (`*` wildcards) that must match some buffer
        const bool pattern = name.find('*') != std::string::npos;
        std::vector<std::string> all;
        bool known = false;
        for (const ManifestBuffer& b : manifest.buffers) {
            if (std::find(all.begin(), all.end(), b.name) == all.end()) all.push_back(b.name);
            if (pattern ? tolerance_pattern_matches(name, b.name) : b.name == name) {
                known = true;
                if (std::find(names.begin(), names.end(), b.name) == names.end())
                    names.push_back(b.name);
            }
        }
        if (!known) {
            std::string nearest;
            for (const std::string& n : nearest_names(name, all))
                nearest += (nearest.empty() ? "" : ", ") + n;
            throw Error("--require: " +
                        (pattern ? "the pattern '" + name + "' matches no buffer of the golden"
                                 : "the golden has no buffer '" + name + "'") +
                        " (nearest: " + nearest + ")");
        }
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

}  // namespace

Image load_image(const DiffOptions& o, const std::string& path, const std::string& kind, int width,
                 int height, int channels, std::string* note) {
    Image image;
    if (is_raw(path)) {
        if (o.raw_size.empty() && width == 0)
            throw Error(path + ": a raw binary32 file needs --raw-size WxH[xC]");
        image = read_raw(path, raw_layout(o, width, height, channels));
    } else if (lower_extension(path) == ".png") {
        image = read_png(path, !o.png_linear && kind == "color");
    } else if (std::find(candidate_extensions.begin(), candidate_extensions.end(),
                         lower_extension(path)) != candidate_extensions.end()) {
        image = read_image(path);
    } else {
        std::string list;
        for (const std::string& ext : candidate_extensions)
            list += (list.empty() ? "" : ", ") + ext;
        throw Error(path + ": unknown image extension \"" + lower_extension(path) +
                    "\" (expected " + list +
                    "; .raw, .bin and .f32 are raw binary32 with "
                    "--raw-size WxH[xC])");
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

void collect_bundle_items(const DiffOptions& o, const Manifest& manifest, bool candidate_dir,
                          DiffReport& report, ItemInputs& inputs) {
    report.case_name = manifest.golden_case.name;
    report.mode = manifest.golden_case.mode;
    report.scene = manifest.golden_case.scene;
    inputs.screen_width = manifest.golden_case.width;
    inputs.screen_height = manifest.golden_case.height;
    const std::vector<std::string> required = required_names(o.require, manifest);
    std::vector<std::string> files;
    if (candidate_dir) files = list_files(o.candidate);
    std::vector<bool> used(files.size(), false);
    for (std::size_t k = 0; k < files.size(); ++k)
        if (files[k] == "port.json") {
            used[k] = true;
            report.port = port_lines((fs::path(o.candidate) / files[k]).string());
        }
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
        item.space = space_of(manifest.golden_case.mode, b.name);
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
            // A suggestion only when it names another file (not f000_final.png for itself: a
            // preview beside the f000_final.pfm that was compared)
            const std::string hint = closest_buffer_file(files[k], manifest);
            report.ignored.push_back(files[k]);
            report.ignored_hint.push_back(hint == files[k] ? "" : hint);
        }
}

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

}  // namespace fovref
