#include "ref/log_polar/stereo.h"

#include <algorithm>
#include <cmath>

#include "ref/core/error.h"
#include "ref/core/vec.h"
#include "ref/filters/internal_aa.h"

namespace fovref {

namespace {

// The foveated parameters stereo-lp takes (the rest keep the preset's values).
const char* const eye_params[] = {"sigma", "alpha", "beta", "lp_aspect", "L", "gaze", "gaze_track"};

}  // namespace

const FoveationPreset& stereo_preset() {
    static const FoveationPreset preset = [] {
        FoveationPreset p;
        p.name = "stereo-lp";
        p.source = "Gupta 2019";
        p.map.sigma = 1.41421356f;
        p.map.kernel = power_kernel(1.0f);
        p.map.lp_aspect = 0.0f;
        p.map.radius = RadiusMode::corners;
        return p;
    }();
    return preset;
}

std::vector<ParamSpec> stereo_param_specs() {
    std::vector<ParamSpec> specs;
    for (const ParamSpec& spec : foveated_param_specs(stereo_preset()))
        for (const char* name : eye_params)
            if (spec.name == name) specs.push_back(spec);
    for (ParamSpec& spec : specs)
        if (spec.name == "gaze" || spec.name == "gaze_track")
            spec.doc += " (in each eye's coordinates, for both eyes; default each eye's centre)";
    specs.push_back({"ipd", "0.064", "interpupillary distance in scene units"});
    specs.push_back({"barrel", "off", "Gupta's barrel distortion in pass 2: on or off"});
    specs.push_back({"k1", "0.22", "barrel distortion: coefficient of |q|^2"});
    specs.push_back({"k2", "0.24", "barrel distortion: coefficient of |q|^4"});
    specs.push_back({"blur", "off",
                     "Gupta's pre-resolve blur (Gupta §2, citing Meng): 'internal_aa' runs Meng's "
                     "internal AA on each eye's buffer before pass 2; 'off' (Gupta's shader)"});
    return specs;
}

StereoParams parse_stereo_params(const Params& params) {
    const std::vector<ParamSpec> specs = stereo_param_specs();
    std::map<std::string, std::string> eye;
    for (const auto& [key, value] : params.values())
        for (const char* name : eye_params)
            if (key == name) eye[key] = value;
    StereoParams parsed;
    parsed.eye = parse_foveated_params(Params(eye), stereo_preset());
    parsed.ipd = params.get_float(specs, "ipd", 0.0f, 1e6f);
    parsed.barrel = params.get_bool(specs, "barrel");
    parsed.k1 = params.get_float(specs, "k1", -10.0f, 10.0f);
    parsed.k2 = params.get_float(specs, "k2", -10.0f, 10.0f);
    if (!parsed.barrel && (params.given("k1") || params.given("k2")))
        throw Error("parameters 'k1' and 'k2' apply to the barrel distortion: add barrel=on");
    const std::string blur = params.get_string(specs, "blur");
    if (blur != "off" && blur != "internal_aa")
        throw Error("parameter 'blur': '" + blur + "' is neither off nor internal_aa");
    parsed.blur = blur == "internal_aa";
    return parsed;
}

Camera eye_camera(const Camera& camera, int eye, float ipd) {
    Camera c = camera;
    const float offset = (eye == 0 ? -0.5f : 0.5f) * ipd;
    c.position = camera.position + offset * camera.right;
    return c;
}

int stereo_eye_width(int width) {
    if (width % 2 != 0)
        throw Error("stereo-lp: the width " + std::to_string(width) +
                    " is odd; the two eyes share it equally (give an even --width)");
    return width / 2;
}

std::array<LogPolarMap, 2> stereo_maps(const StereoParams& params, const Scene& scene,
                                       const Camera& camera, int width, int height, int frame) {
    const int eye_width = stereo_eye_width(width);
    return {foveated_map(params.eye, scene, camera, eye_width, height, frame),
            foveated_map(params.eye, scene, camera, eye_width, height, frame)};
}

std::array<PrimaryView, 2> eye_views(const Scene& scene, const Bvh& bvh,
                                     const std::array<Camera, 2>& cameras,
                                     const std::array<Camera, 2>& previous) {
    return {PrimaryView(scene, bvh, cameras[0], previous[0]),
            PrimaryView(scene, bvh, cameras[1], previous[1])};
}

TexelStatus stereo_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points,
                                 const std::array<LogPolarMap, 2>& maps,
                                 const std::array<LpInverseTable, 2>& tables,
                                 const std::array<PrimaryView, 2>& views, int x, int y,
                                 FoveatedTraceStats& stats) {
    const int w = maps[0].width;
    const int eye = x / w, i = x - eye * w;
    const LogPolarMap& map = maps[static_cast<std::size_t>(eye)];
    glm::vec2 p{0.0f};
    const TexelStatus status = lp_texel_status(map, tables[static_cast<std::size_t>(eye)], i, y, p);
    screen_points.at(x, y, 0) = p.x + static_cast<float>(eye * map.screen_width);
    screen_points.at(x, y, 1) = p.y;
    if (status != TexelStatus::traced) {
        ++stats.texels_off_screen;  // no gaze buffer in stereo: never inside it
        return status;
    }
    ++stats.texels_traced;
    buffer.valid.at(x, y) = 1.0f;
    raycast_sample(buffer.gbuffer, x, y, p, map.screen_width, map.screen_height,
                   views[static_cast<std::size_t>(eye)], stats.rays);
    return status;
}

