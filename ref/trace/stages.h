// The ray tracers' passes as stages (Lund §3.1-3.2, Koskela §2.4; SPEC §3, §8; docs/trace.md,
// docs/pathtrace.md). Each stage is declared by a *_stage_def function (its ports, its state)
// and runs as the plain function named beside it, so `break fovref::shade_stage` works:
//
//   raycast            (nothing)                    -> gbuffer_*: one ray per pixel centre (or
//                                                      at the frame's TAA jitter)
//   shade              <prefix>world_position ... primitive_id -> the output: the basic ray
//                      tracer's shading (shade_basic), of the screen, of a buffer, of a window of
//                      the screen (the gaze buffer) or of both eyes' buffers (stereo)
//   supersample        (nothing)                    -> final: 16 Halton rays per pixel, shaded,
//                                                      box-filtered (ground truth)
//   pathtrace          <prefix>world_position ... [, mask] -> radiance [, emission]: 1-spp paths
//   pathtrace_reference (nothing)                   -> final, standard_error, the running sums
//
// The stages that trace hold the render's one BvhCache (ref/bvh/bvh_cache.h).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>

#include "ref/bvh/bvh_cache.h"
#include "ref/core/halton.h"
#include "ref/raster/gbuffer.h"
#include "ref/stage/pipeline.h"
#include "ref/trace/pathtrace.h"
#include "ref/trace/pathtrace_reference.h"
#include "ref/trace/raycast_gbuffer.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

/// The launch offset of a frame's primary rays in their pixel or texel (TAA's Halton jitter,
/// SPEC §7); empty: the centre.
using FrameJitter = std::function<Offset2(const FrameContext&)>;

/// The primary visibility by ray casting: raycast_gbuffer (ref/trace/raycast_gbuffer.h) of the
/// frame's camera, jittered by `jitter`; stage "primary_visibility", outputs gbuffer_*.
StageDef raycast_stage_def(std::shared_ptr<BvhCache> bvh, FrameJitter jitter = {});
void raycast_stage(FrameContext& context);

/// What the shading stage shades besides a plain screen G-buffer.
struct ShadeView {
    /// Where the G-buffer lies on the screen (the gaze buffer's window), for the random numbers'
    /// pixel index; empty: the buffer is its own screen (or a foveation buffer's texels).
    std::function<ScreenWindow(const FrameContext&)> window;
    /// Stereo: the two eyes' cameras; the left half of the buffer is shaded with the first, the
    /// right half with the second (shade_stereo); empty: the frame's camera.
    std::function<std::array<Camera, 2>(const FrameContext&)> eye_cameras;
};

/// The basic ray tracer's shading (shade_basic, Lambert + one shadow ray per light) of the
/// G-buffer `prefix`* (its shading_ports), written to `output`: the one shading stage of every
/// mode that shades as basic does (basic, the log-polar buffers and the gaze buffer, stereo,
/// visual-polar-basic). No lights: no shadow rays and no BVH.
StageDef shade_stage_def(std::string name, const std::string& prefix, std::string output,
                         std::shared_ptr<BvhCache> bvh, ShadeView view = {});
void shade_stage(FrameContext& context);

/// ground-truth's supersampling (render_ground_truth, ref/trace/ground_truth.h) -> final.
StageDef supersample_stage_def(std::shared_ptr<BvhCache> bvh);
void supersample_stage(FrameContext& context);

/// The path tracer (pathtrace, ref/trace/pathtrace.h) over a G-buffer, tracing where `mask` is
/// not 0 (all pixels when empty).
struct PathTraceStage {
    std::string name = "pathtrace";
    std::string gbuffer = "gbuffer_";  ///< the G-buffer's prefix
    std::string mask;                  ///< the sample mask's buffer, or "" for every pixel
    std::string radiance = "final";    ///< the output
    std::string emission;  ///< the directly seen emission's output (BMFR keeps it out of the
                           ///< fit), or "" for none
    PathTraceParams path;
    std::shared_ptr<BvhCache> bvh;
    /// Also count why paths ended (paths_ended_*): the pathtrace mode's counters; the sparse
    /// modes count the paths only.
    bool path_end_counters = false;
};
StageDef pathtrace_stage_def(PathTraceStage config);
void pathtrace_stage(FrameContext& context);

/// pathtrace-reference's stage (pathtrace_reference, ref/trace/pathtrace_reference.h): `spp`
/// samples per pixel, resumable from an earlier run's sums (`fovref render --resume DIR`).
StageDef pathtrace_reference_stage_def(PathTraceParams path, int spp, ReferenceJitter jitter,
                                       std::shared_ptr<BvhCache> bvh);
void pathtrace_reference_stage(FrameContext& context);

/// The frame's primary view: its scene, the render's BVH (built on first use, counted in the
/// frame), this frame's and the previous frame's cameras.
PrimaryView primary_view(FrameContext& context, BvhCache& bvh);

/// The shading pass's inputs: the running stage's G-buffer slots (shading_ports).
ShadeInputs shade_inputs_of(const FrameContext& context);
void add_shading_counters(Counters& counters, const ShadingStats& stats);
/// The stage note of a shading pass: says when no shadow rays were traced.
std::string shadow_note(const Scene& scene);

}  // namespace fovref
