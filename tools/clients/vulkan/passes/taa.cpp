// Lund's TAA (shaders/taa.comp, docs/temporal.md): for each frame of a sequence, the current
// colour (`shaded` in basic, `resolved` in the log-polar modes and kfr), the current view depth
// (`gbuffer_view_depth`, or `taa_view_depth` from taa_source) and, for clamp-buffer, the boxes
// `taa_bounds` in; the history is the golden's PREVIOUS frame: its TAA output, `taa_age`, the
// depth it read and its camera (the manifest's). Out: the taa stage's colour (`final` or
// `taa_color`) and `taa_age`. Frame 0 has no history. The per-frame constants (stationary
// camera, the reprojection factored in the previous camera's axes) are made on the host, as a
// renderer would. The dump's record (port.json) gets the decisions' counts per frame next to the
// oracle's counters and whether they agree; FOVREF_VK_TAA_DECISIONS=1 also writes each pixel's
// decision to OUT/taa_decision/fNNN.f32 (0 first, 1 stationary, 2 kept, 3 rejected, 4 periphery, 5
// clamped, +8 for a non-finite input). stereo-lp (TAA per eye) and gaze_track are refused.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

// shaders/taa.comp's push constants (100 bytes, every member 4 bytes: no padding).
struct TaaPush {
    std::int32_t width, height, history, rejection;
    float tau, age_cap, periphery_radius, gaze_x, gaze_y, sx_scale, sy_scale;
    float offset[3], forward[3], right[3], up[3], a[2];
};
static_assert(sizeof(TaaPush) == 100, "push constants out of step with shaders/taa.comp");

struct Vec3 {
    float x, y, z;
    bool operator==(const Vec3&) const = default;
};

// A frame's camera as the manifest records it (binary32 values).
struct Pose {
    Vec3 position, right, up, forward;
    float vfov_deg, tan_half;
    // Bit-for-bit pose equality, as the oracle's (the stationary rule, SPEC §7).
    bool same_pose(const Pose& o) const {
        return position == o.position && right == o.right && up == o.up && forward == o.forward &&
               vfov_deg == o.vfov_deg;
    }
};

Vec3 vec3_of(const json& v) {
    return {v.at(0).get<float>(), v.at(1).get<float>(), v.at(2).get<float>()};
}

Pose pose_of(const json& frame) {
    if (!frame.contains("camera"))
        throw std::runtime_error("frame " + std::to_string(frame.at("frame").get<int>()) +
                                 " records no camera: TAA reprojects with it");
    const json& c = frame.at("camera");
    return {vec3_of(c.at("position")),     vec3_of(c.at("right")),
            vec3_of(c.at("up")),           vec3_of(c.at("forward")),
            c.at("vfov_deg").get<float>(), c.at("tan_half_vfov").get<float>()};
}

// (a . b) in binary32, summed x, y, z in that order.
float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// v in the previous camera's axes: (v . R', -(v . U'), v . F').
void in_axes(const Pose& previous, Vec3 v, float out[3]) {
    out[0] = dot(v, previous.right);
    out[1] = -dot(v, previous.up);
    out[2] = dot(v, previous.forward);
}

// The reprojection's per-frame constants (the oracle's taa_reprojection, binary32).
void set_reprojection(TaaPush& push, const Pose& camera, const Pose& previous) {
    const float w = static_cast<float>(push.width), h = static_cast<float>(push.height);
    push.sx_scale = camera.tan_half * (w / h);
    push.sy_scale = camera.tan_half;
    const Vec3 offset{camera.position.x - previous.position.x,
                      camera.position.y - previous.position.y,
                      camera.position.z - previous.position.z};
    in_axes(previous, offset, push.offset);
    in_axes(previous, camera.forward, push.forward);
    in_axes(previous, camera.right, push.right);
    in_axes(previous, camera.up, push.up);
    push.a[0] = (0.5f * w) / (previous.tan_half * (w / h));
    push.a[1] = (0.5f * h) / previous.tan_half;
}

