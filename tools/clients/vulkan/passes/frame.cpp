// The end-to-end composite-foveation frame (Lund's fov, kfov, cfov, ckfov with primary rays):
// unlike the stage-isolated passes it reads no golden intermediate, only the bundle's exported
// scene (`fovref golden export CASE DIR --with-scene --raw-copies`) and the frames' cameras, and
// renders every stage on the GPU:
//
//   host:   the scene (frame_scene.h), the BVH in the client's own layout (frame_bvh.h), the
//           log-polar map's constants (buffer size in binary64; R, L, r_G, G in binary32) and
//           the gaze window (binary64), as a renderer computes them once per frame;
//   frame_trace (launch 0): per log-polar texel the inverse map, validity, primary ray, closest
//           hit, G-buffer record and shading (lp_trace, lp_shade);
//   frame_trace (launch 1, composite modes): per gaze-window pixel the same (gaze_trace,
//           gaze_shade);
//   frame_resolve: pass 2 (resolve), then gaussian_lerp.comp where the case has the lerp.
//
// Every stage's buffers are written under the bundle's names, so `fovref diff` compares them
// all. Refused with a message: kfr and primary=raster, TAA, gaze_track, lp_widen, internal AA,
// post-AA, the mip resolve.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"
#include "tools/clients/vulkan/passes/frame_bvh.h"
#include "tools/clients/vulkan/passes/frame_scene.h"

#ifndef FOVREF_VK_SHADER_DIR
#define FOVREF_VK_SHADER_DIR "."
#endif

