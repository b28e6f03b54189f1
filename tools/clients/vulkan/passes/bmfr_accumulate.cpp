// BMFR's phase I, the accumulation of the noisy illumination (shaders/bmfr_accumulate.comp;
// docs/bmfr.md, "Phase I"), stage-isolated: per frame that has the bmfr_accumulate_noisy stage,
// the golden's bmfr_illumination, gbuffer_world_position and gbuffer_shading_normal in; the
// history is the golden's PREVIOUS frame: its G-buffer position and normal, its
// bmfr_accumulated_noisy and bmfr_spp, and its camera (the manifest's, made into the oracle's
// view-projection on the host, as a renderer would). Out: bmfr_accumulated_noisy, bmfr_spp,
// bmfr_accept, bmfr_previous_pixel and bmfr_accept_margin. Frame 0 has no history. Screen space
// only: a Visual-Polar bundle (vp_valid) is refused.
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "tools/clients/vulkan/pass.h"

namespace fovref_client {
namespace {

// shaders/bmfr_accumulate.comp's push constants (80 bytes: 8 words, then 3 vec4 at offset 32).
struct AccumulatePush {
    std::int32_t width, height, has_history;
    float position_limit_squared, normal_limit_squared, alpha_min, offset_x, offset_y;
    float row_x[4], row_y[4], row_w[4];
};
static_assert(sizeof(AccumulatePush) == 80, "push constants out of step with the shader");

// One row of the view-projection, (axis, -axis . C) / scale with C the camera's position, in
// binary32 in the oracle's order (its view_projection).
void matrix_row(const json& axis_json, const json& position_json, float scale, float row[4]) {
    float axis[3], position[3];
    for (int i = 0; i < 3; ++i) {
        axis[i] = axis_json.at(i).get<float>();
        position[i] = position_json.at(i).get<float>();
    }
    const float offset = -(axis[0] * position[0] + axis[1] * position[1] + axis[2] * position[2]);
    for (int i = 0; i < 3; ++i) row[i] = axis[i] / scale;
    row[3] = offset / scale;
}

// Rows 0, 1 and 3 of frame `frame`'s view-projection on a W x H screen (docs/bmfr.md, "The
// view-projection matrix"): (R, -R.C) / (t W / H), (U, -U.C) / t, (F, -F.C), t = tan(vfov / 2)
// as the manifest records it.
void view_projection(const json& frame, int width, int height, AccumulatePush& push) {
    if (!frame.contains("camera"))
        throw std::runtime_error("bmfr_accumulate: frame " +
                                 std::to_string(frame.at("frame").get<int>()) +
                                 " records no camera: phase I reprojects with it");
    const json& camera = frame.at("camera");
    const float tan_half = camera.at("tan_half_vfov").get<float>();
    const float sx = tan_half * (static_cast<float>(width) / static_cast<float>(height));
    matrix_row(camera.at("right"), camera.at("position"), sx, push.row_x);
    matrix_row(camera.at("up"), camera.at("position"), tan_half, push.row_y);
    matrix_row(camera.at("forward"), camera.at("position"), 1.0f, push.row_w);
}

// Runs phase I on one frame (its history: `previous`, nullptr on frame 0) and writes its five
// buffers.
void accumulate_frame(PassContext& ctx, const json& frame, const json* previous,
                      AccumulatePush push) {
    Image illumination = ctx.read(frame, "bmfr_illumination");
    Image world = ctx.read(frame, "gbuffer_world_position");
    Image normal = ctx.read(frame, "gbuffer_shading_normal");
    const int width = illumination.width, height = illumination.height;
    for (const Image* image : {&world, &normal})
        if (image->width != width || image->height != height || image->channels != 3)
            throw std::runtime_error(
                "bmfr_accumulate: the G-buffer is not the illumination's size");
    // Frame 0 binds 1-pixel placeholders (the shader reads no history)
    const Image none3{1, 1, 3, {0, 0, 0}};
    Image previous_world = none3, previous_normal = none3, previous_accumulated = none3;
    Image previous_spp{1, 1, 1, {0}};
    push.width = width;
    push.height = height;
    push.has_history = previous ? 1 : 0;
    if (previous) {
        previous_world = ctx.read(*previous, "gbuffer_world_position");
        previous_normal = ctx.read(*previous, "gbuffer_shading_normal");
        previous_accumulated = ctx.read(*previous, "bmfr_accumulated_noisy");
        previous_spp = ctx.read(*previous, "bmfr_spp");
        view_projection(*previous, width, height, push);
        for (const Image* image : {&previous_world, &previous_normal, &previous_accumulated})
            if (image->width != width || image->height != height || image->channels != 3 ||
                previous_spp.width != width || previous_spp.height != height)
                throw std::runtime_error(
                    "bmfr_accumulate: the previous frame's buffers are not the frame's size");
    }
    const std::size_t pixels = static_cast<std::size_t>(width) * height;
    Image accumulated{width, height, 3, std::vector<float>(3 * pixels)};
    Image spp{width, height, 1, std::vector<float>(pixels)};
    Image accept{width, height, 1, std::vector<float>(pixels)};
    Image previous_pixel{width, height, 2, std::vector<float>(2 * pixels)};
    Image margin{width, height, 3, std::vector<float>(3 * pixels)};
    ctx.dispatch("bmfr_accumulate",
                 {host(illumination.data), host(world.data), host(normal.data),
                  host(previous_world.data), host(previous_normal.data),
                  host(previous_accumulated.data), host(previous_spp.data), host(accumulated.data),
                  host(spp.data), host(accept.data), host(previous_pixel.data), host(margin.data)},
                 &push, sizeof push, groups(width, 8), groups(height, 8));
    const int index = frame.at("frame").get<int>();
    ctx.write(index, "bmfr_accumulated_noisy", accumulated);
    ctx.write(index, "bmfr_spp", spp);
    ctx.write(index, "bmfr_accept", accept);
    ctx.write(index, "bmfr_previous_pixel", previous_pixel);
    ctx.write(index, "bmfr_accept_margin", margin);
}

int run(PassContext& ctx) {
    AccumulatePush push{};
    push.position_limit_squared = ctx.float_param("bmfr_position_limit_squared", "0.01");
    push.normal_limit_squared = ctx.float_param("bmfr_normal_limit_squared", "0.25");
    push.alpha_min = 0.2f;                 // the authors' noisy alpha minimum (no parameter)
    push.offset_x = push.offset_y = 0.5f;  // the pixel centres (a render's samples)
    ctx.notes["precise"] =
        "the view-projection's rows, the pixel index, |P' - P|^2, |n' - n|^2, the tap weights and "
        "the blend (the oracle's binary32 order, no contraction)";
    return ctx.each_frame(
        "bmfr_accumulate_noisy",
        [&](const json& frame, const std::string&) {
            if (PassContext::has(frame, "vp_valid"))
                throw std::runtime_error("Visual-Polar BMFR is not ported");
            const json* previous = ctx.previous_frame(frame);
            accumulate_frame(ctx, frame, previous, push);
        },
        "the bundle has no bmfr_accumulate_noisy stage (bmfr_accumulated_noisy)");
}

const bool registered = register_pass(
    {"bmfr_accumulate",
     "BMFR's phase I: bmfr_illumination, the G-buffer and the previous frame's -> "
     "bmfr_accumulated_noisy, bmfr_spp, bmfr_accept, bmfr_previous_pixel, bmfr_accept_margin",
     "the reprojected pixel without the -1/2 of the pixel centre", run});

}  // namespace
}  // namespace fovref_client
