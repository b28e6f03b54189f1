// One BMFR frame: the phases in order, and the history handed to the next frame.
#include "ref/bmfr/bmfr.h"

namespace fovref {

BmfrFrame bmfr_denoise_frame(const BmfrParams& params, const Image& radiance, const Image& albedo,
                             const Image& emission, const Image& normal,
                             const Image& world_position, const ViewProjection& camera, int frame,
                             BmfrHistory& history, BmfrStats& stats, const BmfrSpace& space_in) {
    BmfrSpace space = space_in;
    space.previous_valid = history.valid_texels.empty() ? nullptr : &history.valid_texels;
    space.previous_map = history.map;
    BmfrFrame f;
    f.illumination = bmfr_demodulate(params, radiance, albedo, emission, stats);
    f.accumulation = bmfr_accumulate_noisy(params, f.illumination, world_position, normal, history,
                                           stats, space);
    f.fit =
        bmfr_fit(params, f.accumulation.accumulated, world_position, normal, frame, stats, space);
    f.fitted = bmfr_weighted_sum(f.fit, world_position, normal, stats, space.valid);
    const BmfrAccumulation& a = f.accumulation;
    f.filtered = bmfr_accumulate_filtered(params, f.fitted, a.spp, a.accept, a.previous_pixel,
                                          history.accumulated_filtered, space);
    f.display = bmfr_remodulate(params, f.filtered, albedo, emission);
    f.taa = bmfr_taa(params, f.display, a.previous_pixel, history.taa, stats, space);
    f.output = bmfr_linearize(f.taa);
    history = bmfr_next_history(f, world_position, normal, camera, space);
    return f;
}

BmfrHistory bmfr_next_history(const BmfrFrame& f, const Image& world_position, const Image& normal,
                              const ViewProjection& camera, const BmfrSpace& space) {
    BmfrHistory h;
    h.valid = true;
    h.map = space.map;
    if (space.valid) h.valid_texels = *space.valid;
    h.view_projection = camera;
    h.world_position = world_position;
    h.normal = normal;
    h.accumulated_noisy = f.accumulation.accumulated;
    h.spp = f.accumulation.spp;
    h.accumulated_filtered = f.filtered;
    h.taa = f.taa;
    return h;
}

}  // namespace fovref
