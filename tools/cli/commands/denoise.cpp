#include "tools/cli/commands/denoise.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>

#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/bmfr_params.h"
#include "ref/bmfr/stages.h"
#include "ref/core/error.h"
#include "ref/golden/bundle.h"
#include "ref/image/image_io.h"
#include "ref/stage/pipeline.h"
#include "tools/cli/common/output_dir.h"
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
    std::vector<glm::vec2> pixel_offsets;  ///< per frame; (0.5, 0.5) unless cameras.json says
    std::string cameras_file;
    /// cameras.json's "position_limit_squared" and "normal_limit_squared" (as bmfr_* params)
    std::vector<std::pair<std::string, std::string>> limits;
};

// A frame's "pixel_offset": [x, y], each in [0, 1) (the BMFR authors' pixel_offsets[frame]).
glm::vec2 frame_pixel_offset(const nlohmann::json& frame, const std::string& where) {
    if (!frame.contains("pixel_offset")) return glm::vec2(0.5f);
    const nlohmann::json& o = frame["pixel_offset"];
    if (!o.is_array() || o.size() != 2) throw Error(where + ".pixel_offset: expected [x, y]");
    const glm::vec2 offset{finite_number(o[0], where + ".pixel_offset[0]"),
                           finite_number(o[1], where + ".pixel_offset[1]")};
    if (!(offset.x >= 0.0f && offset.x < 1.0f && offset.y >= 0.0f && offset.y < 1.0f))
        throw Error(where + ".pixel_offset: each coordinate must lie in [0, 1)");
    return offset;
}

// cameras.json's reprojection limits, as the parameters they set.
void read_limits(const nlohmann::json& j, const std::string& file, Input& in) {
    for (const char* key : {"position_limit_squared", "normal_limit_squared"}) {
        if (!j.contains(key)) continue;
        const float v = finite_number(j[key], file + ": " + key);
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", static_cast<double>(v));
        in.limits.emplace_back(std::string("bmfr_") + key, text);
    }
}

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
        for (std::size_t f = 0; f < j["frames"].size(); ++f) {
            const std::string where = cameras + ": frames[" + std::to_string(f) + "]";
            in.cameras.push_back(frame_matrix(j["frames"][f], where, in.width, in.height));
            in.pixel_offsets.push_back(frame_pixel_offset(j["frames"][f], where));
        }
        read_limits(j, cameras, in);
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
        for (std::size_t f = 0; f < j["frames"].size(); ++f) {
            in.cameras.push_back(frame_matrix(j["frames"][f],
                                              manifest + ": frames[" + std::to_string(f) + "]",
                                              in.width, in.height));
            in.pixel_offsets.push_back(glm::vec2(0.5f));
        }
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

// The input buffers of a frame (the load stage's outputs): name, kind, channel names.
struct InputBuffer {
    const char* name;
    BufferKind kind;
    std::vector<std::string> channels;
};
const std::vector<InputBuffer>& input_buffers() {
    static const std::vector<InputBuffer> buffers = {
        {"radiance", BufferKind::color, {"r", "g", "b"}},
        {"gbuffer_albedo", BufferKind::color, {"r", "g", "b"}},
        {"gbuffer_shading_normal", BufferKind::vector, {"x", "y", "z"}},
        {"gbuffer_world_position", BufferKind::scalar, {"x", "y", "z"}}};
    return buffers;
}

// What the load stage reads: IN_DIR and the screen, and whether it reads the emission.
struct LoadState : StageState {
    std::string dir;
    int width = 0, height = 0;
    bool emission = false;
};

// The stage that stands for another renderer's passes: frame f's buffers from IN_DIR.
void load_inputs_stage(FrameContext& ctx) {
    const LoadState& s = ctx.state<LoadState>();
    for (const InputBuffer& b : input_buffers())
        ctx.output(b.name, b.kind, b.channels,
                   read_input_buffer(s.dir, ctx.frame, b.name, s.width, s.height));
    if (s.emission)
        ctx.output("emission", BufferKind::color, {"r", "g", "b"},
                   read_input_buffer(s.dir, ctx.frame, "emission", s.width, s.height));
    ctx.note = "read from " + s.dir;
}

// --frames N (0 .. N-1) or A..B (A .. B written; BMFR runs 0 .. B, its history needs them).
std::pair<int, int> frame_range(const std::string& text, int available, const std::string& file) {
    const auto number = [&](const std::string& t) {
        std::size_t used = 0;
        int v = -1;
        try {
            v = std::stoi(t, &used);
        } catch (const std::exception&) {
            used = 0;
        }
        if (t.empty() || used != t.size() || v < 0 ||
            !std::isdigit(static_cast<unsigned char>(t[0])))
            throw Error("--frames '" + text + "': expected N or A..B (non-negative integers)");
        return v;
    };
    if (text.empty()) return {0, available - 1};
    const std::size_t dots = text.find("..");
    const int first = dots == std::string::npos ? 0 : number(text.substr(0, dots));
    const int last = dots == std::string::npos ? number(text) - 1 : number(text.substr(dots + 2));
    if (last < first) throw Error("--frames '" + text + "': the range is empty");
    if (last >= available)
        throw Error("--frames '" + text + "': " + file + " has " + std::to_string(available) +
                    " frame(s) (0 .. " + std::to_string(available - 1) + ")");
    return {first, last};
}

