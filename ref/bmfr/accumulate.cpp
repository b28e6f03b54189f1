// Demodulation and the two temporal accumulations of BMFR (SPEC §9 items 1, 2 and 9).
#include <algorithm>
#include <cmath>
#include <utility>

#include "ref/bmfr/accumulate_avx.h"
#include "ref/bmfr/bmfr.h"
#include "ref/bmfr/half.h"
#include "ref/core/error.h"

namespace fovref {

namespace {

float finite_or_zero(float v, std::int64_t& nonfinite) {
    if (std::isfinite(v)) return v;
    ++nonfinite;
    return 0.0f;
}

glm::vec3 finite_or_zero(glm::vec3 v, BmfrStats& stats) {
    for (int c = 0; c < 3; ++c) v[c] = finite_or_zero(v[c], stats.nonfinite_inputs);
    return v;
}

glm::vec3 load3(const Image& image, int x, int y) {
    const float* p = &image.data[image.index(x, y)];
    return {p[0], p[1], p[2]};
}

float distance_squared(glm::vec3 a, glm::vec3 b) {
    const glm::vec3 d = a - b;
    return d.x * d.x + d.y * d.y + d.z * d.z;
}

// round half to even (the authors' convert with rte), for the sample count
float round_half_even(float v) {
    const float r = std::floor(v);
    const float d = v - r;
    if (d > 0.5f) return r + 1.0f;
    if (d == 0.5f && std::fmod(r, 2.0f) != 0.0f) return r + 1.0f;
    return r;
}

void check_shape(const Image& image, int width, int height, int channels, const char* name) {
    FOVREF_CHECK(image.width == width && image.height == height && image.channels == channels,
                 std::string("bmfr: buffer '") + name + "' is " + std::to_string(image.width) +
                     "x" + std::to_string(image.height) + "x" + std::to_string(image.channels) +
                     ", expected " + std::to_string(width) + "x" + std::to_string(height) + "x" +
                     std::to_string(channels));
}

bool inside(int x, int y, int width, int height) {
    return x >= 0 && y >= 0 && x < width && y < height;
}

// A bilinear blend of `image` over the taps whose bit is set in `mask`, renormalised; false when
// their weights sum to 0.
bool blend_accepted(const Image& image, const BmfrTaps& taps, unsigned mask, float* out) {
    float total = 0.0f;
    for (int c = 0; c < image.channels; ++c) out[c] = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if ((mask & (1u << k)) == 0) continue;
        // phase I accepts only taps on the image; a corrupted mask or coordinate (a foreign
        // buffer) must not read outside it
        if (taps.x[k] < 0 || taps.y[k] < 0 || taps.x[k] >= image.width || taps.y[k] >= image.height)
            continue;
        const float* p = &image.data[image.index(taps.x[k], taps.y[k])];
        for (int c = 0; c < image.channels; ++c) out[c] += taps.w[k] * p[c];
        total += taps.w[k];
    }
    if (!(total > 0.0f)) return false;
    for (int c = 0; c < image.channels; ++c) out[c] = out[c] / total;
    return true;
}

// Phase I's reprojection of world point p (BmfrSpace): the previous frame's pixel index, or on
// a Visual-Polar buffer (u - 1/2, t) through the previous screen and map; false when behind.
bool reproject(const BmfrParams& params, const BmfrHistory& history, const BmfrSpace& space,
               int width, int height, glm::vec3 p, glm::vec2& q) {
    if (!space.map)
        return bmfr_project(history.view_projection, width, height, p, q, params.pixel_offset,
                            params.project_behind_camera);
    const VisualPolarMap& previous = *history.map;
    glm::vec2 s;
    if (!bmfr_project(history.view_projection, previous.screen_width, previous.screen_height, p, s,
                      glm::vec2(0.5f), params.project_behind_camera))
        return false;
    const glm::vec2 ut = vp_forward_angle(previous, s + glm::vec2(0.5f));
    q = {ut.x - 0.5f, ut.y};
    return std::isfinite(q.x) && std::isfinite(q.y);
}

}  // namespace

