#include "tools/cli/commands/denoise.h"

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/bmfr_params.h"
#include "ref/bmfr/stages.h"
#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

namespace fs = std::filesystem;

nlohmann::json read_json(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open");
    std::stringstream text;
    text << in.rdbuf();
    try {
        return nlohmann::json::parse(text.str());
    } catch (const nlohmann::json::parse_error& e) {
        throw Error(path + ": JSON syntax error at byte " + std::to_string(e.byte));
    }
}

float finite_number(const nlohmann::json& v, const std::string& where) {
    if (!v.is_number()) throw Error(where + ": expected a number");
    const double d = v.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > 3.0e38) throw Error(where + ": not a finite float");
    return static_cast<float>(d);
}

glm::vec3 vec3_of(const nlohmann::json& v, const std::string& where) {
    if (!v.is_array() || v.size() != 3) throw Error(where + ": expected [x, y, z]");
    return {finite_number(v[0], where), finite_number(v[1], where), finite_number(v[2], where)};
}

// One frame's matrix: "view_projection" (16 numbers, row-major) or "camera" (a fovref
// manifest's camera: position, right, up, forward, vfov_deg).
ViewProjection frame_matrix(const nlohmann::json& frame, const std::string& where, int width,
                            int height) {
    if (!frame.is_object()) throw Error(where + ": expected an object");
    if (frame.contains("view_projection")) {
        const nlohmann::json& m = frame["view_projection"];
        if (!m.is_array() || m.size() != 16)
            throw Error(where + ".view_projection: expected 16 numbers (row-major 4x4)");
        ViewProjection vp;
        for (std::size_t i = 0; i < 16; ++i)
            vp.m[i] = finite_number(m[i], where + ".view_projection[" + std::to_string(i) + "]");
        return vp;
    }
    if (frame.contains("camera")) {
        const nlohmann::json& c = frame["camera"];
        const std::string w = where + ".camera";
        if (!c.is_object()) throw Error(w + ": expected an object");
        for (const char* key : {"position", "right", "up", "forward", "vfov_deg"})
            if (!c.contains(key)) throw Error(w + ": missing '" + key + "'");
        Camera camera;
        camera.position = vec3_of(c["position"], w + ".position");
        camera.right = vec3_of(c["right"], w + ".right");
        camera.up = vec3_of(c["up"], w + ".up");
        camera.forward = vec3_of(c["forward"], w + ".forward");
        camera.vfov_deg = finite_number(c["vfov_deg"], w + ".vfov_deg");
        if (!(camera.vfov_deg > 0.0f && camera.vfov_deg < 180.0f))
            throw Error(w + ".vfov_deg: must lie in (0, 180)");
        return view_projection(camera, width, height);
    }
    throw Error(where + ": give 'view_projection' (16 numbers) or 'camera'");
}

struct Input {
    int width = 0, height = 0;
    std::vector<ViewProjection> cameras;
    std::string cameras_file;
};

// IN_DIR/cameras.json, else the frames of IN_DIR/manifest.json (a fovref bundle).
Input read_input(const std::string& dir) {
    Input in;
    const std::string cameras = dir + "/cameras.json";
    const std::string manifest = dir + "/manifest.json";
    if (fs::exists(cameras)) {
        in.cameras_file = cameras;
        const nlohmann::json j = read_json(cameras);
        if (!j.is_object() || !j.contains("width") || !j.contains("height") ||
            !j.contains("frames") || !j["width"].is_number_integer() ||
            !j["height"].is_number_integer() || !j["frames"].is_array())
            throw Error(cameras + ": expected {\"width\": W, \"height\": H, \"frames\": [...]}");
        in.width = j["width"].get<int>();
        in.height = j["height"].get<int>();
        if (in.width < 1 || in.height < 1 || in.width > 16384 || in.height > 16384)
            throw Error(cameras + ": width and height must lie in 1..16384");
        for (std::size_t f = 0; f < j["frames"].size(); ++f)
            in.cameras.push_back(frame_matrix(j["frames"][f],
                                              cameras + ": frames[" + std::to_string(f) + "]",
                                              in.width, in.height));
    } else if (fs::exists(manifest)) {
        in.cameras_file = manifest;
        const nlohmann::json j = read_json(manifest);
        if (!j.is_object() || !j.contains("case") || !j["case"].is_object() ||
            !j.contains("frames") || !j["frames"].is_array() || !j["case"].contains("width") ||
            !j["case"]["width"].is_number_integer() || !j["case"].contains("height") ||
            !j["case"]["height"].is_number_integer())
            throw Error(manifest +
                        ": not a fovref bundle manifest (case.width, case.height, "
                        "frames)");
        in.width = j["case"]["width"].get<int>();
        in.height = j["case"]["height"].get<int>();
        if (in.width < 1 || in.height < 1 || in.width > 16384 || in.height > 16384)
            throw Error(manifest + ": width and height must lie in 1..16384");
        for (std::size_t f = 0; f < j["frames"].size(); ++f)
            in.cameras.push_back(frame_matrix(j["frames"][f],
                                              manifest + ": frames[" + std::to_string(f) + "]",
                                              in.width, in.height));
    } else {
        throw Error(dir +
                    ": no cameras.json (per-frame view-projection matrices; docs/bmfr.md) "
                    "and no manifest.json of a fovref bundle");
    }
    if (in.cameras.empty()) throw Error(in.cameras_file + ": no frames");
    return in;
}