// The BMFR parameters: --param, then cameras.json's limits where --param does not set them (both
// setting one to different values is an error).
Params denoise_params(const DenoiseOptions& o, const Input& in) {
    Params params = Params::from_assignments(o.params);
    params.check_known(bmfr_param_specs(), "denoise bmfr");
    for (const auto& [key, value] : in.limits) {
        if (params.given(key) && params.get_string(bmfr_param_specs(), key) != value)
            throw Error("--param " + key + "=" + params.get_string(bmfr_param_specs(), key) +
                        " and " + in.cameras_file + "'s " + key.substr(5) + " = " + value +
                        " disagree; give one");
        params.set(key, value);
    }
    params.set("denoise", "bmfr");
    return params;
}

// Every input file of frames 0 .. last, checked before any work.
void check_inputs(const std::string& dir, int last, bool emission) {
    for (int f = 0; f <= last; ++f) {
        for (const InputBuffer& b : input_buffers())
            if (!has_input_buffer(dir, f, b.name))
                throw Error(dir + "/" + input_prefix(f) + b.name +
                            ".pfm (or .exr): missing (frame " + std::to_string(f) + ")");
        if (emission && !has_input_buffer(dir, f, "emission"))
            throw Error(dir + "/" + input_prefix(f) + "emission.pfm (or .exr): missing (frame " +
                        std::to_string(f) + "; bmfr_emission=separate reads it)");
    }
}

// `denoise bmfr` as a mode: the load stage, then BMFR's stages wired to the input's matrices and
// pixel offsets.
ModeInfo denoise_mode(const DenoiseOptions& o, std::shared_ptr<const Input> in) {
    ModeInfo m;
    m.name = "denoise-bmfr";
    m.description = "BMFR on another renderer's buffers";
    m.needs_scene = false;
    m.params = concat_specs(bmfr_param_specs(), {});
    m.stateless = false;
    m.build = [dir = o.input, demodulated = o.demodulated, in](const Scene*,
                                                               const RenderSettings& settings) {
        BmfrSettings bmfr = parse_bmfr_params(settings.params);
        if (demodulated && bmfr.params.separate_emission)
            throw Error(
                "--demodulated with bmfr_emission=separate: a colour already divided by "
                "albedo has no emission to keep apart");
        bmfr.params.demodulated_input = demodulated;
        auto load = std::make_shared<LoadState>();
        load->dir = dir;
        load->width = in->width;
        load->height = in->height;
        load->emission = bmfr.params.separate_emission;
        std::vector<Port> outputs;
        for (const InputBuffer& b : input_buffers()) outputs.emplace_back(b.name);
        if (load->emission) outputs.emplace_back("emission");
        Pipeline p;
        p.add({"load_inputs", {}, outputs, load_inputs_stage, load});
        BmfrWiring wiring{bmfr, "radiance", "emission", "final"};
        wiring.view_projection = [in](const FrameContext&, int frame) {
            return in->cameras[static_cast<std::size_t>(frame)];
        };
        wiring.pixel_offset = [in](const FrameContext& ctx) {
            return in->pixel_offsets[static_cast<std::size_t>(ctx.frame)];
        };
        add_bmfr_stages(p, wiring);
        p.final_outputs = {"final"};
        return p;
    };
    return m;
}

}  // namespace

DenoiseRun denoise_each(const DenoiseOptions& o, const std::vector<std::string>& requested,
                        const std::function<void(double)>& progress,
                        const std::function<void(FrameResult&)>& on_frame) {
    const auto in = std::make_shared<const Input>(read_input(o.input));
    DenoiseRun run;
    run.params = denoise_params(o, *in);
    std::tie(run.first, run.last) =
        frame_range(o.frames, static_cast<int>(in->cameras.size()), in->cameras_file);
    run.width = in->width;
    run.height = in->height;
    check_inputs(o.input, run.last, parse_bmfr_params(run.params).params.separate_emission);
    if (!on_frame) return run;  // checked only
    RenderSettings settings;
    settings.width = in->width;
    settings.height = in->height;
    settings.frame_count = run.last + 1;
    settings.params = run.params;
    settings.requested = requested;
    settings.progress = progress;
    render_each(nullptr, denoise_mode(o, in), settings, [&](FrameResult& frame) {
        if (frame.frame >= run.first) on_frame(frame);
    });
    return run;
}

int run_denoise(const DenoiseOptions& o) {
    check_output_directory("OUT_DIR", o.output);
    const bool all = o.outputs.empty() ||
                     std::find(o.outputs.begin(), o.outputs.end(), "all") != o.outputs.end();
    const std::vector<std::string> requested = all ? std::vector<std::string>{"all"} : o.outputs;
    const DenoiseRun checked = denoise_each(o, requested, {}, {});  // inputs, before any work
    GoldenCase run;
    run.name = "denoise";
    run.mode = "denoise-bmfr";
    run.width = checked.width;
    run.height = checked.height;
    run.frames = checked.last - checked.first + 1;
    run.params = checked.params;
    BundleOptions options;
    options.previews_for_all = o.previews;
    options.include_timings = true;
    Progress progress("denoise bmfr", o.quiet);
    BundleWriter writer(o.output, run, options);
    denoise_each(
        o, requested, [&](double f) { progress.update(f); },
        [&](FrameResult& frame) {
            // Only the requested buffers are written; the frame keeps the others (BMFR's stages
            // take their history back from it)
            writer.add_frame(frame, all ? nullptr : &o.outputs);
        });
    writer.commit();
    progress.finish();
    if (!o.quiet)
        std::printf("denoised frames %d .. %d of %dx%d from %s into %s\n", checked.first,
                    checked.last, checked.width, checked.height, o.input.c_str(), o.output.c_str());
    return 0;
}

}  // namespace fovref