ViewProjection view_projection(const Camera& camera, int width, int height) {
    const float tan_half = tan_half_vfov(camera);
    const float sx = tan_half * (static_cast<float>(width) / static_cast<float>(height));
    const auto row = [&](glm::vec3 axis, float scale, float* out) {
        const float offset =
            -(axis.x * camera.position.x + axis.y * camera.position.y + axis.z * camera.position.z);
        out[0] = axis.x / scale;
        out[1] = axis.y / scale;
        out[2] = axis.z / scale;
        out[3] = offset / scale;
    };
    ViewProjection vp;
    row(camera.right, sx, &vp.m[0]);
    row(camera.up, tan_half, &vp.m[4]);
    row(camera.forward, 1.0f, &vp.m[8]);
    row(camera.forward, 1.0f, &vp.m[12]);
    return vp;
}

bool bmfr_project(const ViewProjection& vp, int width, int height, glm::vec3 p, glm::vec2& pixel,
                  glm::vec2 offset, bool behind) {
    const auto& m = vp.m;
    const float cx = m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
    const float cy = m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7];
    const float cw = m[12] * p.x + m[13] * p.y + m[14] * p.z + m[15];
    if (behind ? !(cw != 0.0f) : !(cw > 0.0f)) return false;
    pixel.x = (cx / cw + 1.0f) * 0.5f * static_cast<float>(width) - offset.x;
    pixel.y = (1.0f - cy / cw) * 0.5f * static_cast<float>(height) - offset.y;
    return std::isfinite(pixel.x) && std::isfinite(pixel.y);
}

BmfrTaps bmfr_taps(glm::vec2 q) {
    BmfrTaps t;
    // far off the image all taps are outside anyway; the clamp keeps the int conversion defined
    // (NaN goes far off too)
    q.x = std::isfinite(q.x) ? std::clamp(q.x, -1e6f, 1e6f) : -1e6f;
    q.y = std::isfinite(q.y) ? std::clamp(q.y, -1e6f, 1e6f) : -1e6f;
    const float fx0 = std::floor(q.x), fy0 = std::floor(q.y);
    const float fx = q.x - fx0, fy = q.y - fy0;
    const int x0 = static_cast<int>(fx0), y0 = static_cast<int>(fy0);
    t.x[0] = x0, t.y[0] = y0, t.w[0] = (1.0f - fx) * (1.0f - fy);
    t.x[1] = x0 + 1, t.y[1] = y0, t.w[1] = fx * (1.0f - fy);
    t.x[2] = x0, t.y[2] = y0 + 1, t.w[2] = (1.0f - fx) * fy;
    t.x[3] = x0 + 1, t.y[3] = y0 + 1, t.w[3] = fx * fy;
    return t;
}

BmfrTaps bmfr_vp_taps(const VisualPolarMap& map, glm::vec2 q) {
    BmfrTaps t;
    // t is a fraction of the turn: only its fractional part matters (a foreign value far out
    // must not overflow the row index)
    q.x = std::isfinite(q.x) ? std::clamp(q.x, -1e6f, 1e6f) : -1e6f;
    q.y = std::isfinite(q.y) ? q.y - std::floor(q.y) : 0.0f;
    const float fx0 = std::floor(q.x);
    const float fx = q.x - fx0;
    const int x0 = static_cast<int>(fx0);
    for (int side = 0; side < 2; ++side) {
        const int c = x0 + side;
        const float wx = side == 0 ? 1.0f - fx : fx;
        int y0 = -1, y1 = -1;
        float fy = 0.0f;
        if (c >= 0 && c < map.width) {
            const int rows = vp_column_rows(map, c);
            const float v = q.y * static_cast<float>(rows) - 0.5f;
            const float fv0 = std::floor(v);
            fy = v - fv0;
            y0 = vp_wrap_row(static_cast<int>(fv0), rows);
            y1 = y0 + 1 == rows ? 0 : y0 + 1;
        }
        t.x[side] = c, t.y[side] = y0, t.w[side] = wx * (1.0f - fy);
        t.x[side + 2] = c, t.y[side + 2] = y1, t.w[side + 2] = wx * fy;
    }
    return t;
}

