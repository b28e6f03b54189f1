#include "ref/golden/bundle.h"

#include <algorithm>
#include <bit>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <system_error>

#include "ref/core/error.h"
#include "ref/core/json_locator.h"
#include "ref/image/image_io.h"
#include "ref/scene/procedural.h"
#include "ref/scene/scene_file.h"

#ifndef FOVREF_VERSION
#define FOVREF_VERSION "unknown"
#endif
#ifndef FOVREF_COMPILER
#define FOVREF_COMPILER "unknown"
#endif
#ifndef FOVREF_BUILD_FLAGS
#define FOVREF_BUILD_FLAGS "unknown"
#endif

namespace fovref {

namespace fs = std::filesystem;
using json = nlohmann::ordered_json;

std::string fovref_version() { return FOVREF_VERSION; }
std::string fovref_compiler() { return FOVREF_COMPILER; }
std::string fovref_build_flags() { return FOVREF_BUILD_FLAGS; }

// ---- Cases ----------------------------------------------------------------------------------

namespace {

json case_to_json(const GoldenCase& c) {
    json j;
    j["name"] = c.name;
    if (!c.description.empty()) j["description"] = c.description;
    j["scene"] = c.scene;
    j["mode"] = c.mode;
    j["width"] = c.width;
    j["height"] = c.height;
    j["frames"] = c.frames;
    j["time_start"] = c.time_start;
    j["time_step"] = c.time_step;
    j["params"] = json(c.params.values());
    if (c.files != "all") j["files"] = c.files;
    return j;
}

// A case object at `pointer` of `path` (golden/cases.json or a manifest); errors name the file,
// the line (from `locator`) and the key.
GoldenCase case_from_json(const json& j, const std::string& path, const std::string& pointer,
                          const JsonLocator& locator) {
    auto fail = [&](const std::string& at, const std::string& message) {
        return file_error(path, locator.find(at).key_line,
                          (pointer.empty() ? std::string("case") : pointer) + ": " + message);
    };
    if (!j.is_object()) throw fail(pointer, "a case must be a JSON object");
    static const char* known[] = {"name",   "description", "scene",     "mode",   "width", "height",
                                  "frames", "time_start",  "time_step", "params", "files"};
    for (const auto& item : j.items()) {
        bool ok = false;
        for (const char* k : known) ok = ok || item.key() == k;
        if (!ok)
            throw fail(json_pointer_member(pointer, item.key()),
                       "unknown key '" + item.key() + "'");
    }
    auto value = [&](const char* key, bool required) -> const json* {
        const auto it = j.find(key);
        if (it == j.end()) {
            if (required) throw fail(pointer, std::string("missing key '") + key + "'");
            return nullptr;
        }
        return &*it;
    };
    auto text = [&](const char* key, bool required) {
        const json* v = value(key, required);
        if (!v) return std::string();
        if (!v->is_string())
            throw fail(json_pointer_member(pointer, key),
                       std::string("'") + key + "' must be a string, got " + v->type_name());
        return v->get<std::string>();
    };
    auto integer = [&](const char* key, bool required, int fallback) {
        const json* v = value(key, required);
        if (!v) return fallback;
        if (!v->is_number_integer() ||
            (v->is_number_unsigned() && v->get<std::uint64_t>() > 1u << 30) ||
            v->get<std::int64_t>() < -(1 << 30) || v->get<std::int64_t>() > (1 << 30))
            throw fail(
                json_pointer_member(pointer, key),
                std::string("'") + key + "' must be an integer in [-2^30, 2^30], got " + v->dump());
        return static_cast<int>(v->get<std::int64_t>());
    };
    auto number = [&](const char* key, float fallback) {
        const json* v = value(key, false);
        if (!v) return fallback;
        if (!v->is_number())
            throw fail(json_pointer_member(pointer, key),
                       std::string("'") + key + "' must be a number, got " + v->type_name());
        return static_cast<float>(v->get<double>());
    };
    GoldenCase c;
    c.name = text("name", true);
    c.description = text("description", false);
    c.scene = text("scene", false);
    c.mode = text("mode", true);
    c.width = integer("width", true, 0);
    c.height = integer("height", true, 0);
    c.frames = integer("frames", false, 1);
    c.time_start = number("time_start", 0.0f);
    c.time_step = number("time_step", 1.0f / 30);
    if (value("files", false)) {
        c.files = text("files", false);
        if (c.files != "all" && c.files != "last-frame")
            throw fail(json_pointer_member(pointer, "files"),
                       "'files' must be \"all\" or \"last-frame\", got \"" + c.files + "\"");
    }
    if (const json* params = value("params", false)) {
        if (!params->is_object())
            throw fail(json_pointer_member(pointer, "params"), "'params' must be an object");
        for (const auto& item : params->items())
            c.params.set(item.key(), item.value().is_string() ? item.value().get<std::string>()
                                                              : item.value().dump());
    }
    auto where_fail = [&](const std::string& message) { return fail(pointer, message); };
    if (c.name.empty() || c.name.find_first_of("/\\. ") != std::string::npos)
        throw where_fail("case name '" + c.name +
                         "' must be non-empty without '/', '\\', '.' or spaces");
    return c;
}

}  // namespace

std::vector<GoldenCase> load_golden_cases(const std::string& path) {
    const std::string text = read_file(path);
    json document = parse_json_document<json>(text, path);
    const JsonLocator locator(text, path);
    if (!document.is_object() || !document.contains("cases") || !document["cases"].is_array())
        throw Error(path + ": expected an object with a \"cases\" array");
    std::vector<GoldenCase> cases;
    for (std::size_t k = 0; k < document["cases"].size(); ++k) {
        GoldenCase c =
            case_from_json(document["cases"][k], path, json_pointer_element("/cases", k), locator);
        for (const GoldenCase& other : cases)
            if (other.name == c.name)
                throw Error(path + ": case '" + c.name + "' is defined twice");
        cases.push_back(std::move(c));
    }
    return cases;
}

const GoldenCase& find_golden_case(const std::vector<GoldenCase>& cases, const std::string& name) {
    for (const GoldenCase& c : cases)
        if (c.name == name) return c;
    std::vector<std::string> names;
    for (const GoldenCase& c : cases) names.push_back(c.name);
    throw Error("unknown golden case '" + name + "' (cases: " + join_names(names) + ")");
}

const Scene* SceneCache::get(const std::string& scene) {
    if (scene.empty()) return nullptr;
    auto it = scenes_.find(scene);
    if (it != scenes_.end()) return &it->second;
    std::string path = scene;
    if (!is_procedural_scene(scene) && !fs::path(scene).is_absolute())
        path = (fs::path(base_dir_) / scene).string();
    return &scenes_.emplace(scene, load_scene(path)).first->second;
}

RenderSettings case_settings(const GoldenCase& golden_case,
                             const std::vector<std::string>& requested,
                             const std::function<void(double)>& progress) {
    RenderSettings settings;
    settings.width = golden_case.width;
    settings.height = golden_case.height;
    settings.frame_count = golden_case.frames;
    settings.time_start = golden_case.time_start;
    settings.time_step = golden_case.time_step;
    settings.params = golden_case.params;
    settings.requested = requested;
    settings.progress = progress;
    return settings;
}

// ---- Writing ---------------------------------------------------------------------------------

namespace {

constexpr const char* bundle_format = "fovref-bundle-1";

std::string buffer_file_name(int frame, const Buffer& buffer, const char* extension = nullptr) {
    char prefix[32];
    std::snprintf(prefix, sizeof prefix, "f%03d_", frame);
    const bool pfm = buffer.image.channels == 1 || buffer.image.channels == 3;
    return prefix + buffer.name + (extension ? extension : pfm ? ".pfm" : ".exr");
}

json counters_to_json(const Counters& counters) {
    json j = json::object();
    for (const auto& [key, value] : counters.values) j[key] = value;
    return j;
}

// The image's floats as stored in memory (little-endian on every platform fovref builds on).
void write_raw_binary32(const std::string& path, const Image& image) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(image.data.data()),
              static_cast<std::streamsize>(image.data.size() * sizeof(float)));
    if (!out) throw Error(path + ": cannot write");
}

