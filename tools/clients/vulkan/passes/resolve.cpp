// Pass 2 of the log-polar modes (shaders/resolve.comp, shaders/resolve_mips.comp): lp_color (or
// lp_color_aa after Meng's internal AA), lp_valid and, in the composite modes, gaze_color in; the
// resolve stage's buffer (`final` or `resolved`) out, on every frame that has it. Bilinear
// (fov, kfov, cfov, ckfov) or Meng's mip resolve (kfr, `resolve=mip`): the pyramid takes one
// dispatch per level, then one dispatch resolves every pixel. The map's constants (R, L, r_G,
// G) are computed once per frame on the host, as a renderer would, from the case's parameters
// (the mode's defaults where the manifest lists none), the frame's display distance and the
// manifest's counters (gaze_window_x0, gaze_window_y0); the gaze is the case's `gaze`
// (default the screen centre); `gaze_track` is refused. The dump also holds the decisions each
// pixel took, resolve_tap and (mip) resolve_mip_level, which the diff judges against the
// oracle's margins, and each pixel's lookup, fNNN_<output>_lookup.f32 (u, v, lambda, source),
// to look at a flip with.
//
// log_polar_map_block (below) is shared with passes/stereo_resolve.cpp and passes/post_aa.cpp.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include "tools/clients/vulkan/pass.h"
#include "tools/clients/vulkan/passes/lp_map.h"

