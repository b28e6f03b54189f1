#include "ref/frustum/stages.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "ref/core/error.h"
#include "ref/scene/camera.h"
#include "ref/scene/surface.h"
#include "ref/trace/direct_light.h"

namespace fovref {

namespace {

struct FrustumState : StageState {
    FrustumSettings settings;
    std::shared_ptr<BvhCache> bvh;
    std::string prefix;
    std::function<FrustumRegion(const FrameContext&)> region;
};

void write_tile(Image& tiles, int tx, int ty, const TileCulling& c) {
    float* t = &tiles.data[tiles.index(tx, ty)];
    t[0] = static_cast<float>(c.nodes_kept);
    t[1] = static_cast<float>(c.leaves_kept);
    t[2] = static_cast<float>(c.triangles_kept);
    t[3] = static_cast<float>(c.entry);
    t[4] = static_cast<float>(c.entry_depth);
    t[5] = static_cast<float>(c.nodes_tested);
}

const std::vector<std::string> tile_channels = {"nodes_kept", "leaves_kept", "triangles_kept",
                                                "entry",      "entry_depth", "nodes_tested"};

// What the stage writes and counts over a frame.
struct FrustumFrame {
    Image tiles, lost, shadow_tiles, shadow_lost;
    std::int64_t tested = 0, kept = 0, triangles = 0, hits_lost = 0;
    TraceStats culled, whole;  ///< the checked rays through the culled trees / the whole BVH2
    TileCulling all;           ///< the whole BVH2 (keep_everything)
    std::int64_t shadow_rays = 0, shadow_unculled = 0, shadow_kept = 0, shadow_lost_count = 0;
};

std::string visits_per_ray(const TraceStats& stats) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f",
                  stats.rays > 0
                      ? static_cast<double>(stats.nodes_visited) / static_cast<double>(stats.rays)
                      : 0.0);
    return text;
}

// A shadow ray and the pixel (of the region) it belongs to.
struct ShadowRay {
    Ray ray;
    glm::ivec2 pixel;
};

// Tile (tx, ty) of the region: its culled tree, every traced pixel-centre primary ray through it
// against the whole BVH, and (light >= 0) the shadow rays of the tile's hits collected.
void cull_primary_tile(const FrameContext& ctx, const Bvh& bvh, const FrustumSettings& settings,
                       const FrustumRegion& region, int tx, int ty, int light, FrustumFrame& out,
                       std::vector<ShadowRay>& shadows) {
    const int width = ctx.settings->width, height = ctx.settings->height, size = settings.tile_size;
    // the tile in the region's pixels, and on the screen
    const int x0 = tx * size, y0 = ty * size;
    const int x1 = std::min(x0 + size, region.width), y1 = std::min(y0 + size, region.height);
    const TileFrustum f = tile_frustum(ctx.camera, width, height, region.x0 + x0, region.y0 + y0,
                                       region.x0 + x1, region.y0 + y1);
    const TileCulling c = cull_bvh(bvh, f, settings.options);
    write_tile(out.tiles, tx, ty, c);
    out.tested += c.nodes_tested;
    out.kept += c.nodes_kept;
    out.triangles += c.triangles_kept;
    const float tan_half = tan_half_vfov(ctx.camera);
    shadows.clear();
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            const glm::vec2 centre{static_cast<float>(region.x0 + x) + 0.5f,
                                   static_cast<float>(region.y0 + y) + 0.5f};
            if (region.traced && !region.traced(centre)) continue;
            Ray ray;
            ray.origin = ctx.camera.position;
            ray.direction =
                primary_ray_direction(ctx.camera, tan_half, width, height, centre.x, centre.y);
            TraceStats stats;
            const Hit whole = trace_closest(bvh, ray, stats);
            (void)trace_culled(bvh, out.all, ray, &out.whole);
            if (!(trace_culled(bvh, c, ray, &out.culled) == whole)) {
                out.lost.at(x, y) = 1.0f;
                ++out.hits_lost;
            }
            ShadowRay shadow{{}, {x, y}};
            if (light >= 0 && whole.hit() &&
                shadow_ray_of(*ctx.scene, whole, ctx.camera.position,
                              ctx.scene->lights[static_cast<std::size_t>(light)].position,
                              shadow.ray))
                shadows.push_back(shadow);
        }
}

