#include "ref/modes/mode_common.h"

#include "ref/core/error.h"

namespace fovref {

const Bvh& BvhCache::get(const Scene& scene, Counters& counters) {
    if (!bvh) {
        bvh = build_bvh(scene.positions);
        counters.add("bvh_built_nodes", bvh->stats.nodes);
        counters.add("bvh_built_leaves", bvh->stats.leaves);
    }
    return *bvh;
}

void add_trace_counters(Counters& counters, const std::string& kind, const TraceStats& stats) {
    counters.add("rays_" + kind, stats.rays);
    counters.add(kind + "_nodes_visited", stats.nodes_visited);
    counters.add(kind + "_triangles_tested", stats.triangles_tested);
    counters.add(kind + "_hits", stats.hits);
}

void add_raster_counters(Counters& counters, const RasterStats& stats) {
    counters.add("raster_triangles_rasterized", stats.triangles_rasterized);
    counters.add("raster_fragments_written", stats.fragments_written);
    if (stats.fragments_without_plane_hit > 0)
        counters.add("raster_fragments_without_plane_hit", stats.fragments_without_plane_hit);
}

void add_shading_counters(Counters& counters, const ShadingStats& stats) {
    counters.add("pixels_shaded", stats.shaded);
    counters.add("texture_fetches", stats.texture_fetches);
    counters.add("light_samples_facing_away", stats.lights_facing_away);
    counters.add("light_samples_degenerate", stats.light_samples_degenerate);
    counters.add("nonfinite_inputs_replaced", stats.nonfinite_inputs);
    counters.add("invalid_material_ids", stats.invalid_material_ids);
    counters.add("shadow_rays_occluded", stats.shadow_rays_occluded);
    add_trace_counters(counters, "shadow", stats.shadow_trace);
}

ShadeInputs shade_inputs_of(const FrameContext& ctx, const std::string& prefix) {
    return {ctx.input(prefix + "world_position"),   ctx.input(prefix + "shading_normal"),
            ctx.input(prefix + "geometric_normal"), ctx.input(prefix + "albedo"),
            ctx.input(prefix + "material_id"),      ctx.input(prefix + "primitive_id")};
}

const Image& resumed_buffer(const FrameContext& ctx, const std::string& name, int channels,
                            const std::string& what, std::optional<glm::ivec2> size) {
    const int width = size ? size->x : ctx.settings->width;
    const int height = size ? size->y : ctx.settings->height;
    for (const Buffer& b : ctx.settings->state_buffers) {
        if (b.name != name) continue;
        const Image& image = b.image;
        if (image.width != width || image.height != height || image.channels != channels)
            throw Error("--resume: buffer '" + name + "' is " + std::to_string(image.width) + "x" +
                        std::to_string(image.height) + "x" + std::to_string(image.channels) +
                        ", the frame needs " + std::to_string(width) + "x" +
                        std::to_string(height) + "x" + std::to_string(channels));
        return image;
    }
    throw Error("frame " + std::to_string(ctx.frame) + ": " + what + " carries state from frame " +
                std::to_string(ctx.frame - 1) + ", and buffer '" + name +
                "' of that frame was not given: render from frame 0, or resume from a --dump of "
                "frame " +
                std::to_string(ctx.frame - 1) + " (`fovref render --resume DIR`)");
}

std::string shadow_note(const Scene& scene) {
    return scene.lights.empty() ? "no lights: no shadow rays traced" : "";
}

}  // namespace fovref