std::string input_prefix(int frame) {
    char prefix[32];
    std::snprintf(prefix, sizeof prefix, "f%03d_", frame);
    return prefix;
}

bool has_input_buffer(const std::string& dir, int frame, const std::string& name) {
    const std::string base = dir + "/" + input_prefix(frame) + name;
    return fs::exists(base + ".pfm") || fs::exists(base + ".exr");
}

// IN_DIR/fNNN_<name>.pfm or .exr, 3 channels, W x H.
Image read_input_buffer(const std::string& dir, int frame, const std::string& name, int width,
                        int height) {
    const std::string prefix = input_prefix(frame);
    std::string path;
    for (const char* ext : {".pfm", ".exr"}) {
        const std::string p = dir + "/" + prefix + name + ext;
        if (fs::exists(p)) {
            path = p;
            break;
        }
    }
    if (path.empty())
        throw Error(dir + "/" + prefix + name + ".pfm (or .exr): missing (frame " +
                    std::to_string(frame) + ")");
    Image image = read_image(path);
    if (image.width != width || image.height != height || image.channels != 3)
        throw Error(path + ": is " + std::to_string(image.width) + "x" +
                    std::to_string(image.height) + "x" + std::to_string(image.channels) +
                    ", expected " + std::to_string(width) + "x" + std::to_string(height) + "x3");
    return image;
}

}  // namespace

void add_denoise_options(CLI::App& c, DenoiseOptions& o) {
    c.add_option("IN_DIR", o.input,
                 "per-frame buffers fNNN_radiance, fNNN_gbuffer_albedo, "
                 "fNNN_gbuffer_shading_normal, fNNN_gbuffer_world_position (.pfm or .exr; "
                 "optionally fNNN_emission) and cameras.json (or a fovref bundle's "
                 "manifest.json)")
        ->required();
    c.add_option("OUT_DIR", o.output, "the bundle written: every phase of every frame")->required();
    c.add_option("--param", o.params,
                 "bmfr_storage=half|float, bmfr_position_limit_squared=V, "
                 "bmfr_normal_limit_squared=V, bmfr_emission=separate|include");
}

int run_denoise(const DenoiseOptions& o) {
    Params params = Params::from_assignments(o.params);
    params.check_known(bmfr_param_specs(), "denoise bmfr");
    params.set("denoise", "bmfr");
    const BmfrSettings settings = parse_bmfr_params(params);
    const Input in = read_input(o.input);
    GoldenCase run;
    run.name = "denoise";
    run.mode = "denoise-bmfr";
    run.width = in.width;
    run.height = in.height;
    run.frames = static_cast<int>(in.cameras.size());
    run.params = params;
    BundleOptions options;
    options.previews_for_all = true;
    BundleWriter writer(o.output, run, options);
    Progress progress("denoise bmfr", o.quiet);
    BmfrHistory history;
    const int frames = static_cast<int>(in.cameras.size());
    for (int f = 0; f < frames; ++f) {
        FrameResult frame;
        frame.frame = f;
        const auto buffer = [&](const char* name) {
            return read_input_buffer(o.input, f, name, in.width, in.height);
        };
        frame.add("radiance", BufferKind::color, {"r", "g", "b"}, buffer("radiance"));
        frame.add("gbuffer_albedo", BufferKind::color, {"r", "g", "b"}, buffer("gbuffer_albedo"));
        frame.add("gbuffer_shading_normal", BufferKind::vector, {"x", "y", "z"},
                  buffer("gbuffer_shading_normal"));
        frame.add("gbuffer_world_position", BufferKind::scalar, {"x", "y", "z"},
                  buffer("gbuffer_world_position"));
        // optional: the directly seen emission, kept out of the fit (bmfr_emission=separate)
        const Image* emission = nullptr;
        if (has_input_buffer(o.input, f, "emission")) {
            frame.add("emission", BufferKind::color, {"r", "g", "b"}, buffer("emission"));
            emission = &frame.find("emission")->image;
        }
        static const Image none;
        BmfrStats stats;
        BmfrFrame denoised = bmfr_denoise_frame(
            settings.params, frame.find("radiance")->image, frame.find("gbuffer_albedo")->image,
            emission ? *emission : none, frame.find("gbuffer_shading_normal")->image,
            frame.find("gbuffer_world_position")->image, in.cameras[static_cast<std::size_t>(f)], f,
            history, stats);
        add_bmfr_buffers(frame, std::move(denoised), "final");
        add_bmfr_counters(frame.counters, stats);
        writer.add_frame(frame);
        progress.update(static_cast<double>(f + 1) / frames);
    }
    writer.commit();
    progress.finish();
    if (!o.quiet)
        std::printf("denoised %d frame(s) of %dx%d from %s into %s\n", frames, in.width, in.height,
                    o.input.c_str(), o.output.c_str());
    return 0;
}

}  // namespace fovref
