// What the ray-tracing modes share (internal to ref/modes): the BVH built on first use, and the
// counters every tracing or shading stage adds to its frame (their names are read by scripts and
// recorded in golden manifests).
#pragma once

#include <optional>
#include <string>

#include "ref/bvh/bvh.h"
#include "ref/raster/rasterizer.h"
#include "ref/stage/frame.h"
#include "ref/stage/pipeline.h"
#include "ref/trace/direct_light.h"
#include "ref/trace/shade_basic.h"

namespace fovref {

/// The scene's BVH, built when a stage first traces a ray and kept for later frames; its build
/// appears in the counters of the frame that needed it.
struct BvhCache {
    std::optional<Bvh> bvh;
    const Bvh& get(const Scene& scene, Counters& counters);
};

/// rays_<kind>, <kind>_nodes_visited, <kind>_triangles_tested, <kind>_hits.
void add_trace_counters(Counters& counters, const std::string& kind, const TraceStats& stats);
void add_raster_counters(Counters& counters, const RasterStats& stats);
void add_shading_counters(Counters& counters, const ShadingStats& stats);

/// The shading pass's inputs: the frame's G-buffer channels named prefix + "world_position", ...
ShadeInputs shade_inputs_of(const FrameContext& context, const std::string& prefix);

/// Buffer `name` of frame F - 1 for a stage that carries state (`what`: "TAA", "BMFR") into the
/// first frame F > 0 rendered, from RenderSettings::state_buffers (`fovref render --resume DIR`).
/// Throws fovref::Error naming --resume when it is missing or not W x H x channels (`size`: a
/// buffer's size other than the screen's, e.g. a Visual-Polar buffer).
const Image& resumed_buffer(const FrameContext& context, const std::string& name, int channels,
                            const std::string& what, std::optional<glm::ivec2> size = std::nullopt);

/// The stage note of a shading pass: says when no shadow rays were traced.
std::string shadow_note(const Scene& scene);

}  // namespace fovref