Image bmfr_demodulate(const BmfrParams& params, const Image& radiance, const Image& albedo,
                      const Image& emission, BmfrStats& stats, Image storage) {
    check_shape(albedo, radiance.width, radiance.height, 3, "albedo");
    check_shape(radiance, radiance.width, radiance.height, 3, "radiance");
    const bool separate = params.separate_emission && !emission.empty();
    if (separate) check_shape(emission, radiance.width, radiance.height, 3, "emission");
    FOVREF_CHECK(!(params.demodulated_input && separate),
                 "bmfr: a demodulated input colour cannot keep the emission apart");
    Image out = std::move(storage);  // every value is written below
    keep_or_make(out, radiance.width, radiance.height, 3);
    if (params.demodulated_input) {  // the illumination as given (the authors' input)
        for (std::size_t i = 0; i < out.data.size(); ++i)
            out.data[i] = std::clamp(finite_or_zero(radiance.data[i], stats.nonfinite_inputs),
                                     -half_max, half_max);
        return out;
    }
    for (std::size_t i = 0; i < out.data.size(); ++i) {
        const float a = finite_or_zero(albedo.data[i], stats.nonfinite_inputs);
        float c = finite_or_zero(radiance.data[i], stats.nonfinite_inputs);
        if (separate) c = c - finite_or_zero(emission.data[i], stats.nonfinite_inputs);
        out.data[i] = std::clamp(c / std::max(a, params.albedo_floor), -half_max, half_max);
    }
    return out;
}

namespace {

// The history's buffers must have the frame's size (a resumed render's are checked by name).
void check_history(const BmfrHistory& history, const BmfrSpace& space, int width, int height) {
    check_shape(history.world_position, width, height, 3, "world_position history");
    check_shape(history.normal, width, height, 3, "normal history");
    check_shape(history.accumulated_noisy, width, height, 3, "accumulated_noisy history");
    check_shape(history.spp, width, height, 1, "spp history");
    if (space.map) {
        FOVREF_CHECK(history.map.has_value(), "bmfr: the history has no Visual-Polar map");
        check_shape(history.valid_texels, width, height, 1, "valid history");
    }
}

// Phase I's accept bits (bit k: tap k) for a pixel at world position p with normal n: a tap is
// accepted inside the buffer, on a traced texel (Visual-Polar), within both limits (strict).
// `margin` (channels 0 and 1 of accept_margin): the smallest |L^2 - d^2| / L^2 of each test.
unsigned accepted_taps(const BmfrParams& params, const BmfrHistory& history, const BmfrSpace& space,
                       const BmfrTaps& taps, int width, int height, glm::vec3 p, glm::vec3 n,
                       float margin[2]) {
    unsigned mask = 0;
    const auto closer = [](float& m, float d2, float limit2) {
        m = std::min(m, std::fabs(limit2 - d2) / limit2);
    };
    for (int k = 0; k < 4; ++k) {
        if (!inside(taps.x[k], taps.y[k], width, height)) continue;
        if (space.map && history.valid_texels.at(taps.x[k], taps.y[k]) == 0.0f) continue;
        const float dp = distance_squared(load3(history.world_position, taps.x[k], taps.y[k]), p);
        closer(margin[0], dp, params.position_limit_squared);
        if (!(dp < params.position_limit_squared)) continue;
        const float dn = distance_squared(load3(history.normal, taps.x[k], taps.y[k]), n);
        closer(margin[1], dn, params.normal_limit_squared);
        if (!(dn < params.normal_limit_squared)) continue;
        mask |= 1u << k;
    }
    return mask;
}

// The accepted taps' colours and sample counts blended, the weights renormalised (accumulated in
// tap order); false when no accepted tap has a weight.
bool blend_noisy_history(const BmfrHistory& history, const BmfrTaps& taps, unsigned mask, int width,
                         float h[3], float& h_spp) {
    float total = 0.0f;
    for (int k = 0; k < 4; ++k) {
        if ((mask & (1u << k)) == 0) continue;
        const std::size_t i =
            static_cast<std::size_t>(taps.y[k]) * width + static_cast<std::size_t>(taps.x[k]);
        const float* c_k = &history.accumulated_noisy.data[3 * i];
        h[0] += taps.w[k] * c_k[0];
        h[1] += taps.w[k] * c_k[1];
        h[2] += taps.w[k] * c_k[2];
        h_spp += taps.w[k] * history.spp.data[i];
        total += taps.w[k];
    }
    if (!(total > 0.0f)) return false;
    for (int c = 0; c < 3; ++c) h[c] = h[c] / total;
    h_spp = h_spp / total;
    return true;
}

}  // namespace