// Rows [first, first + count) as their own image.
Image row_block(const Image& image, int first, int count) {
    Image block(image.width, count, image.channels);
    const std::size_t row = static_cast<std::size_t>(image.width) * image.channels;
    std::copy(image.data.begin() + static_cast<std::ptrdiff_t>(first * row),
              image.data.begin() + static_cast<std::ptrdiff_t>((first + count) * row),
              block.data.begin());
    return block;
}

std::vector<std::string> block_hashes(const Image& image, int block_rows) {
    std::vector<std::string> hashes;
    for (int first = 0; first < image.height; first += block_rows)
        hashes.push_back(
            canonical_sha256(row_block(image, first, std::min(block_rows, image.height - first))));
    return hashes;
}

// The target as a clean path: no trailing separator, not '.', '..' or a root.
fs::path bundle_target(const std::string& directory) {
    fs::path target = fs::path(directory).lexically_normal();
    if (!target.empty() && target.filename().empty()) target = target.parent_path();
    // A symbolic link is written through: the bundle replaces the directory it points to (the
    // staging directory is made beside that one), and the link stays (docs/limits.md, Outputs).
    for (int hop = 0; hop < 40; ++hop) {
        std::error_code ec;
        if (!fs::is_symlink(fs::symlink_status(target, ec))) break;
        const fs::path link = fs::read_symlink(target, ec);
        if (ec) throw Error(directory + ": cannot read the symbolic link: " + ec.message());
        target = (link.is_absolute() ? link : target.parent_path() / link).lexically_normal();
    }
    const std::string name = target.filename().string();
    if (target.empty() || name.empty() || name == "." || name == ".." ||
        target == target.root_path())
        throw Error("'" + directory +
                    "': not usable as a bundle directory (name a new or existing bundle "
                    "directory)");
    return target;
}

