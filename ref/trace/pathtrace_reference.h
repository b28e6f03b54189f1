// The converged path-traced reference (SPEC §8; docs/pathtrace.md, "Converged reference"): the
// estimator of `pathtrace` (ref/trace/pathtrace.h) averaged over N samples per pixel, each
// sample a full frame of jittered primary rays (ray cast instead of rasterized, so that the
// reference averages over the pixel's area) followed by the same paths.
//
//   sample s: jitter of pixel p (index y W + x) = frac(u(s) + r(p)) per axis d, with
//             u(s, d) = rand(0xffffffff, s, d) and the pixel's rotation r(p, d) =
//             rand(0xfffffffe, p, d) (a Cranley-Patterson rotation: each pixel a differently
//             rotated copy of one sequence, so that coverage errors do not repeat along an edge;
//             reference_jitter=shared: u(s) in every pixel, the error correlated along edges);
//             frame-independent: every frame's reference uses the same jitter;
//             the paths' random numbers rand(seed(F, s), pixel, d), seed(F, s) =
//             0x80000000 | (F << 16) ^ s  (never a frame number of a render: frames < 2^31).
//   sum      Neumaier-compensated float sum of the samples in sample order (sum + compensation
//            kept as two buffers), so a run resumed from the written sums gives the same bits as
//            one run;
//   squares  plain float sum of the squared samples (for the variance estimate only).
//   mean = (sum + compensation) / n; standard error per channel
//            sqrt(max(0, squares / n - mean^2) / (n - 1)) (0 for n = 1).
#pragma once

#include <cstdint>
#include <functional>

#include "ref/bvh/bvh.h"
#include "ref/core/halton.h"
#include "ref/image/image.h"
#include "ref/scene/scene.h"
#include "ref/trace/pathtrace.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

/// The running sums of a reference (W x H x 3 each) and the number of samples in them.
struct PathReferenceSums {
    Image sum, compensation, squares;
    int count = 0;
};

/// An empty accumulation for a W x H frame.
PathReferenceSums empty_reference_sums(int width, int height);

/// How the reference jitters its primary rays (above).
enum class ReferenceJitter {
    per_pixel,  ///< the shared sequence rotated per pixel (default)
    shared      ///< the same jitter in every pixel
};

/// The jitter of sample s in pixel `pixel` (y W + x), and the random-number seed of its paths in
/// frame `frame`.
Offset2 reference_jitter(int sample, int pixel, ReferenceJitter mode);
std::uint32_t reference_seed(int frame, int sample);

/// Adds samples sums.count .. total - 1 of frame `frame` to `sums`; `progress` (may be empty)
/// gets the fraction done after each sample.
void pathtrace_reference(const Scene& scene, const Bvh& bvh, const PathTraceParams& params,
                         const Camera& camera, int frame, int total, ReferenceJitter jitter,
                         PathReferenceSums& sums, TraceStats& primary, PathTraceStats& stats,
                         const std::function<void(double)>& progress);

/// The mean image and the per-channel standard error of the mean.
void reference_estimate(const PathReferenceSums& sums, Image& mean, Image& standard_error);

}  // namespace fovref