// What every frame shares: the size, the rejection rule, tau, the cap, the periphery radius
// (periphery x the screen diagonal, binary32) and the gaze (the `gaze` parameter, else the
// screen's centre).
TaaPush frame_constants(const PassContext& ctx) {
    TaaPush push{};
    push.width = ctx.width();
    push.height = ctx.height();
    const std::string mode = ctx.param("taa", "off");
    if (mode == "off") throw std::runtime_error("the case runs no TAA (parameter taa=off)");
    push.rejection = mode == "depth" ? 0 : mode == "clamp-screen" ? 1 : 2;
    if (ctx.manifest.at("case").value("mode", "") == "stereo-lp")
        throw std::runtime_error("stereo-lp's TAA per eye is not ported");
    if (!ctx.param("gaze_track", "").empty())
        throw std::runtime_error("gaze_track is not read yet (give a case with `gaze`)");
    push.tau = ctx.float_param("taa_tau", "0.01");
    push.age_cap = ctx.float_param("taa_age_cap", "20");
    const float w = static_cast<float>(push.width), h = static_cast<float>(push.height);
    push.periphery_radius =
        ctx.float_param("taa_periphery", "0.333333343") * std::sqrt(w * w + h * h);
    push.gaze_x = 0.5f * w;
    push.gaze_y = 0.5f * h;
    const std::string gaze = ctx.param("gaze", "");
    if (!gaze.empty()) std::sscanf(gaze.c_str(), "%f,%f", &push.gaze_x, &push.gaze_y);
    return push;
}

// The buffers TAA reads and writes in `frame`: colour, depth, output (the taa stage's colour
// buffer; its taa_margin, the oracle's distances from the thresholds, is not a port's output).
struct TaaNames {
    std::string colour, depth, output;
};

TaaNames names_of(const json& frame) {
    TaaNames n;
    n.colour = PassContext::has(frame, "resolved") ? "resolved" : "shaded";
    n.depth = PassContext::has(frame, "taa_view_depth") ? "taa_view_depth" : "gbuffer_view_depth";
    for (const json& b : frame.at("buffers"))
        if (b.value("stage", "") == "taa" && b.value("kind", "") == "color")
            n.output = b.at("name");
    if (n.output.empty())
        throw std::runtime_error("frame " + std::to_string(frame.at("frame").get<int>()) +
                                 " has no colour buffer of the taa stage");
    return n;
}

// The decisions' counts of one frame beside the oracle's counters (the manifest's).
json count_decisions(const json& frame, const std::vector<std::uint32_t>& decisions) {
    static const char* const names[] = {"first",    "stationary", "kept",
                                        "rejected", "periphery",  "clamped"};
    json counts = json::object();
    for (const char* name : names) counts[name] = 0;
    int nonfinite = 0;
    for (const std::uint32_t d : decisions) {
        counts[names[d & 7u]] = counts[names[d & 7u]].get<int>() + 1;
        nonfinite += (d & 8u) ? 1 : 0;
    }
    counts["nonfinite"] = nonfinite;
    json oracle = json::object();
    if (frame.contains("counters"))
        for (const auto& [key, value] : frame.at("counters").items())
            if (key.rfind("taa_", 0) == 0) oracle[key] = value;
    const auto count = [&](const char* name) { return counts[name].get<std::int64_t>(); };
    const auto counter = [&](const char* name) { return oracle.value(name, std::int64_t{-1}); };
    const bool agree = count("stationary") + count("kept") == counter("taa_history_kept") &&
                       count("rejected") == counter("taa_history_rejected") &&
                       count("clamped") == counter("taa_history_clamped") &&
                       count("periphery") == counter("taa_periphery_kept") &&
                       count("stationary") == counter("taa_reprojection_skipped") &&
                       count("nonfinite") == counter("taa_history_nonfinite");
    return {{"frame", frame.at("frame")}, {"vulkan", counts}, {"oracle", oracle}, {"agree", agree}};
}