bool is_bundle_directory(const fs::path& directory) {
    std::error_code ec;
    if (fs::is_empty(directory, ec) && !ec) return true;
    const fs::path manifest = directory / "manifest.json";
    if (!fs::is_regular_file(manifest, ec)) return false;
    try {
        const json j = parse_json_document<json>(read_file(manifest.string()), manifest.string());
        return j.is_object() && j.value("format", "") == bundle_format;
    } catch (const std::exception&) {
        return false;
    }
}

}  // namespace

int hash_block_rows(int height) { return std::max(1, (height + 255) / 256); }

struct BundleWriter::State {
    fs::path target, staging, previous;
    GoldenCase golden_case;
    BundleOptions options;
    json frames = json::array();
    std::string scene_export;  ///< "" or the bundle-relative directory of the exported scene
    bool committed = false;
};

BundleWriter::BundleWriter(const std::string& directory, GoldenCase golden_case,
                           BundleOptions options)
    : state_(std::make_unique<State>()) {
    State& s = *state_;
    s.target = bundle_target(directory);
    s.golden_case = std::move(golden_case);
    s.options = options;
    std::error_code ec;
    if (fs::exists(s.target, ec)) {
        if (!fs::is_directory(s.target, ec))
            throw Error(s.target.string() + ": exists and is not a directory; not overwritten");
        if (!is_bundle_directory(s.target))
            throw Error(s.target.string() +
                        ": exists and is not a fovref bundle (no manifest.json of format " +
                        bundle_format +
                        "); not overwritten: remove it or choose another directory");
    }
    const fs::path parent = s.target.has_parent_path() ? s.target.parent_path() : fs::path(".");
    s.staging = parent / (s.target.filename().string() + ".writing");
    s.previous = parent / (s.target.filename().string() + ".previous");
    fs::create_directories(parent, ec);
    fs::remove_all(s.staging, ec);
    fs::create_directories(s.staging, ec);
    if (ec) throw Error(s.staging.string() + ": cannot create directory: " + ec.message());
}

BundleWriter::~BundleWriter() {
    if (state_ && !state_->committed) {
        std::error_code ec;
        fs::remove_all(state_->staging, ec);  // nothing half-written is left behind
    }
}

