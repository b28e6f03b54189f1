#include "ref/log_polar/map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "ref/core/dmath.h"
#include "ref/core/error.h"
#include "ref/core/limits.h"

namespace fovref {

namespace {

constexpr float two_pi = 6.28318530717958647692f;

std::string number_text(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.9g", value);
    return text;
}

}  // namespace

BufferSize log_polar_buffer_size(const LogPolarParams& params, int screen_width,
                                 int screen_height) {
    if (!std::isfinite(params.sigma) || params.sigma <= 0.0f)
        throw Error("parameter 'sigma': " + number_text(params.sigma) +
                    " is not a positive number");
    if (!std::isfinite(params.lp_aspect) || params.lp_aspect < 0.0f)
        throw Error("parameter 'lp_aspect': " + number_text(params.lp_aspect) +
                    " is neither 0 (off) nor a positive number");
    const double sigma = params.sigma, aspect = params.lp_aspect;
    const double screen_w = screen_width, screen_h = screen_height;
    double w = 0.0, h = 0.0;
    if (aspect > 0.0) {
        h = std::round(std::sqrt(screen_w * screen_h / aspect) / sigma);
        w = std::round(h * aspect);
    } else {
        w = std::round(screen_w / sigma);
        h = std::round(screen_h / sigma);
    }
    w = std::max(w, 1.0);
    h = std::max(h, 1.0);
    // Both below 2^31 before the product is checked against the image-size limit.
    const double limit = static_cast<double>(input_limits().max_image_pixels);
    if (w > limit || h > limit || w * h > limit)
        throw Error("parameters 'sigma' = " + number_text(sigma) +
                    ", 'lp_aspect' = " + number_text(aspect) + ": the log-polar buffer would be " +
                    number_text(w) + "x" + number_text(h) + " texels, more than the limit of " +
                    number_text(limit) + " (FOVREF_MAX_IMAGE_PIXELS; see docs/limits.md)");
    return {static_cast<int>(w), static_cast<int>(h)};
}

LogPolarMap make_log_polar_map(const LogPolarParams& params, int screen_width, int screen_height,
                               glm::vec2 gaze, float display_distance_px) {
    if (!std::isfinite(gaze.x) || !std::isfinite(gaze.y) || std::fabs(gaze.x) > 1e7f ||
        std::fabs(gaze.y) > 1e7f)
        throw Error("gaze (" + number_text(gaze.x) + ", " + number_text(gaze.y) +
                    "): not a finite point within 1e7 pixels of the screen");
    if (!std::isfinite(params.gaze_angle) || params.gaze_angle < 0.0f || params.gaze_angle > 1.5f)
        throw Error("parameter 'gaze_angle': " + number_text(params.gaze_angle) +
                    " rad is outside [0, 1.5] (a_G, the gaze buffer's angular radius)");
    if (params.gaze_angle > 0.0f && !(display_distance_px > 0.0f))
        throw Error("parameter 'gaze_angle': the display model gives no viewing distance (" +
                    number_text(display_distance_px) + " px) to turn a_G into pixels");
    const BufferSize size = log_polar_buffer_size(params, screen_width, screen_height);
    LogPolarMap map;
    map.screen_width = screen_width;
    map.screen_height = screen_height;
    map.gaze = gaze;
    map.width = size.width;
    map.height = size.height;
    map.kernel = params.kernel;

    // R: the screen diagonal, or the farthest corner from the gaze point.
    const float w = static_cast<float>(screen_width), h = static_cast<float>(screen_height);
    if (params.radius == RadiusMode::diagonal) {
        map.radius_max = std::sqrt(w * w + h * h);
    } else {
        const glm::vec2 corners[4] = {{0.0f, 0.0f}, {w, 0.0f}, {0.0f, h}, {w, h}};
        for (const glm::vec2& c : corners)
            map.radius_max = std::max(map.radius_max, gaze_distance(gaze, c));
    }
    map.log_radius_max = dm::log(1.0f + map.radius_max);

    // The gaze buffer (SPEC §5.2): r_G = d_px tan(a_G), G = K(l(r_G) / L), at most 1.
    if (params.gaze_angle > 0.0f) {
        map.gaze_radius = display_distance_px * dm::tan(params.gaze_angle);
        map.composite = std::min(
            1.0f, kernel_forward(map.kernel, dm::log(1.0f + map.gaze_radius) / map.log_radius_max));
    }

    // Lund §3.3.5: with R the diagonal, a centred gaze's farthest corner lies at R / 2, so only
    // the share f = (K(l(R / 2) / L) - G) / (1 - G) of the columns is on screen; the buffer is
    // widened to ceil(w / f) columns
    if (params.widen && params.radius == RadiusMode::diagonal && map.composite < 1.0f) {
        const float rho = dm::log(1.0f + 0.5f * map.radius_max) / map.log_radius_max;
        const float used = (kernel_forward(map.kernel, rho) - map.composite) /
                           std::max(1.0f - map.composite, 0x1p-24f);
        if (used > 0.0f && used < 1.0f) {
            const double wide = std::ceil(static_cast<double>(size.width) / used);
            check_limit("parameter 'lp_widen': the widened log-polar buffer",
                        static_cast<std::uint64_t>(wide) * static_cast<std::uint64_t>(size.height),
                        input_limits().max_image_pixels, "texels", "FOVREF_MAX_IMAGE_PIXELS");
            map.width = static_cast<int>(wide);
        }
    }
    return map;
}

glm::vec2 lp_forward(const LogPolarMap& map, glm::vec2 p) {
    const float dx = p.x - map.gaze.x, dy = p.y - map.gaze.y;
    const float r = std::sqrt(dx * dx + dy * dy);
    const float rho = dm::log(1.0f + r) / map.log_radius_max;
    const float k = kernel_forward(map.kernel, rho);
    const float u = static_cast<float>(map.width) * (k - map.composite) /
                    std::max(1.0f - map.composite, 0x1p-24f);
    float theta = dm::atan2(dy, dx);
    if (theta < 0.0f) theta += two_pi;
    const float h = static_cast<float>(map.height);
    float v = h * theta / two_pi;
    if (v >= h) v -= h;
    return {u, v};
}

namespace {

float inverse_radius(const LogPolarMap& map, float u) {
    const float t = map.composite + (1.0f - map.composite) * (u / static_cast<float>(map.width));
    const float rho = kernel_inverse(map.kernel, t);
    return dm::exp(map.log_radius_max * rho) - 1.0f;
}

float inverse_angle(const LogPolarMap& map, float v) {
    return two_pi * v / static_cast<float>(map.height);
}

}  // namespace

glm::vec2 lp_inverse(const LogPolarMap& map, glm::vec2 uv) {
    const float r = inverse_radius(map, uv.x);
    const float theta = inverse_angle(map, uv.y);
    return {map.gaze.x + r * dm::cos(theta), map.gaze.y + r * dm::sin(theta)};
}

LpInverseTable lp_inverse_table(const LogPolarMap& map, Offset2 jitter, glm::vec2 screen_offset) {
    LpInverseTable table;
    table.screen_offset = screen_offset;
    table.radius.resize(static_cast<std::size_t>(map.width));
    table.cos_theta.resize(static_cast<std::size_t>(map.height));
    table.sin_theta.resize(static_cast<std::size_t>(map.height));
    for (int i = 0; i < map.width; ++i)
        table.radius[static_cast<std::size_t>(i)] =
            inverse_radius(map, static_cast<float>(i) + jitter.x);
    for (int j = 0; j < map.height; ++j) {
        const float theta = inverse_angle(map, static_cast<float>(j) + jitter.y);
        table.cos_theta[static_cast<std::size_t>(j)] = dm::cos(theta);
        table.sin_theta[static_cast<std::size_t>(j)] = dm::sin(theta);
    }
    return table;
}

TexelsPerPixel texels_per_pixel(const LogPolarMap& map, float r) {
    const float rho = dm::log(1.0f + r) / map.log_radius_max;
    TexelsPerPixel s;
    s.radial = static_cast<float>(map.width) * kernel_derivative(map.kernel, rho) /
               ((1.0f + r) * map.log_radius_max * std::max(1.0f - map.composite, 0x1p-24f));
    s.angular = static_cast<float>(map.height) / (two_pi * r);
    return s;
}

TexelStatus lp_texel_status(const LogPolarMap& map, const LpInverseTable& table, int i, int j,
                            glm::vec2& screen_point) {
    const float r = table.radius[static_cast<std::size_t>(i)];
    screen_point = {map.gaze.x + r * table.cos_theta[static_cast<std::size_t>(j)],
                    map.gaze.y + r * table.sin_theta[static_cast<std::size_t>(j)]};
    if (table.screen_offset != glm::vec2(0.0f)) screen_point += table.screen_offset;
    if (!on_screen(map.screen_width, map.screen_height, screen_point))
        return TexelStatus::off_screen;
    if (inside_gaze_circle(map, screen_point)) return TexelStatus::inside_gaze;
    return TexelStatus::traced;
}

}  // namespace fovref