// With FOVREF_VK_TAA_DECISIONS=1: the frame's per-pixel decisions as raw binary32, top row first.
void write_decisions(const PassContext& ctx, int frame,
                     const std::vector<std::uint32_t>& decisions) {
    const char* wanted = std::getenv("FOVREF_VK_TAA_DECISIONS");
    if (!wanted || std::string(wanted) != "1") return;
    std::filesystem::create_directories(ctx.out + "/taa_decision");
    char file[64];
    std::snprintf(file, sizeof file, "/taa_decision/f%03d.f32", frame);
    write_binary32(ctx.out + file, std::vector<float>(decisions.begin(), decisions.end()));
}

// One frame: the dispatch over its inputs and the previous frame's state (null: no history).
void run_frame(PassContext& ctx, TaaPush push, const json& frame, const json* previous) {
    const TaaNames names = names_of(frame);
    Image colour = ctx.read(frame, names.colour), depth = ctx.read(frame, names.depth);
    Image history = colour,
          age{push.width, push.height, 1, std::vector<float>(depth.data.size(), 1.0f)};
    Image history_depth = depth, bounds{1, 1, 1, {0.0f}};
    push.history = 0;
    if (previous) {
        const TaaNames before = names_of(*previous);
        history = ctx.read(*previous, before.output);
        age = ctx.read(*previous, "taa_age");
        history_depth = ctx.read(*previous, before.depth);
        const Pose camera = pose_of(frame), previous_camera = pose_of(*previous);
        push.history = camera.same_pose(previous_camera) ? 1 : 2;
        set_reprojection(push, camera, previous_camera);
    }
    if (push.rejection == 2) bounds = ctx.read(frame, "taa_bounds");
    Image result{push.width, push.height, 3, std::vector<float>(colour.data.size(), 0.0f)};
    Image result_age{push.width, push.height, 1, std::vector<float>(depth.data.size(), 0.0f)};
    std::vector<std::uint32_t> decisions(depth.data.size(), 0u);
    ctx.dispatch("taa",
                 {host(colour.data), host(depth.data), host(history.data), host(age.data),
                  host(history_depth.data), host(bounds.data), host(result.data),
                  host(result_age.data), host(decisions)},
                 &push, sizeof push, groups(push.width, 8), groups(push.height, 8));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, names.output, result);
    ctx.write(index, "taa_age", result_age);
    write_decisions(ctx, index, decisions);
    ctx.notes["decisions"].push_back(count_decisions(frame, decisions));
}

int run(PassContext& ctx) {
    const json* previous = nullptr;
    TaaPush constants{};
    int frames = 0;
    for (const json& frame : ctx.frames()) {
        if (!PassContext::has(frame, "taa_age")) {
            previous = nullptr;
            continue;
        }
        if (frames == 0) ctx.notes["decisions"] = json::array();
        const int index = frame.at("frame").get<int>();
        if (index > 0 && (!previous || previous->at("frame").get<int>() != index - 1))
            throw std::runtime_error("frame " + std::to_string(index) + " needs frame " +
                                     std::to_string(index - 1) + "'s TAA history, not in " +
                                     ctx.bundle);
        if (frames == 0) {
            constants = frame_constants(ctx);  // refuses what is not ported
            ctx.notes["precise"] =
                "taa.comp: the reprojection (sx, sy, d, q, p') and the blend history (1 - w) + "
                "current w, whose binary32 order the docs give; the bilinear sums are not";
        }
        run_frame(ctx, constants, frame, index > 0 ? previous : nullptr);
        previous = &frame;
        ++frames;
    }
    if (frames == 0) throw std::runtime_error("the bundle has no taa stage (no taa_age)");
    return frames;
}

const bool registered = register_pass(
    {"taa",
     "Lund's TAA (depth rejection, Karis clamp-screen/clamp-buffer): the current colour and "
     "depth, the previous frame's output, taa_age, depth, camera -> the taa stage's colour, "
     "taa_age",
     "the history's bilinear taps around p' instead of p' - 1/2 (half a pixel off)", run});

}  // namespace
}  // namespace fovref_client