void BundleWriter::add_frame(const FrameResult& frame, const std::vector<std::string>* only) {
    State& s = *state_;
    json jf;
    jf["frame"] = frame.frame;
    jf["time"] = frame.time;
    if (frame.display_distance_px > 0.0f) jf["display_distance_px"] = frame.display_distance_px;
    if (frame.camera) {
        // Binary32 values as doubles: nlohmann writes the shortest decimal that reads back as
        // the same double, hence the same float.
        auto vec = [](glm::vec3 v) { return json::array({v.x, v.y, v.z}); };
        const Camera& c = *frame.camera;
        jf["camera"] = {{"position", vec(c.position)},
                        {"right", vec(c.right)},
                        {"up", vec(c.up)},
                        {"forward", vec(c.forward)},
                        {"vfov_deg", c.vfov_deg},
                        {"tan_half_vfov", tan_half_vfov(c)}};
    }
    json buffers = json::array();
    for (const Buffer& buffer : frame.buffers) {
        if (only && std::find(only->begin(), only->end(), buffer.name) == only->end()) continue;
        json jb;
        jb["name"] = buffer.name;
        jb["kind"] = buffer_kind_name(buffer.kind);
        jb["stage"] = buffer.stage;
        jb["width"] = buffer.image.width;
        jb["height"] = buffer.image.height;
        jb["channels"] = buffer.image.channels;
        jb["channel_names"] = buffer.channel_names;
        jb["sha256"] = canonical_sha256(buffer.image);
        const bool small = buffer.image.pixel_count() <= s.options.max_stored_pixels;
        const bool earlier_frame =
            s.golden_case.files == "last-frame" && frame.frame != s.golden_case.frames - 1;
        if (small && !earlier_frame) {
            const std::string file = buffer_file_name(frame.frame, buffer);
            write_image((s.staging / file).string(), buffer.image);
            jb["file"] = file;
            if (s.options.raw_copies && buffer.image.channels != 1 && buffer.image.channels != 3) {
                const std::string raw = buffer_file_name(frame.frame, buffer, ".f32");
                write_raw_binary32((s.staging / raw).string(), buffer.image);
                jb["raw_file"] = raw;
            }
        } else {
            // Hash only: too large for the repository (with per-block hashes that locate a
            // difference), or an earlier frame of a "last-frame" case (the whole hash only).
            jb["file"] = nullptr;
            if (!small) {
                jb["block_rows"] = hash_block_rows(buffer.image.height);
                jb["block_sha256"] =
                    block_hashes(buffer.image, hash_block_rows(buffer.image.height));
            }
        }
        if (s.options.previews_for_all || buffer.name == "final") {
            const std::string png = buffer_file_name(frame.frame, buffer, ".png");
            write_png((s.staging / png).string(), preview_image(buffer));
            jb["preview"] = png;
        }
        buffers.push_back(jb);
    }
    jf["buffers"] = buffers;
    jf["counters"] = counters_to_json(frame.counters);
    json stages = json::array();
    for (const StageRun& run : frame.stages) {
        json js;
        js["name"] = run.name;
        js["ran"] = run.ran;
        if (!run.note.empty()) js["note"] = run.note;
        if (s.options.include_timings) js["seconds"] = run.seconds;
        stages.push_back(js);
    }
    jf["stages"] = stages;
    s.frames.push_back(jf);
}

void BundleWriter::add_scene(const Scene& scene, const std::string& relative_directory) {
    State& s = *state_;
    export_scene(scene, (s.staging / relative_directory).string());
    s.scene_export = relative_directory;
}