// Tile (tx, ty)'s shadow rays through the culled tree of their frustum (apex the light), against
// trace_any over the whole BVH. No shadow ray: no frustum.
void cull_shadow_tile(const Bvh& bvh, const CullOptions& options, glm::vec3 light, int tx, int ty,
                      const std::vector<ShadowRay>& shadows, FrustumFrame& out) {
    if (shadows.empty()) return;
    std::vector<glm::vec3> origins;
    for (const ShadowRay& s : shadows) origins.push_back(s.ray.origin);
    TileFrustum f;
    const bool culled = shadow_frustum(light, origins, f);
    const TileCulling c = culled ? cull_bvh(bvh, f, options) : keep_everything(bvh);
    write_tile(out.shadow_tiles, tx, ty, c);
    out.shadow_unculled += culled ? 0 : 1;
    out.shadow_kept += c.nodes_kept;
    for (const ShadowRay& s : shadows) {
        TraceStats stats;
        const bool whole = trace_any(bvh, s.ray, stats);
        ++out.shadow_rays;
        if (trace_culled(bvh, c, s.ray).hit() != whole) {
            out.shadow_lost.at(s.pixel.x, s.pixel.y) = 1.0f;
            ++out.shadow_lost_count;
        }
    }
}

}  // namespace

int shadow_light(const Scene& scene, int light, const std::string& light_option,
                 const std::string& shadow_option) {
    if (light >= 0) {
        if (light >= static_cast<int>(scene.lights.size()) ||
            scene.lights[static_cast<std::size_t>(light)].type != Light::Type::point)
            throw Error(light_option + ": light " + std::to_string(light) +
                        " is not a point light of the scene (it has " +
                        std::to_string(scene.lights.size()) + " lights)");
        return light;
    }
    for (std::size_t l = 0; l < scene.lights.size(); ++l)
        if (scene.lights[l].type == Light::Type::point) return static_cast<int>(l);
    throw Error(shadow_option + ": the scene has no point light (shadow frusta need one)");
}

bool shadow_ray_of(const Scene& scene, const Hit& hit, glm::vec3 eye, glm::vec3 light, Ray& ray) {
    const SurfacePoint s = surface_at(scene, hit.primitive, hit.u, hit.v);
    const bool front = glm::dot(s.geometric_normal, eye - s.position) >= 0.0f;
    const glm::vec3 n_g = front ? s.geometric_normal : -s.geometric_normal;
    const glm::vec3 to_light = light - s.position;
    if (!(glm::dot(to_light, to_light) > min_light_distance2) || glm::dot(n_g, to_light) <= 0.0f)
        return false;
    ray.origin = s.position + n_g * (shadow_epsilon_scale * scene.scene_scale);
    ray.direction = light - ray.origin;
    ray.t_min = 0.0f;
    ray.t_max = shadow_t_max;
    return true;
}

std::vector<ParamSpec> frustum_param_specs() {
    return {{"frustum", "off",
             "tile frustum culling of the BVH (Lund §3.7; docs/frustum.md): 'off', 'lund' (his "
             "biased-box test) or 'exact' (the box's faces clipped against the tile's pyramid); "
             "writes frustum_tiles and frustum_hit_lost"},
            {"tile_size", "32", "frustum culling: tile edge in pixels (1 .. 4096)"},
            {"frustum_trim", "on", "frustum culling: remove inner nodes left without children"},
            {"frustum_entry", "on",
             "frustum culling: start at the deepest node holding every kept leaf"},
            {"frustum_bridge", "on", "frustum culling: replace nodes left with one child"},
            {"frustum_shadow", "off",
             "frustum culling: 'on' also culls each tile's shadow rays towards a point light "
             "with a frustum whose apex is the light (frustum_shadow_tiles, "
             "frustum_shadow_lost)"},
            {"frustum_light", "-1",
             "frustum_shadow: the index of the point light in the scene's lights (-1: the first "
             "point light)"}};
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
    s.shadow = params.get_bool(specs, "frustum_shadow");
    s.light = params.get_int(specs, "frustum_light", -1, 1 << 20);
    if (s.light >= 0 && !s.shadow && params.given("frustum_light"))
        throw Error("parameter 'frustum_light' applies to frustum_shadow=on");
    if (!s.enabled)
        for (const char* key : {"tile_size", "frustum_trim", "frustum_entry", "frustum_bridge",
                                "frustum_shadow", "frustum_light"})
            if (params.given(key))
                throw Error(std::string("parameter '") + key +
                            "' applies to frustum culling: add frustum=lund or frustum=exact");
    return s;
}