MaskedGBuffer trace_stereo_gbuffer(const std::array<LogPolarMap, 2>& maps,
                                   const std::array<PrimaryView, 2>& views, Image& screen_points,
                                   FoveatedTraceStats& stats, Offset2 jitter) {
    const int w = maps[0].width, h = maps[0].height;
    MaskedGBuffer buffer(2 * w, h);
    screen_points = Image(2 * w, h, 2, 0.0f);
    const std::array<LpInverseTable, 2> tables = {lp_inverse_table(maps[0], jitter),
                                                  lp_inverse_table(maps[1], jitter)};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < 2 * w; ++x)
            stereo_gbuffer_texel(buffer, screen_points, maps, tables, views, x, y, stats);
    return buffer;
}

bool stereo_lookup(const StereoParams& params, const std::array<LogPolarMap, 2>& maps, int x, int y,
                   glm::vec2& uv) {
    const int eye_width = maps[0].screen_width, height = maps[0].screen_height;
    const int eye = x / eye_width;
    glm::vec2 c = pixel_centre(x - eye * eye_width, y);
    if (params.barrel) {
        c = barrel_source(c, eye_width, height, params.k1, params.k2);
        if (!on_screen(eye_width, height, c)) return false;
    }
    uv = lp_forward(maps[static_cast<std::size_t>(eye)], c);
    return true;
}

StereoForwardTable stereo_forward_table(const StereoParams& params,
                                        const std::array<LogPolarMap, 2>& maps) {
    StereoForwardTable table;
    table.maps = maps;
    table.barrel = params.barrel;
    table.k1 = params.k1;
    table.k2 = params.k2;
    const int width = 2 * maps[0].screen_width, height = maps[0].screen_height;
    table.uv.assign(static_cast<std::size_t>(width) * height, glm::vec2(0.0f));
    table.in_lens.assign(static_cast<std::size_t>(width) * height, 0);
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const std::size_t k = static_cast<std::size_t>(y) * width + x;
            table.in_lens[k] = stereo_lookup(params, maps, x, y, table.uv[k]) ? 1 : 0;
        }
    return table;
}