void BundleWriter::commit() {
    State& s = *state_;
    json manifest;
    manifest["format"] = bundle_format;
    manifest["case"] = case_to_json(s.golden_case);
    manifest["fovref_version"] = fovref_version();
    manifest["compiler"] = fovref_compiler();
    manifest["flags"] = fovref_build_flags();
    manifest["canonical_data"] =
        "SHA-256 of row-major, top-row-first, little-endian binary32, channels interleaved";
    if (!s.scene_export.empty()) manifest["scene_export"] = s.scene_export + "/scene.json";
    if (!s.options.effective_params.empty())
        manifest["effective_params"] = json(s.options.effective_params);
    manifest["frames"] = s.frames;
    write_file_atomic((s.staging / "manifest.json").string(), manifest.dump(1) + "\n");

    // Swap: target -> previous, staging -> target, then drop previous.
    std::error_code ec;
    fs::remove_all(s.previous, ec);
    const bool had_previous = fs::exists(s.target, ec);
    if (had_previous) {
        fs::rename(s.target, s.previous, ec);
        if (ec) throw Error(s.target.string() + ": cannot replace: " + ec.message());
    }
    fs::rename(s.staging, s.target, ec);
    if (ec) {
        const std::string message = ec.message();
        if (had_previous) fs::rename(s.previous, s.target, ec);  // put the old bundle back
        throw Error(s.target.string() + ": cannot move the new bundle in place: " + message);
    }
    s.committed = true;
    fs::remove_all(s.previous, ec);
}

void write_bundle(const std::string& directory, const GoldenCase& golden_case,
                  const std::vector<FrameResult>& frames, const BundleOptions& options) {
    BundleWriter writer(directory, golden_case, options);
    for (const FrameResult& frame : frames) writer.add_frame(frame);
    writer.commit();
}

// ---- Reading and comparing ---------------------------------------------------------------------

namespace {

// Typed access to a manifest's members: a missing or mistyped member is an error naming the
// file, the line of the key and the key's JSON pointer (never nlohmann's bare type_error).
class ManifestFields {
public:
    ManifestFields(const std::string& text, std::string path)
        : path_(std::move(path)),
          root_(parse_json_document<json>(text, path_)),
          locator_(text, path_) {}

    const json& root() const { return root_; }
    const JsonLocator& locator() const { return locator_; }

    [[noreturn]] void fail(const std::string& pointer, const std::string& message) const {
        throw file_error(
            path_, locator_.find(pointer).key_line,
            "malformed manifest: " + (pointer.empty() ? "the document" : pointer) + ": " + message);
    }

    const json& member(const json& object, const std::string& pointer,
                       const std::string& key) const {
        if (!object.is_object())
            fail(pointer, std::string("expected an object, got ") + object.type_name());
        const auto it = object.find(key);
        if (it == object.end()) fail(pointer, "missing key \"" + key + "\"");
        return *it;
    }
    bool has(const json& object, const std::string& key) const {
        return object.is_object() && object.contains(key);
    }
    const json& array(const json& object, const std::string& pointer,
                      const std::string& key) const {
        const json& v = member(object, pointer, key);
        if (!v.is_array())
            fail(at(pointer, key), std::string("expected an array, got ") + v.type_name());
        return v;
    }
    std::string string(const json& object, const std::string& pointer, const std::string& key,
                       const char* fallback = nullptr) const {
        if (fallback && !has(object, key)) return fallback;
        const json& v = member(object, pointer, key);
        if (!v.is_string())
            fail(at(pointer, key), std::string("expected a string, got ") + v.type_name());
        return v.get<std::string>();
    }
    std::int64_t integer(const json& object, const std::string& pointer, const std::string& key,
                         std::int64_t min, std::int64_t max,
                         std::optional<std::int64_t> fallback = std::nullopt) const {
        if (fallback && !has(object, key)) return *fallback;
        const json& v = member(object, pointer, key);
        if (!v.is_number_integer())
            fail(at(pointer, key), std::string("expected an integer, got ") + v.type_name());
        // Compare as the stored type: a value beyond int64 is an unsigned JSON number.
        if (v.is_number_unsigned() ? v.get<std::uint64_t>() > static_cast<std::uint64_t>(max)
                                   : (v.get<std::int64_t>() < min || v.get<std::int64_t>() > max))
            fail(at(pointer, key), "integer " + v.dump() + " outside [" + std::to_string(min) +
                                       ", " + std::to_string(max) + "]");
        return v.get<std::int64_t>();
    }
    float number(const json& object, const std::string& pointer, const std::string& key,
                 float fallback) const {
        if (!has(object, key)) return fallback;
        const json& v = member(object, pointer, key);
        if (!v.is_number())
            fail(at(pointer, key), std::string("expected a number, got ") + v.type_name());
        return static_cast<float>(v.get<double>());
    }
    std::vector<std::string> strings(const json& object, const std::string& pointer,
                                     const std::string& key) const {
        std::vector<std::string> out;
        if (!has(object, key)) return out;
        const json& v = array(object, pointer, key);
        for (std::size_t i = 0; i < v.size(); ++i) {
            if (!v[i].is_string())
                fail(json_pointer_element(at(pointer, key), i),
                     std::string("expected a string, got ") + v[i].type_name());
            out.push_back(v[i].get<std::string>());
        }
        return out;
    }
    static std::string at(const std::string& pointer, const std::string& key) {
        return json_pointer_member(pointer, key);
    }

private:
    std::string path_;
    json root_;
    JsonLocator locator_;
};

}  // namespace