namespace fovref_client {
namespace {

/// The mode's log-polar parameters: Lund Table 5.1's preset, then the case's overrides.
struct MapSettings {
    float sigma = 1.0f, alpha = 1.0f, gaze_angle = 0.0f, lp_aspect = 0.0f;
    std::vector<float> beta;  ///< Meng's polynomial kernel when not empty
    bool corners = false;     ///< L=corners (else the diagonal)
    bool lerp = false;        ///< filters=lerp
};

/// std430 mirror of frame_common.glsl's `Frame` block.
struct FrameParams {
    float camera_position[4], camera_right[4], camera_up[4], camera_forward[4];
    float previous_position[4], previous_right[4], previous_up[4], previous_forward[4];
    std::int32_t screen[4], window[4], counts[4], launch[4];
    float map[4], map2[4], scene[4];
    float beta[20];
};

/// The log-polar map of one frame (docs/foveation.md, "The buffer", "The mapping").
struct FrameMap {
    int width = 0, height = 0;  ///< the buffer
    float gaze_x = 0.0f, gaze_y = 0.0f, log_radius_max = 0.0f, gaze_radius = 0.0f;
    float composite = 0.0f;                                   ///< G
    int x0 = 0, y0 = 0, window_width = 1, window_height = 1;  ///< the gaze window
};

float number_of(const std::string& text, const std::string& what) {
    try {
        std::size_t end = 0;
        const float value = std::stof(text, &end);
        if (end == text.size() && std::isfinite(value)) return value;
    } catch (const std::exception&) {
    }
    throw std::runtime_error("frame: parameter '" + what + "': '" + text + "' is not a number");
}

// The mode's preset and the case's parameters; what this pass does not port is refused.
MapSettings map_settings(const PassContext& ctx) {
    const std::string mode = ctx.manifest.at("case").at("mode").get<std::string>();
    MapSettings s;
    if (mode == "fov")
        s = {0.75f, 1.0f, 0.0f, 1.2f, {}, false, false};
    else if (mode == "kfov")
        s = {1.0f, 3.0f, 0.0f, 0.70f, {}, false, false};
    else if (mode == "cfov")
        s = {1.4f, 1.0f, 0.20f, 0.33f, {}, false, false};
    else if (mode == "ckfov")
        s = {1.3f, 2.0f, 0.15f, 0.35f, {}, false, false};
    else
        throw std::runtime_error("frame: mode '" + mode +
                                 "' is not a log-polar mode with primary rays (fov, kfov, cfov, "
                                 "ckfov)");
    for (const char* refused : {"taa", "gaze_track", "lp_widen"})
        if (!ctx.param(refused, "").empty() && ctx.param(refused, "") != "off")
            throw std::runtime_error(std::string("frame: parameter '") + refused +
                                     "' is not ported by this pass");
    if (ctx.param("primary", "ray") != "ray" || ctx.param("resolve", "bilinear") != "bilinear")
        throw std::runtime_error("frame: only primary=ray and resolve=bilinear are ported");
    const std::string filters = ctx.param("filters", "");
    if (!filters.empty() && filters != "lerp")
        throw std::runtime_error("frame: filters '" + filters + "': only 'lerp' is ported");
    s.lerp = filters == "lerp";
    s.sigma = number_of(ctx.param("sigma", std::to_string(s.sigma)), "sigma");
    if (ctx.param("kernel", "power") != "power")
        throw std::runtime_error("kernel '" + ctx.param("kernel", "power") +
                                 "' is not ported (the power and polynomial kernels are)");
    s.alpha = number_of(ctx.param("alpha", std::to_string(s.alpha)), "alpha");
    s.gaze_angle = number_of(ctx.param("gaze_angle", std::to_string(s.gaze_angle)), "gaze_angle");
    s.lp_aspect = number_of(ctx.param("lp_aspect", std::to_string(s.lp_aspect)), "lp_aspect");
    s.corners = ctx.param("L", "diagonal") == "corners";
    std::stringstream beta(ctx.param("beta", ""));
    for (std::string item; std::getline(beta, item, ',');)
        s.beta.push_back(number_of(item, "beta"));
    if (s.beta.size() > 20) throw std::runtime_error("frame: more than 20 beta coefficients");
    return s;
}

// K(x) on the host (for G), as the shader computes it
float kernel_forward(const MapSettings& s, float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    if (s.beta.empty()) return s.alpha == 1.0f ? x : std::pow(x, s.alpha);
    float sum = 0.0f;
    for (std::size_t i = s.beta.size() - 1; i >= 1; --i) sum = sum * x + s.beta[i];
    return sum * x;
}

// The buffer size (binary64, halves away from zero), R, L, r_G, G and the gaze window.
FrameMap frame_map(const MapSettings& s, int width, int height, float gaze_x, float gaze_y,
                   float display_distance_px) {
    FrameMap m;
    const double screen_w = width, screen_h = height;
    double w = std::round(screen_w / s.sigma), h = std::round(screen_h / s.sigma);
    if (s.lp_aspect > 0.0f) {
        h = std::round(std::sqrt(screen_w * screen_h / s.lp_aspect) / s.sigma);
        w = std::round(h * s.lp_aspect);
    }
    m.width = static_cast<int>(std::max(w, 1.0));
    m.height = static_cast<int>(std::max(h, 1.0));
    m.gaze_x = gaze_x;
    m.gaze_y = gaze_y;
    const float fw = static_cast<float>(width), fh = static_cast<float>(height);
    float radius_max = std::sqrt(fw * fw + fh * fh);
    if (s.corners) {
        radius_max = 0.0f;
        for (const float cx : {0.0f, fw})
            for (const float cy : {0.0f, fh}) {
                const float dx = cx - gaze_x, dy = cy - gaze_y;
                radius_max = std::max(radius_max, std::sqrt(dx * dx + dy * dy));
            }
    }
    m.log_radius_max = std::log(1.0f + radius_max);
    if (s.gaze_angle > 0.0f) {
        m.gaze_radius = display_distance_px * std::tan(s.gaze_angle);
        m.composite =
            std::min(1.0f, kernel_forward(s, std::log(1.0f + m.gaze_radius) / m.log_radius_max));
    }
    // The window round the gaze circle, one pixel wider, clipped to the screen (binary64)
    const double r = static_cast<double>(m.gaze_radius) + 1.0;
    const auto clip = [](double v, int size) {
        return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(size)));
    };
    m.x0 = std::min(clip(std::floor(gaze_x - r), width), width - 1);
    m.y0 = std::min(clip(std::floor(gaze_y - r), height), height - 1);
    m.window_width = std::max(clip(std::ceil(gaze_x + r), width) - m.x0, 1);
    m.window_height = std::max(clip(std::ceil(gaze_y + r), height) - m.y0, 1);
    return m;
}

// Camera vectors of a manifest frame into the parameters (position's w: tan(vfov / 2)).
void set_camera(const json& camera, float* position, float* right, float* up, float* forward) {
    for (int k = 0; k < 3; ++k) {
        position[k] = camera.at("position").at(k).get<float>();
        right[k] = camera.at("right").at(k).get<float>();
        up[k] = camera.at("up").at(k).get<float>();
        forward[k] = camera.at("forward").at(k).get<float>();
    }
    position[3] = camera.at("tan_half_vfov").get<float>();
    right[3] = up[3] = forward[3] = 0.0f;
}

