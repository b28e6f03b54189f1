// The basic ray tracer's shading pass (Lund §3.1, `shade_direct` stage of mode `basic`): every
// G-buffer pixel shaded with shade_direct (direct_light.h). One pass, one per-pixel function:
//
//   for each pixel (x, y), row by row:   shade_basic_pixel(x, y)
//     gbuffer_surface: read the G-buffer channels (NaN/Inf -> 0, counted: SPEC §0);
//                      background (primitive id < 0) stays black, an id that is not a valid
//                      material index is treated as background (counted)
//     shade_direct(frame, pixel index y W + x, dimension base 0); for a buffer that is a window of
//                  the screen (the gaze buffer), the screen pixel's index (y0 + y) W + x0 + x
#pragma once

#include <array>

#include "ref/bvh/bvh.h"
#include "ref/image/image.h"
#include "ref/raster/gbuffer.h"
#include "ref/scene/camera.h"
#include "ref/scene/scene.h"
#include "ref/scene/surface.h"
#include "ref/trace/direct_light.h"

namespace fovref {

/// The G-buffer channels the shading pass reads (its named input buffers).
struct ShadeInputs {
    const Image& position;
    const Image& shading_normal;
    const Image& geometric_normal;
    const Image& albedo;
    const Image& material_id;
    const Image& primitive_id;
    /// Where the buffer lies on the screen, for the random numbers' pixel index; null: the
    /// buffer is its own screen (the index of pixel (x, y) is y width + x).
    const ScreenWindow* window = nullptr;
};

/// The random numbers' pixel index of buffer pixel (x, y) (SPEC §3): y W + x on the screen.
inline std::uint32_t shade_pixel_index(const ShadeInputs& in, int x, int y) {
    if (!in.window) return static_cast<std::uint32_t>(y * in.position.width + x);
    return static_cast<std::uint32_t>((in.window->y0 + y) * in.window->screen_width +
                                      in.window->x0 + x);
}

/// Pixel (x, y) of the G-buffer as the pass reads it. False for background and for an invalid
/// material id (then `surface` is unspecified); counts non-finite values and invalid ids.
bool gbuffer_surface(const Scene& scene, const ShadeInputs& in, int x, int y, SurfacePoint& surface,
                     ShadingStats& stats);

/// Per-pixel work of the pass: the radiance of pixel (x, y) (black for background). `record`
/// receives shade_direct's light samples (for `fovref probe`).
glm::vec3 shade_basic_pixel(const Scene& scene, const Bvh* bvh, const ShadeInputs& in,
                            const Camera& camera, int frame, int x, int y, ShadingStats& stats,
                            std::vector<LightSampleRecord>* record = nullptr);

/// The pass: an RGB image of the G-buffer's size. `bvh` may be null only without lights.
Image shade_basic(const Scene& scene, const Bvh* bvh, const ShadeInputs& in, const Camera& camera,
                  int frame, ShadingStats& stats);

/// The basic shading of the side-by-side buffer of a stereo frame (Gupta's stereo-lp: both eyes'
/// buffers side by side, eye_buffer_width columns each), each texel with its eye's camera.
Image shade_stereo(const Scene& scene, const Bvh* bvh, const ShadeInputs& inputs,
                   const std::array<Camera, 2>& cameras, int eye_buffer_width, int frame,
                   ShadingStats& stats);

}  // namespace fovref
