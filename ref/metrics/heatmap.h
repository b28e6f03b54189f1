// Error heatmaps (SPEC §10; Lund §4.3.1, Fig. 4.4, 5.6): a per-pixel error map drawn through a
// fixed perceptually uniform colour table (matplotlib's "inferno", black = no error, pale yellow =
// the top of the scale), with a legend (a colour bar with its scale values) and optionally the
// error-range ring boundaries drawn over it.
#pragma once

#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "ref/image/image.h"
#include "ref/metrics/rings.h"

namespace fovref {

struct HeatmapSettings {
    /// Value mapped to the top of the colour table; <= 0 means the largest finite value of the
    /// map (so an all-zero map is all black). Larger values are clamped to the top colour.
    float scale_max = 0.0f;
    bool legend = true;                 ///< colour bar and scale values to the right of the map
    const RingLayout* rings = nullptr;  ///< when set, ring boundaries blended 25% white
};

/// The colour table at t in [0, 1] (linear RGB; the table itself is sRGB-encoded bytes).
glm::vec3 heatmap_colour(float t);

/// A linear RGB image (write_png encodes it) of a 1-channel map: the map is width x height, the
/// legend adds a panel on the right. Non-finite values are drawn in magenta.
Image heatmap(const Image& values, const HeatmapSettings& settings = {});

/// The scale heatmap() uses for these settings: scale_max, or the largest finite value.
float heatmap_scale(const Image& values, const HeatmapSettings& settings);

/// Where two id buffers differ, drawn so that single pixels stay visible when the image is shown
/// scaled down: `background` (an RGB preview of the golden ids) dimmed to grey, and around every
/// mismatched pixel a square ring of radius r = max(3, max(W, H) / 64) pixels and thickness
/// max(1, r / 4), with the pixel itself filled: orange (edge_marker_colour) for edge mismatches
/// (mismatch_map value 1), red (interior_marker_colour) for interior ones (value 2, drawn on top).
inline constexpr glm::vec3 edge_marker_colour{1.0f, 0.55f, 0.0f};
inline constexpr glm::vec3 interior_marker_colour{1.0f, 0.0f, 0.0f};
Image id_mismatch_image(const Image& background, const Image& mismatch_map);

/// Draws a square ring in `colour` around each of `pixels` (and the pixel itself) of `image`,
/// within its first map_width x map_height pixels (a heatmap's legend panel is left alone): radius
/// 1/64 of the map's larger side (at least 3), so that an isolated pixel stays visible after the
/// report's downscaling.
void mark_pixels(Image& image, int map_width, int map_height, const std::vector<glm::ivec2>& pixels,
                 glm::vec3 colour);

/// Draws `text` (digits, '.', '-', '+', 'e', 'x', space) with a 3x5 pixel font scaled by `scale`
/// at (x, y) (top-left), clipped to the image. For legends and plot labels in PNGs.
void draw_text(Image& image, int x, int y, const std::string& text, glm::vec3 colour, int scale);

}  // namespace fovref