/// The scene as the shaders' storage buffers (frame_bvh.glsl, frame_shade.glsl).
struct SceneBuffers {
    GpuBvh bvh;
    std::vector<float> attributes, materials, texels, lights;
    float max_coordinate = 0.0f;  ///< the largest |coordinate| (the boxes' padding)
    float scene_scale = 1.0f;
    int light_count = 0;
};

float int_bits(std::int32_t value) {
    float f;
    std::memcpy(&f, &value, sizeof f);
    return f;
}

void push3(std::vector<float>& out, Vec3 v) { out.insert(out.end(), {v.x, v.y, v.z}); }

// Packs the scene: per primitive normals, uvs, material; materials; texels; lights.
SceneBuffers scene_buffers(const FrameScene& scene) {
    SceneBuffers b;
    b.bvh = build_gpu_bvh(scene);
    for (std::size_t t = 0; t < scene.triangles(); ++t) {
        for (int k = 0; k < 3; ++k) push3(b.attributes, scene.normals[3 * t + k]);
        b.attributes.insert(b.attributes.end(), scene.uvs.begin() + 6 * t,
                            scene.uvs.begin() + 6 * t + 6);
        b.attributes.push_back(static_cast<float>(scene.material_ids[t]));
    }
    std::vector<int> offsets;
    for (const FrameTexture& texture : scene.textures) {
        offsets.push_back(static_cast<int>(b.texels.size()));
        b.texels.insert(b.texels.end(), texture.rgb.begin(), texture.rgb.end());
    }
    for (const FrameMaterial& m : scene.materials) {
        push3(b.materials, m.albedo);
        push3(b.materials, m.emission);
        const bool textured = m.texture >= 0;
        const FrameTexture* texture = textured ? &scene.textures[m.texture] : nullptr;
        b.materials.insert(
            b.materials.end(),
            {int_bits(textured ? offsets[m.texture] : -1), int_bits(textured ? texture->width : 0),
             int_bits(textured ? texture->height : 0), 0.0f, 0.0f, 0.0f});
    }
    for (const FrameLight& l : scene.lights) {
        b.lights.push_back(int_bits(l.type));
        for (const Vec3& v : {l.position, l.edge_u, l.edge_v, l.intensity}) push3(b.lights, v);
        b.lights.insert(b.lights.end(), {0.0f, 0.0f, 0.0f});
    }
    for (const Vec3& p : scene.positions)
        b.max_coordinate =
            std::max({b.max_coordinate, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    b.scene_scale = scene.scene_scale;
    b.light_count = static_cast<int>(scene.lights.size());
    // Vulkan has no empty buffers
    for (std::vector<float>* v : {&b.attributes, &b.materials, &b.texels, &b.lights})
        if (v->empty()) v->push_back(0.0f);
    return b;
}

/// One frame's state on the host: its parameters and the records the trace kernel wrote.
struct FrameRun {
    FrameParams params{};
    FrameMap map;
    std::vector<float> lp, gaze;  ///< 25 floats per texel / gaze-window pixel (frame_common.glsl)
};

// The parameters of a manifest frame (its camera, the previous frame's for the motion).
FrameParams frame_params(const PassContext& ctx, const json& frame, const json& previous,
                         const MapSettings& s, const FrameMap& m, const SceneBuffers& b) {
    FrameParams p{};
    set_camera(frame.at("camera"), p.camera_position, p.camera_right, p.camera_up,
               p.camera_forward);
    set_camera(previous.at("camera"), p.previous_position, p.previous_right, p.previous_up,
               p.previous_forward);
    const std::int32_t screen[4] = {ctx.width(), ctx.height(), m.width, m.height};
    const std::int32_t window[4] = {m.x0, m.y0, m.window_width, m.window_height};
    const std::int32_t counts[4] = {b.light_count, frame.at("frame").get<std::int32_t>(),
                                    s.beta.empty() ? 0 : 1,
                                    static_cast<std::int32_t>(s.beta.size())};
    const std::int32_t launch[4] = {0, m.gaze_radius > 0.0f ? 1 : 0, 0, 0};
    const float map[4] = {m.gaze_x, m.gaze_y, m.log_radius_max, m.composite};
    const float map2[4] = {m.gaze_radius, s.alpha, 1.0f / s.alpha,
                           std::max(1.0f - m.composite, 0x1p-24f)};
    // the shadow rays' offset and t_max (docs/trace.md), the boxes' padding (docs/bvh.md)
    const float scene[4] = {1e-4f * b.scene_scale, 0x1p-19f * b.max_coordinate, 1.0f - 1e-4f, 0.0f};
    std::copy(screen, screen + 4, p.screen);
    std::copy(window, window + 4, p.window);
    std::copy(counts, counts + 4, p.counts);
    std::copy(launch, launch + 4, p.launch);
    std::copy(map, map + 4, p.map);
    std::copy(map2, map2 + 4, p.map2);
    std::copy(scene, scene + 4, p.scene);
    std::copy(s.beta.begin(), s.beta.end(), p.beta);
    return p;
}

// Channels [first, first + channels) of every record as an image of the buffer's size.
Image channels_of(const std::vector<float>& records, int width, int height, int first,
                  int channels) {
    Image image{width, height, channels, {}};
    image.data.resize(static_cast<std::size_t>(width) * height * channels);
    for (std::size_t k = 0; k < static_cast<std::size_t>(width) * height; ++k)
        for (int c = 0; c < channels; ++c)
            image.data[k * channels + c] = records[k * 25 + first + c];
    return image;
}

// Writes the G-buffer, validity (and screen points) and colour of `prefix` ("lp_", "gaze_"),
// each buffer the golden frame has.
void write_records(const PassContext& ctx, const json& frame, const std::string& prefix,
                   const std::vector<float>& records, int width, int height) {
    const struct {
        const char* name;
        int first, channels;
    } buffers[] = {{"gbuffer_view_depth", 0, 1},
                   {"gbuffer_hit_distance", 1, 1},
                   {"gbuffer_world_position", 2, 3},
                   {"gbuffer_shading_normal", 5, 3},
                   {"gbuffer_geometric_normal", 8, 3},
                   {"gbuffer_albedo", 11, 3},
                   {"gbuffer_material_id", 14, 1},
                   {"gbuffer_primitive_id", 15, 1},
                   {"gbuffer_motion", 16, 2},
                   {"valid", 18, 1},
                   {"screen_point", 19, 2},
                   {"color", 21, 3}};
    for (const auto& b : buffers) {
        const std::string name = prefix + b.name;
        if (!PassContext::has(frame, name)) continue;
        ctx.write(frame.at("frame").get<int>(), name,
                  channels_of(records, width, height, b.first, b.channels));
    }
}

// Lund's Fig. 3.3 buffer `ray_positions` (rays through each screen pixel), counted on the host
// from the records: a traced texel adds 1 at floor(its screen point), a traced gaze pixel at
// its own pixel (a debugging view, not a stage worth a kernel). `pixels` receives each texel's
// decision, ray_pixel: (floor(x), floor(y)) of the point it was counted at, (-1, -1) if none.
Image ray_positions(const PassContext& ctx, const FrameRun& run, Image& pixels) {
    const int width = ctx.width(), height = ctx.height();
    Image counts{width, height, 1,
                 std::vector<float>(static_cast<std::size_t>(width) * height, 0.0f)};
    pixels =
        Image{run.map.width, run.map.height, 2, std::vector<float>(run.lp.size() / 25 * 2, -1.0f)};
    for (std::size_t k = 0; k + 25 <= run.lp.size(); k += 25) {
        const float x = run.lp[k + 19], y = run.lp[k + 20];
        if (run.lp[k + 18] == 0.0f || !(x >= 0.0f && x < static_cast<float>(width) && y >= 0.0f &&
                                        y < static_cast<float>(height)))
            continue;
        const int px = static_cast<int>(x), py = static_cast<int>(y);
        counts.data[static_cast<std::size_t>(py) * width + px] += 1.0f;
        pixels.data[k / 25 * 2] = static_cast<float>(px);
        pixels.data[k / 25 * 2 + 1] = static_cast<float>(py);
    }
    if (!(run.map.gaze_radius > 0.0f)) return counts;
    for (int j = 0; j < run.map.window_height; ++j)
        for (int i = 0; i < run.map.window_width; ++i)
            if (run.gaze[(static_cast<std::size_t>(j) * run.map.window_width + i) * 25 + 18] !=
                0.0f)
                counts.data[static_cast<std::size_t>(run.map.y0 + j) * width + run.map.x0 + i] +=
                    1.0f;
    return counts;
}

// Texels or pixels of a record list with status `status` (frame_common.glsl), for the notes.
long count_status(const std::vector<float>& records, float status) {
    long n = 0;
    for (std::size_t k = 24; k < records.size(); k += 25) n += records[k] == status ? 1 : 0;
    return n;
}

/// The scene's buffers in the order of frame_trace.comp's bindings 1-6.
struct Bound {
    SceneBuffers& b;
    std::vector<HostBuffer> buffers() {
        return {host(b.bvh.nodes), host(b.bvh.triangles), host(b.attributes),
                host(b.materials), host(b.texels),        host(b.lights)};
    }
};

// Traces and shades the log-polar buffer and the gaze window (launch 0 and 1), timing each.
void trace_frame(PassContext& ctx, FrameRun& run, SceneBuffers& scene) {
    const FrameMap& m = run.map;
    for (int launch = 0; launch < 2; ++launch) {
        const bool gaze = launch == 1;
        if (gaze && !(m.gaze_radius > 0.0f)) {
            run.gaze.assign(25, 0.0f);  // bound, never read
            continue;
        }
        const int width = gaze ? m.window_width : m.width;
        const int height = gaze ? m.window_height : m.height;
        std::vector<float>& records = gaze ? run.gaze : run.lp;
        records.assign(static_cast<std::size_t>(width) * height * 25, 0.0f);
        std::vector<FrameParams> params{run.params};
        params[0].launch[0] = launch;
        std::vector<HostBuffer> buffers{host(params)};
        for (const HostBuffer& b : Bound{scene}.buffers()) buffers.push_back(b);
        buffers.push_back(host(records));
        ctx.dispatch("frame_trace", buffers, nullptr, 0, groups(width, 8), groups(height, 8));
        ctx.notes[gaze ? "gaze_trace_ms" : "lp_trace_ms"] = ctx.vk.last_run_ms();
    }
}

// Lund's Gaussian lerp after pass 2 with the lerp pass's correct shader (this pass's bug lives
// in its own shaders); `in` is pass 2's output.
Image gaussian_lerp(PassContext& ctx, const FrameRun& run, Image& in) {
    const int width = ctx.width(), height = ctx.height();
    const float diagonal = std::sqrt(static_cast<float>(width * width + height * height));
    float farthest = 0.0f;
    for (const float cx : {0.0f, static_cast<float>(width)})
        for (const float cy : {0.0f, static_cast<float>(height)})
            farthest = std::max(farthest, std::hypot(cx - run.map.gaze_x, cy - run.map.gaze_y));
    const struct {
        std::int32_t width, height, channels;
        float gaze_x, gaze_y, ramp_start, ramp_span;
    } push{width,
           height,
           3,
           run.map.gaze_x,
           run.map.gaze_y,
           diagonal / 6.0f,
           farthest - diagonal / 6.0f};
    Image out{width, height, 3, std::vector<float>(in.data.size(), 0.0f)};
    ctx.vk.dispatch(std::string(FOVREF_VK_SHADER_DIR) + "/gaussian_lerp.spv",
                    {host(in.data), host(out.data)}, &push, sizeof push, groups(width, 8),
                    groups(height, 8));
    ctx.device_ms += ctx.vk.last_run_ms();
    ++ctx.dispatches;
    return out;
}

// Pass 2 (and the lerp) of one frame; writes the screen buffers the golden frame has.
void resolve_frame(PassContext& ctx, const json& frame, FrameRun& run, const MapSettings& s) {
    Image resolved{ctx.width(), ctx.height(), 3, {}};
    resolved.data.assign(static_cast<std::size_t>(ctx.width()) * ctx.height() * 3, 0.0f);
    std::vector<FrameParams> params{run.params};
    std::vector<float> decisions(resolved.data.size() / 3 * 4, 0.0f);
    ctx.dispatch("frame_resolve",
                 {host(params), host(run.lp), host(run.gaze), host(resolved.data), host(decisions)},
                 nullptr, 0, groups(ctx.width(), 8), groups(ctx.height(), 8));
    ctx.notes["resolve_ms"] = ctx.vk.last_run_ms();
    const int index = frame.at("frame").get<int>();
    ctx.write_resolve_decisions(index, decisions, 0);
    const std::string resolve_output = PassContext::output_of(frame, "resolve");
    if (!resolve_output.empty()) ctx.write(index, resolve_output, resolved);
    const std::string lerp_output = PassContext::output_of(frame, "gaussian_lerp");
    if (s.lerp && !lerp_output.empty())
        ctx.write(index, lerp_output, gaussian_lerp(ctx, run, resolved));
}

// The gaze of the case (`gaze` X,Y; default the screen centre)
void case_gaze(const PassContext& ctx, float& x, float& y) {
    x = 0.5f * static_cast<float>(ctx.width());
    y = 0.5f * static_cast<float>(ctx.height());
    const std::string gaze = ctx.param("gaze", "");
    if (!gaze.empty() && std::sscanf(gaze.c_str(), "%f,%f", &x, &y) != 2)
        throw std::runtime_error("frame: parameter 'gaze': '" + gaze + "' is not X,Y");
}

// The exported scene's file (manifest "scene_export"), or a message naming the export option.
std::string scene_file(const PassContext& ctx) {
    if (!ctx.manifest.contains("scene_export"))
        throw std::runtime_error("frame: " + ctx.bundle +
                                 " has no exported scene (manifest \"scene_export\"): export "
                                 "the bundle with `fovref golden export CASE DIR --with-scene "
                                 "--raw-copies`");
    return ctx.bundle + "/" + ctx.manifest.at("scene_export").get<std::string>();
}

int run(PassContext& ctx) {
    const MapSettings settings = map_settings(ctx);
    const FrameScene scene = load_frame_scene(scene_file(ctx));
    SceneBuffers buffers = scene_buffers(scene);
    ctx.notes["bvh"] =
        "binned-SAH BVH2 (16 bins, leaves <= 4 triangles), depth-first 32-byte nodes "
        "(left child adjacent, right index stored), triangles in leaf order: " +
        std::to_string(buffers.bvh.nodes.size()) + " nodes, " + std::to_string(buffers.bvh.leaves) +
        " leaves, depth " + std::to_string(buffers.bvh.depth);
    ctx.notes["precise"] =
        "map (t, r, p), gaze distance, primary direction, watertight test, "
        "surface interpolation, texture bilinear, shading sums, pass-2 lerps";
    float gaze_x = 0.0f, gaze_y = 0.0f;
    case_gaze(ctx, gaze_x, gaze_y);
    const json* previous = nullptr;
    int frames = 0;
    for (const json& frame : ctx.frames()) {
        if (!PassContext::has(frame, "lp_valid"))
            throw std::runtime_error("frame: frame " +
                                     std::to_string(frame.at("frame").get<int>()) + " of " +
                                     ctx.bundle + " has no lp_valid (not a log-polar mode)");
        const float display = frame.value("display_distance_px",
                                          0.5f * static_cast<float>(ctx.height()) /
                                              frame.at("camera").at("tan_half_vfov").get<float>());
        FrameRun run;
        run.map = frame_map(settings, ctx.width(), ctx.height(), gaze_x, gaze_y, display);
        run.params =
            frame_params(ctx, frame, previous ? *previous : frame, settings, run.map, buffers);
        trace_frame(ctx, run, buffers);
        const int index = frame.at("frame").get<int>();
        write_records(ctx, frame, "lp_", run.lp, run.map.width, run.map.height);
        if (run.map.gaze_radius > 0.0f)
            write_records(ctx, frame, "gaze_", run.gaze, run.map.window_width,
                          run.map.window_height);
        resolve_frame(ctx, frame, run, settings);
        if (PassContext::has(frame, "ray_positions")) {
            Image pixels;
            ctx.write(index, "ray_positions", ray_positions(ctx, run, pixels));
            ctx.write(index, "ray_pixel", pixels);
        }
        ctx.notes["frame " + std::to_string(index)] = {
            {"buffer", std::to_string(run.map.width) + "x" + std::to_string(run.map.height)},
            {"texels_traced", count_status(run.lp, 0.0f)},
            {"texels_off_screen", count_status(run.lp, 1.0f)},
            {"gaze_window", {run.map.x0, run.map.y0, run.map.window_width, run.map.window_height}},
            {"gaze_pixels_traced", run.map.gaze_radius > 0.0f ? count_status(run.gaze, 0.0f) : 0}};
        previous = &frame;
        ++frames;
    }
    return frames;
}

const bool registered = register_pass(
    {"frame",
     "end-to-end fov/kfov/cfov/ckfov frame from the exported scene: BVH, log-polar and gaze "
     "trace + shade, pass 2 (and the lerp)",
     "texel centre without +1/2 in the log-polar ray generation (and pass 2's taps)", run});

}  // namespace
}  // namespace fovref_client