Manifest read_manifest(const std::string& directory) {
    const std::string path = (fs::path(directory) / "manifest.json").string();
    const ManifestFields f(read_file(path), path);
    const json& j = f.root();
    constexpr std::int64_t max_int = std::numeric_limits<int>::max();
    Manifest m;
    if (!j.is_object()) f.fail("", "expected a JSON object");
    m.golden_case = case_from_json(f.member(j, "", "case"), path, "/case", f.locator());
    m.fovref_version = f.string(j, "", "fovref_version", "");
    m.compiler = f.string(j, "", "compiler", "");
    m.flags = f.string(j, "", "flags", "");
    const json& frames = f.array(j, "", "frames");
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const json& jf = frames[i];
        const std::string fp = json_pointer_element("/frames", i);
        const int frame = static_cast<int>(f.integer(jf, fp, "frame", 0, max_int));
        m.display_distance_px.push_back(f.number(jf, fp, "display_distance_px", 0.0f));
        const json& buffers = f.array(jf, fp, "buffers");
        for (std::size_t k = 0; k < buffers.size(); ++k) {
            const json& jb = buffers[k];
            const std::string bp = json_pointer_element(ManifestFields::at(fp, "buffers"), k);
            ManifestBuffer b;
            b.frame = frame;
            b.name = f.string(jb, bp, "name");
            b.kind = f.string(jb, bp, "kind", "scalar");
            b.stage = f.string(jb, bp, "stage", "");
            b.width = static_cast<int>(f.integer(jb, bp, "width", 1, max_int));
            b.height = static_cast<int>(f.integer(jb, bp, "height", 1, max_int));
            b.channels = static_cast<int>(f.integer(jb, bp, "channels", 1, 1024));
            b.channel_names = f.strings(jb, bp, "channel_names");
            b.sha256 = f.string(jb, bp, "sha256");
            const json& file = f.member(jb, bp, "file");
            b.file = file.is_null() ? "" : f.string(jb, bp, "file");
            b.block_rows = static_cast<int>(f.integer(jb, bp, "block_rows", 0, max_int, 0));
            b.block_sha256 = f.strings(jb, bp, "block_sha256");
            m.buffers.push_back(std::move(b));
        }
        Counters counters;
        if (f.has(jf, "counters")) {
            const json& jc = f.member(jf, fp, "counters");
            if (!jc.is_object())
                f.fail(ManifestFields::at(fp, "counters"),
                       std::string("expected an object, got ") + jc.type_name());
            for (const auto& item : jc.items())
                counters.add(item.key(),
                             f.integer(jc, ManifestFields::at(fp, "counters"), item.key(),
                                       std::numeric_limits<std::int64_t>::min(),
                                       std::numeric_limits<std::int64_t>::max()));
        }
        m.frame_counters.push_back(counters);
    }
    return m;
}

std::ptrdiff_t first_difference(const Image& expected, const Image& actual) {
    const std::size_t n = std::min(expected.data.size(), actual.data.size());
    for (std::size_t i = 0; i < n; ++i)
        if (std::bit_cast<std::uint32_t>(expected.data[i]) !=
            std::bit_cast<std::uint32_t>(actual.data[i]))
            return static_cast<std::ptrdiff_t>(i);
    if (expected.data.size() != actual.data.size()) return static_cast<std::ptrdiff_t>(n);
    return -1;
}