namespace fovref_client {

namespace {

/// A log-polar mode's defaults for what pass 2 reads (`fovref modes`).
struct ModeDefaults {
    const char* mode;
    const char* alpha;
    const char* radius;      ///< L: "diagonal" or "corners"
    const char* gaze_angle;  ///< a_G in radians
    const char* resolve;     ///< "bilinear" or "mip"
};

constexpr ModeDefaults mode_defaults[] = {
    {"fov", "1", "diagonal", "0", "bilinear"},    {"kfov", "3", "diagonal", "0", "bilinear"},
    {"cfov", "1", "diagonal", "0.2", "bilinear"}, {"ckfov", "2", "diagonal", "0.15", "bilinear"},
    {"kfr", "4", "corners", "0", "mip"},          {"stereo-lp", "1", "corners", "0", "bilinear"},
};

/// shaders/include/lp_map.glsl's LpMap, word for word (std430: 4-byte scalars, float[17]).
struct LpMapBlock {
    float gaze_x, gaze_y;
    std::int32_t screen_width, screen_height, width, height;
    float radius_max, log_radius_max, gaze_radius, composite;
    std::int32_t kernel_kind;
    float alpha, inverse_alpha;
    std::int32_t beta_count;
    float beta[17];
};
static_assert(sizeof(LpMapBlock) == 31 * 4, "LpMap is 31 words");

const ModeDefaults& defaults_of(const PassContext& ctx) {
    const std::string mode = ctx.manifest.at("case").at("mode").get<std::string>();
    for (const ModeDefaults& d : mode_defaults)
        if (mode == d.mode) return d;
    throw std::runtime_error("mode '" + mode + "' is not a log-polar mode (" +
                             "fov, kfov, cfov, ckfov, kfr, stereo-lp)");
}

/// K(x) on the host, for G: x^alpha or Horner from beta_n down (the shader's lp_kernel_forward)
float kernel_forward(const LpMapBlock& m, float x) {
    x = std::clamp(x, 0.0f, 1.0f);
    if (m.kernel_kind == 0) return m.alpha == 1.0f ? x : std::pow(x, m.alpha);
    float sum = 0.0f;
    for (int i = m.beta_count - 1; i >= 1; --i) sum = sum * x + m.beta[i];
    return sum * x;
}

/// The kernel: `beta` (a polynomial) when the case gives it, else x^alpha.
void read_kernel(const PassContext& ctx, const ModeDefaults& d, LpMapBlock& m) {
    if (ctx.param("kernel", "power") != "power")
        throw std::runtime_error("kernel '" + ctx.param("kernel", "power") +
                                 "' is not ported (the power and polynomial kernels are)");
    const std::string beta = ctx.param("beta", "");
    m.alpha = ctx.float_param("alpha", d.alpha);
    m.inverse_alpha = 1.0f / m.alpha;
    if (beta.empty()) return;
    m.kernel_kind = 1;
    for (std::size_t start = 0; start <= beta.size();) {
        const std::size_t comma = std::min(beta.find(',', start), beta.size());
        if (m.beta_count == 17)
            throw std::runtime_error("parameter beta: more than 17 coefficients");
        char* end = nullptr;
        const std::string item = beta.substr(start, comma - start);
        m.beta[m.beta_count++] = std::strtof(item.c_str(), &end);
        if (item.empty() || *end != '\0')
            throw std::runtime_error("parameter beta: '" + item + "' is not a number");
        start = comma + 1;
    }
}

/// The gaze of the case (`gaze`, default the centre of a W x H screen).
void read_gaze(const PassContext& ctx, int screen_width, int screen_height, LpMapBlock& m) {
    if (!ctx.param("gaze_track", "").empty())
        throw std::runtime_error("gaze_track is not read yet (give a case with `gaze`)");
    m.gaze_x = 0.5f * static_cast<float>(screen_width);
    m.gaze_y = 0.5f * static_cast<float>(screen_height);
    const std::string gaze = ctx.param("gaze", "");
    if (!gaze.empty() && std::sscanf(gaze.c_str(), "%f,%f", &m.gaze_x, &m.gaze_y) != 2)
        throw std::runtime_error("parameter gaze '" + gaze + "' is not X,Y");
}

/// R (the screen diagonal, or the farthest corner from the gaze) and L = ln(1 + R).
void set_radius(const std::string& radius, LpMapBlock& m) {
    const float w = static_cast<float>(m.screen_width), h = static_cast<float>(m.screen_height);
    if (radius == "diagonal") {
        m.radius_max = std::sqrt(w * w + h * h);
    } else if (radius == "corners") {
        for (const float cx : {0.0f, w})
            for (const float cy : {0.0f, h}) {
                const float dx = cx - m.gaze_x, dy = cy - m.gaze_y;
                m.radius_max = std::max(m.radius_max, std::sqrt(dx * dx + dy * dy));
            }
    } else {
        throw std::runtime_error("parameter L '" + radius + "' is neither diagonal nor corners");
    }
    m.log_radius_max = std::log(1.0f + m.radius_max);
}

/// The case's log-polar map of frame `frame` for a screen_width x screen_height screen (one eye's
/// in stereo) and a buffer_width x buffer_height buffer (0 x 0 when the pass reads only the gaze
/// and R): the gaze, R, L, r_G = d_px tan(a_G) with the frame's display distance,
/// G = min(1, K(ln(1 + r_G) / L)), the kernel. Throws std::runtime_error naming a parameter it
/// cannot use.
LpMapBlock make_map(const PassContext& ctx, const json& frame, int screen_width, int screen_height,
                    int buffer_width, int buffer_height) {
    const ModeDefaults& d = defaults_of(ctx);
    LpMapBlock m{};
    m.screen_width = screen_width;
    m.screen_height = screen_height;
    m.width = buffer_width;
    m.height = buffer_height;
    read_gaze(ctx, screen_width, screen_height, m);
    read_kernel(ctx, d, m);
    set_radius(ctx.param("L", d.radius), m);
    const float gaze_angle = ctx.float_param("gaze_angle", d.gaze_angle);
    if (gaze_angle > 0.0f) {
        if (!frame.contains("display_distance_px"))
            throw std::runtime_error("frame " + std::to_string(frame.at("frame").get<int>()) +
                                     " has no display_distance_px to turn a_G into pixels");
        const float distance = frame.at("display_distance_px").get<float>();
        m.gaze_radius = distance * std::tan(gaze_angle);
        m.composite =
            std::min(1.0f, kernel_forward(m, std::log(1.0f + m.gaze_radius) / m.log_radius_max));
    }
    return m;
}

/// The block's 31 words, as the shaders bind it.
std::vector<std::uint32_t> words_of(const LpMapBlock& m) {
    std::vector<std::uint32_t> words(sizeof(LpMapBlock) / 4);
    std::memcpy(words.data(), &m, sizeof m);
    return words;
}

}  // namespace

std::vector<std::uint32_t> log_polar_map_block(const PassContext& ctx, const json& frame,
                                               int screen_width, int screen_height,
                                               int buffer_width, int buffer_height) {
    return words_of(make_map(ctx, frame, screen_width, screen_height, buffer_width, buffer_height));
}

namespace {

/// Per level: (first texel, width, height, 0), until 1 x 1 (ceil halves).
std::vector<std::int32_t> pyramid_levels(int width, int height, bool mip) {
    std::vector<std::int32_t> levels = {0, width, height, 0};
    while (mip && (width > 1 || height > 1)) {
        const int offset = levels[levels.size() - 4] + width * height;
        width = (width + 1) / 2;
        height = (height + 1) / 2;
        levels.insert(levels.end(), {offset, width, height, 0});
    }
    return levels;
}

/// The push constants of shaders/resolve.comp.
struct ResolveParameters {
    std::int32_t screen_width, screen_height, channels, level_count, mip;
    std::int32_t gaze_x0, gaze_y0, gaze_width, gaze_height;
};

/// The composite modes' gaze buffer and its window (from the manifest's counters).
Image read_gaze_buffer(const PassContext& ctx, const json& frame, ResolveParameters& push) {
    Image gaze = ctx.read(frame, "gaze_color");
    const json& counters = frame.at("counters");
    for (const char* key : {"gaze_window_x0", "gaze_window_y0"})
        if (!counters.contains(key))
            throw std::runtime_error("frame " + std::to_string(frame.at("frame").get<int>()) +
                                     " has a gaze buffer but no counter " + key);
    push.gaze_x0 = counters.at("gaze_window_x0").get<int>();
    push.gaze_y0 = counters.at("gaze_window_y0").get<int>();
    push.gaze_width = gaze.width;
    push.gaze_height = gaze.height;
    return gaze;
}

/// The pyramid's storage: level 0 is the buffer and its mask, the others are filled by
/// shaders/resolve_mips.comp, one dispatch per level.
void build_pyramid(PassContext& ctx, const Image& colour, const Image& valid,
                   std::vector<std::int32_t>& levels, std::vector<float>& pyramid,
                   std::vector<float>& mask) {
    const int level_count = static_cast<int>(levels.size() / 4);
    const auto level = [&](int l, int k) { return levels[static_cast<std::size_t>(4 * l + k)]; };
    const std::size_t texels = static_cast<std::size_t>(level(level_count - 1, 0)) +
                               static_cast<std::size_t>(level(level_count - 1, 1)) *
                                   static_cast<std::size_t>(level(level_count - 1, 2));
    pyramid.assign(texels * colour.channels, 0.0f);
    mask.assign(texels, 0.0f);
    std::copy(colour.data.begin(), colour.data.end(), pyramid.begin());
    std::copy(valid.data.begin(), valid.data.end(), mask.begin());
    for (int l = 0; l + 1 < level_count; ++l) {
        const std::int32_t push[2] = {l, colour.channels};
        ctx.dispatch("resolve_mips", {host(levels), host(pyramid), host(mask)}, push, sizeof push,
                     groups(level(l + 1, 1), 8), groups(level(l + 1, 2), 8));
    }
}

/// Pass 2 of one frame: writes `output` and its lookups (u, v, lambda, source per pixel).
void resolve_frame(PassContext& ctx, const json& frame, const std::string& output) {
    const ModeDefaults& d = defaults_of(ctx);
    const Image colour =
        ctx.read(frame, PassContext::has(frame, "lp_color_aa") ? "lp_color_aa" : "lp_color");
    const Image valid = ctx.read(frame, "lp_valid");
    if (colour.channels > 4) throw std::runtime_error("more than 4 channels in the buffer");
    if (valid.width != colour.width || valid.height != colour.height || valid.channels != 1)
        throw std::runtime_error("lp_valid is not a mask of the colour buffer's size");
    const LpMapBlock map =
        make_map(ctx, frame, ctx.width(), ctx.height(), colour.width, colour.height);
    const std::string filter = ctx.param("resolve", d.resolve);
    if (filter != "mip" && filter != "bilinear")
        throw std::runtime_error("parameter resolve '" + filter + "' is neither mip nor bilinear");
    std::vector<std::int32_t> levels = pyramid_levels(colour.width, colour.height, filter == "mip");
    std::vector<float> pyramid, mask;
    build_pyramid(ctx, colour, valid, levels, pyramid, mask);
    const int level_count = static_cast<int>(levels.size() / 4);
    ResolveParameters push{
        ctx.width(), ctx.height(), colour.channels, level_count, filter == "mip", 0, 0, 0, 0};
    Image gaze{1, 1, colour.channels, std::vector<float>(4, 0.0f)};
    if (map.gaze_radius > 0.0f) gaze = read_gaze_buffer(ctx, frame, push);
    const std::size_t pixels = static_cast<std::size_t>(ctx.width()) * ctx.height();
    Image result{ctx.width(), ctx.height(), colour.channels,
                 std::vector<float>(pixels * colour.channels, 0.0f)};
    Image lookups{ctx.width(), ctx.height(), 4, std::vector<float>(pixels * 4, 0.0f)};
    std::vector<float> decisions(pixels * 4, 0.0f);
    std::vector<std::uint32_t> words = words_of(map);
    ctx.dispatch("resolve",
                 {host(words), host(levels), host(pyramid), host(mask), host(gaze.data),
                  host(result.data), host(lookups.data), host(decisions)},
                 &push, sizeof push, groups(ctx.width(), 8), groups(ctx.height(), 8));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, output, result);
    ctx.write(index, output + "_lookup", lookups);
    ctx.write_resolve_decisions(index, decisions, filter == "mip" ? 1 : 0);
    ctx.notes["resolve"] =
        filter == "mip" ? "mip, " + std::to_string(level_count) + " levels" : filter;
}

int run(PassContext& ctx) {
    if (ctx.manifest.at("case").at("mode") == "stereo-lp")
        throw std::runtime_error("stereo-lp's pass 2 is the stereo_resolve pass");
    const int frames = ctx.each_frame(
        "resolve",
        [&](const json& frame, const std::string& output) { resolve_frame(ctx, frame, output); },
        "the bundle has no resolve stage (pass 2)");
    ctx.notes["precise"] =
        "lp_map.glsl: x' x' + y' y', the polynomial kernel's Horner steps, the inverse's "
        "G + (1 - G) u / w and g + r cos; lp_bilinear.glsl's lerps; the mip levels' lerp";
    return frames;
}

const bool registered = register_pass(
    {"resolve",
     "pass 2 of the log-polar modes (bilinear, or kfr's mip): lp_color (lp_color_aa), lp_valid "
     "[, gaze_color] -> the resolve stage's buffer",
     "v not wrapped at the buffer's seam (rows clamped like columns)", run});

}  // namespace
}  // namespace fovref_client
