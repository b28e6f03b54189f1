// Stereo foveated ray casting in one pass (Gupta 2019 §2-3; SPEC §1 "Stereo", §6 "Barrel
// distortion", §12 `stereo-lp`). docs/foveation.md, "Stereo".
//
// The W x H screen holds two eyes side by side, each a W/2 x H sub-screen (W even) with its own
// camera (the frame's camera moved by -IPD/2 (eye 0, left) or +IPD/2 (eye 1, right) along its
// right axis, same orientation and field of view), its own gaze (in eye coordinates, by default
// the eye's centre) and its own log-polar map on the sub-screen. Both eyes' buffers are stored side
// by side in one 2w x h buffer: eye e's texel (i, j) is column e w + i.
//
//   trace_stereo_gbuffer:  for each texel (x, y) of the 2w x h buffer, row by row:
//                            stereo_gbuffer_texel(x, y): eye e = x / w, i = x - e w; as
//                            lp_gbuffer_texel with eye e's map and camera on the W/2 x H
//                            sub-screen; lp_screen_point holds the point on the full screen
//                            (x + e W/2)
//   shade_stereo:          (ref/trace/shade_basic.h) the basic shading of every texel with its
//                          eye's camera; rand()'s pixel index is y 2w + x
//   resolve_stereo:        for each screen pixel (x, y), row by row: eye e = x / (W/2); the
//                          eye-local centre c; with barrel distortion its source s (below),
//                          black when s leaves the eye's image; then eye e's bilinear (or mip)
//                          lookup at s in its half of the buffer
//   barrel (Gupta §3):     barrel_source (ref/filters/barrel.h)
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "ref/filters/barrel.h"
#include "ref/log_polar/params.h"
#include "ref/log_polar/resolve.h"
#include "ref/log_polar/trace.h"
#include "ref/stage/params.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

struct StereoParams {
    FoveatedParams eye;   ///< each eye's map (sigma, K, lp_aspect, L) and gaze; bilinear pass 2
    float ipd = 0.064f;   ///< interpupillary distance in scene units
    bool barrel = false;  ///< Gupta's barrel distortion in pass 2
    float k1 = 0.22f, k2 = 0.24f;
    /// Gupta's pre-resolve blur (`blur=internal_aa`; Gupta §2, citing Meng's "Gaussian blur on
    /// the right side of the log-polar buffer"): Meng's internal AA on each eye's buffer before
    /// pass 2. Off by default: Gupta's shader does not blur ("I will add the blurring feature
    /// later").
    bool blur = false;
};

/// stereo-lp's preset (SPEC §12): sigma = sqrt 2 per eye (both buffers together W H / 2 texels),
/// K = x, lp_aspect off, L = corners (Meng's map, which Gupta builds on: choice).
const FoveationPreset& stereo_preset();
std::vector<ParamSpec> stereo_param_specs();
/// Throws fovref::Error naming the parameter.
StereoParams parse_stereo_params(const Params& params);

/// The camera of eye 0 (left) or 1 (right).
Camera eye_camera(const Camera& camera, int eye, float ipd);

/// The width of one eye, W / 2. Throws fovref::Error for an odd W.
int stereo_eye_width(int width);

/// Both eyes' maps for a W x H screen (W even) in frame `frame`.
std::array<LogPolarMap, 2> stereo_maps(const StereoParams& params, const Scene& scene,
                                       const Camera& camera, int width, int height, int frame);

/// The two eyes' primary views (their cameras and previous cameras, which must outlive them).
std::array<PrimaryView, 2> eye_views(const Scene& scene, const Bvh& bvh,
                                     const std::array<Camera, 2>& cameras,
                                     const std::array<Camera, 2>& previous);

/// Per-texel work of trace_stereo_gbuffer.
TexelStatus stereo_gbuffer_texel(MaskedGBuffer& buffer, Image& screen_points,
                                 const std::array<LogPolarMap, 2>& maps,
                                 const std::array<LpInverseTable, 2>& tables,
                                 const std::array<PrimaryView, 2>& views, int x, int y,
                                 FoveatedTraceStats& stats);

/// Both eyes' G-buffers, side by side (2w x h), and the texels' full-screen points.
/// `jitter` (TAA): each eye's texels launch at (i + o_x, j + o_y), before the inverse map.
MaskedGBuffer trace_stereo_gbuffer(const std::array<LogPolarMap, 2>& maps,
                                   const std::array<PrimaryView, 2>& views, Image& screen_points,
                                   FoveatedTraceStats& stats, Offset2 jitter = {});

/// Pass 2 counters, plus the pixels whose barrel source left the eye's image.
struct StereoResolveStats {
    ResolveStats resolve;
    std::int64_t pixels_outside_lens = 0;
};

/// Where screen pixel (x, y) looks in its eye's half: the buffer coordinates of its (barrel-
/// distorted) eye-local centre. False when the barrel source leaves the eye's image.
bool stereo_lookup(const StereoParams& params, const std::array<LogPolarMap, 2>& maps, int x, int y,
                   glm::vec2& uv);

/// stereo_lookup of every pixel, kept while the maps and the distortion stay the same (as the
/// mono modes' ForwardTable): the same bits.
struct StereoForwardTable {
    std::array<LogPolarMap, 2> maps;
    bool barrel = false;
    float k1 = 0.0f, k2 = 0.0f;
    std::vector<glm::vec2> uv;          ///< W x H, row-major
    std::vector<std::uint8_t> in_lens;  ///< W x H: 0 where the barrel source leaves the eye
    bool made_for(const StereoParams& params, const std::array<LogPolarMap, 2>& m) const {
        return maps == m && barrel == params.barrel && k1 == params.k1 && k2 == params.k2;
    }
};
StereoForwardTable stereo_forward_table(const StereoParams& params,
                                        const std::array<LogPolarMap, 2>& maps);

/// Per-pixel work of resolve_stereo (`table`, when given, replaces stereo_lookup).
void resolve_stereo_pixel(const StereoParams& params, const std::array<LogPolarMap, 2>& maps,
                          const std::array<Image, 2>& colors, const std::array<Image, 2>& valid,
                          Image& out, int x, int y, StereoResolveStats& stats,
                          const StereoForwardTable* table = nullptr);

/// Eye e's half of a side-by-side 2w x h buffer (columns e w .. e w + w - 1), as a w x h buffer
/// of its own: pass 2 looks up each eye in its half (the lookup wraps and clamps within it).
Image eye_half(const Image& side_by_side, int eye);

/// Gupta's pre-resolve blur: Meng's internal AA (ref/filters/internal_aa.h) on each eye's half of
/// the side-by-side buffer on its own (its columns clamp and its rows wrap within the half), the
/// result side by side again; the buffer's size and channels.
Image stereo_internal_aa(const Image& color, const Image& valid);

/// Pass 2 of both eyes: a W x H image from the side-by-side buffer and its mask.
Image resolve_stereo(const StereoParams& params, const std::array<LogPolarMap, 2>& maps,
                     const Image& color, const Image& valid, StereoResolveStats& stats,
                     const StereoForwardTable* table = nullptr);

/// The texels of the side-by-side buffer (eye e's texel (i, j) is column e w + i) that pass 2
/// reads for screen pixel (x, y): the four taps of its eye's bilinear lookup, each once; none when
/// the barrel source leaves the eye's image.
std::vector<glm::ivec2> stereo_pixel_taps(const StereoParams& params,
                                          const std::array<LogPolarMap, 2>& maps, int x, int y);

}  // namespace fovref