void frustum_cull_stage(FrameContext& ctx) {
    const FrustumState& s = ctx.state<FrustumState>();
    Counters& counters = ctx.result->counters;
    const Bvh& bvh = s.bvh->get(*ctx.scene, counters);
    const int size = s.settings.tile_size;
    const FrustumRegion region =
        s.region ? s.region(ctx)
                 : FrustumRegion{0, 0, ctx.settings->width, ctx.settings->height, {}};
    const int tiles_x = (region.width + size - 1) / size,
              tiles_y = (region.height + size - 1) / size;
    const int light = s.settings.shadow
                          ? shadow_light(*ctx.scene, s.settings.light, "parameter 'frustum_light'",
                                         "parameter 'frustum_shadow'")
                          : -1;
    FrustumFrame out;
    out.all = keep_everything(bvh);
    out.tiles = Image(tiles_x, tiles_y, 6, 0.0f);
    out.lost = Image(region.width, region.height, 1, 0.0f);
    if (light >= 0) {
        out.shadow_tiles = Image(tiles_x, tiles_y, 6, 0.0f);
        out.shadow_lost = Image(region.width, region.height, 1, 0.0f);
    }
    std::vector<ShadowRay> shadows;
    for (int ty = 0; ty < tiles_y; ++ty) {
        for (int tx = 0; tx < tiles_x; ++tx) {
            cull_primary_tile(ctx, bvh, s.settings, region, tx, ty, light, out, shadows);
            if (light >= 0)
                cull_shadow_tile(bvh, s.settings.options,
                                 ctx.scene->lights[static_cast<std::size_t>(light)].position, tx,
                                 ty, shadows, out);
        }
        ctx.report(static_cast<double>(ty + 1) / tiles_y);
    }
    const std::string& p = s.prefix;
    counters.add(p + "tiles", static_cast<std::int64_t>(tiles_x) * tiles_y);
    counters.add(p + "nodes_tested", out.tested);
    counters.add(p + "nodes_kept", out.kept);
    counters.add(p + "triangles_kept", out.triangles);
    counters.add(p + "hits_lost", out.hits_lost);
    counters.add(p + "rays", out.culled.rays);
    counters.add(p + "visits_culled", out.culled.nodes_visited);
    counters.add(p + "visits_unculled", out.whole.nodes_visited);
    ctx.note = std::to_string(tiles_x) + "x" + std::to_string(tiles_y) + " tiles of " +
               std::to_string(size) + " px, " + (s.settings.options.exact ? "exact" : "Lund's") +
               " test: " + std::to_string(out.kept) + " nodes kept in all, " +
               std::to_string(out.hits_lost) + " primary hits lost, BVH2 nodes visited per ray " +
               visits_per_ray(out.whole) + " unculled, " + visits_per_ray(out.culled) + " culled";
    ctx.output("tiles", BufferKind::scalar, tile_channels, std::move(out.tiles));
    ctx.output("hit_lost", BufferKind::id, {"lost"}, std::move(out.lost));
    if (light < 0) return;
    counters.add(p + "shadow_rays", out.shadow_rays);
    counters.add(p + "shadow_tiles_unculled", out.shadow_unculled);
    counters.add(p + "shadow_nodes_kept", out.shadow_kept);
    counters.add(p + "shadow_lost", out.shadow_lost_count);
    ctx.note += "; light " + std::to_string(light) +
                "'s shadow frusta: " + std::to_string(out.shadow_kept) + " nodes kept, " +
                std::to_string(out.shadow_rays) + " shadow rays, " +
                std::to_string(out.shadow_lost_count) + " occlusions lost";
    ctx.output("shadow_tiles", BufferKind::scalar, tile_channels, std::move(out.shadow_tiles));
    ctx.output("shadow_lost", BufferKind::id, {"lost"}, std::move(out.shadow_lost));
}

StageDef frustum_cull_stage_def(const FrustumSettings& settings, std::shared_ptr<BvhCache> bvh,
                                const std::string& prefix,
                                std::function<FrustumRegion(const FrameContext&)> region) {
    auto state = std::make_shared<FrustumState>();
    state->settings = settings;
    state->bvh = std::move(bvh);
    state->prefix = prefix;
    state->region = std::move(region);
    std::vector<Port> outputs = {{"tiles", prefix + "tiles"}, {"hit_lost", prefix + "hit_lost"}};
    if (settings.shadow) {
        outputs.emplace_back("shadow_tiles", prefix + "shadow_tiles");
        outputs.emplace_back("shadow_lost", prefix + "shadow_lost");
    }
    return {prefix + "cull", {}, std::move(outputs), frustum_cull_stage, state};
}

}  // namespace fovref