void bmfr_accumulate_noisy_pixel(const BmfrParams& params, const Image& illumination,
                                 const Image& world_position, const Image& normal,
                                 const BmfrHistory& history, bool has_previous,
                                 const BmfrSpace& space, BmfrAccumulation& out, int x, int y,
                                 BmfrStats& stats) {
    const int width = illumination.width, height = illumination.height;
    const glm::vec3 c = load3(illumination, x, y);
    // Without history: the texel itself, (x, y) or, Visual-Polar, (x, (y + 1/2) / n_x)
    glm::vec2 q(static_cast<float>(x), static_cast<float>(y));
    if (space.map)
        q.y = (static_cast<float>(y) + 0.5f) / static_cast<float>(vp_column_rows(*space.map, x));
    unsigned mask = 0;
    float h[3] = {0, 0, 0}, h_spp = 0.0f;
    float margin[3] = {bmfr_no_margin, bmfr_no_margin, bmfr_no_margin};
    bool has_history = false;
    const bool data = !space.map || space.valid->at(x, y) != 0.0f;
    if (!data) q = bmfr_behind_camera;
    if (has_previous && data) {
        const glm::vec3 p = finite_or_zero(load3(world_position, x, y), stats);
        const glm::vec3 n = finite_or_zero(load3(normal, x, y), stats);
        if (!reproject(params, history, space, width, height, p, q)) {
            q = bmfr_behind_camera;
            ++stats.history_off_screen;
        } else {
            const BmfrTaps taps = space.map ? bmfr_vp_taps(*history.map, q) : bmfr_taps(q);
            mask = accepted_taps(params, history, space, taps, width, height, p, n, margin);
            if (!space.map)
                margin[2] = std::min({q.x - std::floor(q.x), std::ceil(q.x) - q.x,
                                      q.y - std::floor(q.y), std::ceil(q.y) - q.y});
            has_history = blend_noisy_history(history, taps, mask, width, h, h_spp);
            ++(has_history ? stats.history_accepted : stats.history_rejected);
            if (!has_history) mask = 0;
        }
    }
    float* acc = &out.accumulated.data[out.accumulated.index(x, y)];
    if (has_history) {
        const float alpha = std::max(1.0f / (h_spp + 1.0f), params.noisy_alpha_min);
        for (int ch = 0; ch < 3; ++ch) acc[ch] = alpha * c[ch] + (1.0f - alpha) * h[ch];
        out.spp.at(x, y) = std::min(round_half_even(h_spp) + 1.0f, 255.0f);
    } else {
        for (int ch = 0; ch < 3; ++ch) acc[ch] = c[ch];
        out.spp.at(x, y) = 1.0f;
    }
    out.accept.at(x, y) = static_cast<float>(mask);
    out.previous_pixel.at(x, y, 0) = q.x;
    out.previous_pixel.at(x, y, 1) = q.y;
    if (!out.accept_margin.data.empty())
        for (int ch = 0; ch < 3; ++ch) out.accept_margin.at(x, y, ch) = margin[ch];
}