std::string describe_difference(const Image& expected, const Image& actual, std::ptrdiff_t index,
                                const std::vector<std::string>& channel_names) {
    const int channels = std::max(1, actual.channels);
    const auto i = static_cast<std::size_t>(index);
    const std::size_t pixel = i / channels;
    const int channel = static_cast<int>(i % channels);
    const int width = std::max(1, actual.width);
    char text[256];
    auto value = [](const Image& image, std::size_t k, char* out, std::size_t size) {
        if (k >= image.data.size()) {
            std::snprintf(out, size, "(absent)");
            return;
        }
        std::snprintf(out, size, "%.9g (0x%08" PRIx32 ")", static_cast<double>(image.data[k]),
                      std::bit_cast<std::uint32_t>(image.data[k]));
    };
    char e[64], a[64];
    value(expected, i, e, sizeof e);
    value(actual, i, a, sizeof a);
    const std::string channel_name = channel < static_cast<int>(channel_names.size())
                                         ? channel_names[channel]
                                         : std::to_string(channel);
    std::snprintf(text, sizeof text,
                  "first difference at pixel (%zu, %zu) channel %s: expected %s, got %s",
                  pixel % width, pixel / width, channel_name.c_str(), e, a);
    return text;
}

std::vector<GoldenDifference> compare_with_bundle(const std::string& directory,
                                                  const Manifest& manifest,
                                                  const std::vector<FrameResult>& frames) {
    std::vector<GoldenDifference> differences;
    // Buffers in the manifest that the recomputation lacks.
    for (const ManifestBuffer& stored : manifest.buffers) {
        bool present = false;
        for (const FrameResult& frame : frames)
            if (frame.frame == stored.frame && frame.find(stored.name)) present = true;
        if (!present)
            differences.push_back(
                {stored.frame, stored.name, "in the golden but not produced any more"});
    }
    for (const FrameResult& frame : frames) {
        for (const Buffer& buffer : frame.buffers) {
            const ManifestBuffer* stored = nullptr;
            for (const ManifestBuffer& b : manifest.buffers)
                if (b.frame == frame.frame && b.name == buffer.name) stored = &b;
            if (!stored) {
                differences.push_back({frame.frame, buffer.name, "produced but not in the golden"});
                continue;
            }
            const Image& image = buffer.image;
            if (stored->width != image.width || stored->height != image.height ||
                stored->channels != image.channels) {
                differences.push_back(
                    {frame.frame, buffer.name,
                     "shape " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                         "x" + std::to_string(image.channels) + ", golden has " +
                         std::to_string(stored->width) + "x" + std::to_string(stored->height) +
                         "x" + std::to_string(stored->channels)});
                continue;
            }
            if (canonical_sha256(image) == stored->sha256) continue;
            std::string what;
            if (stored->file.empty()) {
                what = "SHA-256 differs; kept by hash only";
                if (stored->block_rows > 0) {
                    const std::vector<std::string> now = block_hashes(image, stored->block_rows);
                    for (std::size_t k = 0; k < now.size(); ++k)
                        if (k >= stored->block_sha256.size() || now[k] != stored->block_sha256[k]) {
                            const int first = static_cast<int>(k) * stored->block_rows;
                            const int last = std::min(first + stored->block_rows, image.height) - 1;
                            what += ", first differing rows " + std::to_string(first) + ".." +
                                    std::to_string(last);
                            break;
                        }
                }
                what += " (export the case from both builds to compare pixels)";
            } else {
                const Image expected = read_image((fs::path(directory) / stored->file).string());
                const std::ptrdiff_t index = first_difference(expected, image);
                what = index < 0
                           ? "SHA-256 differs from the manifest but the stored file matches: "
                             "the bundle is inconsistent, run `fovref golden update`"
                           : describe_difference(expected, image, index, buffer.channel_names);
            }
            differences.push_back({frame.frame, buffer.name, what});
        }
        if (static_cast<std::size_t>(frame.frame) < manifest.frame_counters.size() &&
            !(manifest.frame_counters[frame.frame] == frame.counters))
            differences.push_back({frame.frame, "(counters)", "statistics differ from the golden"});
    }
    return differences;
}

}  // namespace fovref
