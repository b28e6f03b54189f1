#include "ref/frustum/stages.h"

#include <algorithm>
#include <utility>

#include "ref/core/error.h"
#include "ref/scene/camera.h"

namespace fovref {

namespace {

struct FrustumState : StageState {
    FrustumSettings settings;
    std::shared_ptr<BvhCache> bvh;
};

}  // namespace

std::vector<ParamSpec> frustum_param_specs() {
    return {{"frustum", "off",
             "tile frustum culling of the BVH (Lund §3.7; docs/frustum.md): 'off', 'lund' (his "
             "biased-box test) or 'exact' (the box's faces clipped against the tile's pyramid); "
             "writes frustum_tiles and frustum_hit_lost"},
            {"tile_size", "32", "frustum culling: tile edge in pixels (1 .. 4096)"},
            {"frustum_trim", "on", "frustum culling: remove inner nodes left without children"},
            {"frustum_entry", "on",
             "frustum culling: start at the deepest node holding every kept leaf"},
            {"frustum_bridge", "on", "frustum culling: replace nodes left with one child"}};
}

FrustumSettings parse_frustum_params(const Params& params) {
    const std::vector<ParamSpec> specs = frustum_param_specs();
    FrustumSettings s;
    const std::size_t mode = params.get_choice(specs, "frustum", {"off", "lund", "exact"});
    s.enabled = mode != 0;        // lund or exact
    s.options.exact = mode == 2;  // exact
    s.tile_size = params.get_int(specs, "tile_size", 1, 4096);
    s.options.trim = params.get_bool(specs, "frustum_trim");
    s.options.entry = params.get_bool(specs, "frustum_entry");
    s.options.bridge = params.get_bool(specs, "frustum_bridge");
    if (!s.enabled)
        for (const char* key : {"tile_size", "frustum_trim", "frustum_entry", "frustum_bridge"})
            if (params.given(key))
                throw Error(std::string("parameter '") + key +
                            "' applies to frustum culling: add frustum=lund or frustum=exact");
    return s;
}

void frustum_cull_stage(FrameContext& ctx) {
    const FrustumState& s = ctx.state<FrustumState>();
    Counters& counters = ctx.result->counters;
    const Bvh& bvh = s.bvh->get(*ctx.scene, counters);
    const int width = ctx.settings->width, height = ctx.settings->height,
              size = s.settings.tile_size;
    const int tiles_x = (width + size - 1) / size, tiles_y = (height + size - 1) / size;
    Image tiles(tiles_x, tiles_y, 6, 0.0f);
    Image lost(width, height, 1, 0.0f);
    const float tan_half = tan_half_vfov(ctx.camera);
    std::int64_t tested = 0, kept = 0, triangles = 0, hits_lost = 0;
    for (int ty = 0; ty < tiles_y; ++ty) {
        for (int tx = 0; tx < tiles_x; ++tx) {
            const int x0 = tx * size, y0 = ty * size;
            const int x1 = std::min(x0 + size, width), y1 = std::min(y0 + size, height);
            const TileFrustum f = tile_frustum(ctx.camera, width, height, x0, y0, x1, y1);
            const TileCulling c = cull_bvh(bvh, f, s.settings.options);
            float* t = &tiles.data[tiles.index(tx, ty)];
            t[0] = static_cast<float>(c.nodes_kept);
            t[1] = static_cast<float>(c.leaves_kept);
            t[2] = static_cast<float>(c.triangles_kept);
            t[3] = static_cast<float>(c.entry);
            t[4] = static_cast<float>(c.entry_depth);
            t[5] = static_cast<float>(c.nodes_tested);
            tested += c.nodes_tested;
            kept += c.nodes_kept;
            triangles += c.triangles_kept;
            // The check: every pixel-centre primary ray of the tile, culled against whole
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) {
                    Ray ray;
                    ray.origin = ctx.camera.position;
                    ray.direction = primary_ray_direction(ctx.camera, tan_half, width, height,
                                                          static_cast<float>(x) + 0.5f,
                                                          static_cast<float>(y) + 0.5f);
                    TraceStats stats;
                    if (!(trace_culled(bvh, c, ray) == trace_closest(bvh, ray, stats))) {
                        lost.at(x, y) = 1.0f;
                        ++hits_lost;
                    }
                }
        }
        ctx.report(static_cast<double>(ty + 1) / tiles_y);
    }
    counters.add("frustum_tiles", static_cast<std::int64_t>(tiles_x) * tiles_y);
    counters.add("frustum_nodes_tested", tested);
    counters.add("frustum_nodes_kept", kept);
    counters.add("frustum_triangles_kept", triangles);
    counters.add("frustum_hits_lost", hits_lost);
    ctx.note = std::to_string(tiles_x) + "x" + std::to_string(tiles_y) + " tiles of " +
               std::to_string(size) + " px, " + (s.settings.options.exact ? "exact" : "Lund's") +
               " test: " + std::to_string(kept) + " nodes kept in all, " +
               std::to_string(hits_lost) + " primary hits lost";
    ctx.output(
        "tiles", BufferKind::scalar,
        {"nodes_kept", "leaves_kept", "triangles_kept", "entry", "entry_depth", "nodes_tested"},
        std::move(tiles));
    ctx.output("hit_lost", BufferKind::id, {"lost"}, std::move(lost));
}

StageDef frustum_cull_stage_def(const FrustumSettings& settings, std::shared_ptr<BvhCache> bvh) {
    auto state = std::make_shared<FrustumState>();
    state->settings = settings;
    state->bvh = std::move(bvh);
    return {"frustum_cull",
            {},
            {{"tiles", "frustum_tiles"}, {"hit_lost", "frustum_hit_lost"}},
            frustum_cull_stage,
            state};
}

}  // namespace fovref