void resolve_stereo_pixel(const StereoParams& params, const std::array<LogPolarMap, 2>& maps,
                          const std::array<Image, 2>& colors, const std::array<Image, 2>& valid,
                          Image& out, int x, int y, StereoResolveStats& stats,
                          const StereoForwardTable* table) {
    const auto e = static_cast<std::size_t>(x / maps[0].screen_width);
    float* pixel = &out.at(x, y, 0);
    glm::vec2 uv{0.0f};
    bool in_lens = false;
    if (table) {
        const std::size_t k = static_cast<std::size_t>(y) * out.width + x;
        uv = table->uv[k];
        in_lens = table->in_lens[k] != 0;
    } else {
        in_lens = stereo_lookup(params, maps, x, y, uv);
    }
    if (!in_lens) {
        ++stats.pixels_outside_lens;
        for (int k = 0; k < out.channels; ++k) pixel[k] = 0.0f;
        return;
    }
    ++stats.resolve.pixels_from_buffer;
    if (!sample_lp_bilinear(colors[e], valid[e], uv, pixel)) ++stats.resolve.pixels_untraced_taps;
}

Image eye_half(const Image& side_by_side, int eye) {
    const int w = side_by_side.width / 2, h = side_by_side.height;
    Image half(w, h, side_by_side.channels, 0.0f);
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i)
            for (int k = 0; k < side_by_side.channels; ++k)
                half.at(i, j, k) = side_by_side.at(eye * w + i, j, k);
    return half;
}

Image stereo_internal_aa(const Image& color, const Image& valid) {
    FOVREF_CHECK(color.width % 2 == 0 && valid.width == color.width && valid.height == color.height,
                 "a side-by-side buffer of an odd width, or a mask of another size");
    const int w = color.width / 2;
    Image out(color.width, color.height, color.channels, 0.0f);
    for (int eye = 0; eye < 2; ++eye) {
        const Image half = internal_aa(eye_half(color, eye), eye_half(valid, eye));
        for (int j = 0; j < color.height; ++j)
            for (int i = 0; i < w; ++i)
                for (int k = 0; k < color.channels; ++k)
                    out.at(eye * w + i, j, k) = half.at(i, j, k);
    }
    return out;
}

Image resolve_stereo(const StereoParams& params, const std::array<LogPolarMap, 2>& maps,
                     const Image& color, const Image& valid, StereoResolveStats& stats,
                     const StereoForwardTable* table) {
    if (table) FOVREF_CHECK(table->made_for(params, maps), "a forward table made for other maps");
    const int w = maps[0].width, h = maps[0].height;
    FOVREF_CHECK_EQ(color.width, 2 * w, "side-by-side buffer width");
    FOVREF_CHECK_EQ(color.height, h, "side-by-side buffer height");
    const std::array<Image, 2> colors = {eye_half(color, 0), eye_half(color, 1)};
    const std::array<Image, 2> masks = {eye_half(valid, 0), eye_half(valid, 1)};
    Image out(2 * maps[0].screen_width, maps[0].screen_height, color.channels, 0.0f);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            resolve_stereo_pixel(params, maps, colors, masks, out, x, y, stats, table);
    return out;
}

std::vector<glm::ivec2> stereo_pixel_taps(const StereoParams& params,
                                          const std::array<LogPolarMap, 2>& maps, int x, int y) {
    glm::vec2 uv{0.0f};
    if (!stereo_lookup(params, maps, x, y, uv)) return {};
    const int eye = x / maps[0].screen_width;
    const LogPolarMap& map = maps[static_cast<std::size_t>(eye)];
    const BilinearLookup l = lp_bilinear_taps(Image(map.width, map.height, 1, 1.0f), uv);
    std::vector<glm::ivec2> taps;
    for (const glm::ivec2& tap : {glm::ivec2(l.i0, l.j0), glm::ivec2(l.i1, l.j0),
                                  glm::ivec2(l.i0, l.j1), glm::ivec2(l.i1, l.j1)}) {
        const glm::ivec2 texel{eye * map.width + tap.x, tap.y};
        if (std::find(taps.begin(), taps.end(), texel) == taps.end()) taps.push_back(texel);
    }
    return taps;
}

}  // namespace fovref