BmfrAccumulation bmfr_accumulate_noisy(const BmfrParams& params, const Image& illumination,
                                       const Image& world_position, const Image& normal,
                                       const BmfrHistory& history, BmfrStats& stats,
                                       const BmfrSpace& space, bool margins,
                                       BmfrAccumulation storage) {
    const int width = illumination.width, height = illumination.height;
    check_shape(world_position, width, height, 3, "world_position");
    check_shape(normal, width, height, 3, "normal");
    const bool has_previous = history.valid && !history.accumulated_noisy.empty();
    if (has_previous) check_history(history, space, width, height);
    if (space.map) FOVREF_CHECK(space.valid, "bmfr: Visual-Polar space without a valid mask");
    // Every value of the four outputs is written below (each pixel writes all of them)
    BmfrAccumulation out = std::move(storage);
    keep_or_make(out.accumulated, width, height, 3);
    keep_or_make(out.spp, width, height, 1);
    keep_or_make(out.accept, width, height, 1);
    keep_or_make(out.previous_pixel, width, height, 2);
    out.accept_margin = margins ? Image(width, height, 3) : Image();
    // Eight pixels at a time where the AVX path covers the frame (the same bits:
    // accumulate_avx.h); the reference does the rest of each row and every other frame.
    const bool avx = bmfr_accumulate_noisy_avx_applies(has_previous, space, illumination);
    for (int y = 0; y < height; ++y)
        for (int x = avx ? bmfr_accumulate_noisy_row_avx(params, illumination, world_position,
                                                         normal, history, space, out, y, stats)
                         : 0;
             x < width; ++x)
            bmfr_accumulate_noisy_pixel(params, illumination, world_position, normal, history,
                                        has_previous, space, out, x, y, stats);
    return out;
}

Image bmfr_accumulate_filtered(const BmfrParams& params, const Image& fitted, const Image& spp,
                               const Image& accept, const Image& previous_pixel,
                               const Image& history, const BmfrSpace& space, Image storage) {
    const int width = fitted.width, height = fitted.height;
    check_shape(spp, width, height, 1, "spp");
    check_shape(accept, width, height, 1, "accept");
    check_shape(previous_pixel, width, height, 2, "previous_pixel");
    if (!history.empty()) check_shape(history, width, height, 3, "accumulated_filtered history");
    Image out = std::move(storage);  // every pixel is written below
    keep_or_make(out, width, height, 3);
    const bool avx = bmfr_accumulate_filtered_avx_applies(history, fitted);
    for (int y = 0; y < height; ++y)
        for (int x = avx ? bmfr_accumulate_filtered_row_avx(params, fitted, spp, accept,
                                                            previous_pixel, history, space, out, y)
                         : 0;
             x < width; ++x)
            bmfr_accumulate_filtered_pixel(params, fitted, spp, accept, previous_pixel, history,
                                           space, out, x, y);
    return out;
}

void bmfr_accumulate_filtered_pixel(const BmfrParams& params, const Image& fitted, const Image& spp,
                                    const Image& accept, const Image& previous_pixel,
                                    const Image& history, const BmfrSpace& space, Image& out, int x,
                                    int y) {
    // the accepted-tap bits 0 .. 15 (anything else, e.g. from a corrupted buffer: none)
    const float bits = accept.at(x, y);
    const unsigned mask = bits >= 0.0f && bits < 16.0f ? static_cast<unsigned>(bits) : 0u;
    float* o = &out.data[out.index(x, y)];
    const float* c = &fitted.data[fitted.index(x, y)];
    float h[3];
    const glm::vec2 q(previous_pixel.at(x, y, 0), previous_pixel.at(x, y, 1));
    if (!history.empty() && mask != 0 &&
        blend_accepted(history, space.map ? bmfr_vp_taps(space.history_map(), q) : bmfr_taps(q),
                       mask, h)) {
        const float alpha = std::max(1.0f / spp.at(x, y), params.filtered_alpha_min);
        for (int ch = 0; ch < 3; ++ch) o[ch] = alpha * c[ch] + (1.0f - alpha) * h[ch];
    } else {
        for (int ch = 0; ch < 3; ++ch) o[ch] = c[ch];
    }
}

}  // namespace fovref
