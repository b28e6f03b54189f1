#include "tools/cli/bench/frustum.h"

#include <algorithm>
#include <cstdio>
#include <utility>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/frustum/stages.h"
#include "ref/frustum/tile_frustum.h"
#include "ref/log_polar/map.h"
#include "ref/log_polar/params.h"
#include "ref/scene/camera.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/bench/bench_util.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

// Every pixel-centre primary ray of the screen through `culling_of(tile)`: nodes visited,
// triangles tested, hits that differ from trace_closest's, seconds
struct TraceRun {
    TraceStats stats;
    std::int64_t lost = 0;
    double seconds = 0.0;
};

template <class Culling>
TraceRun trace_tiles(const Bvh& bvh, const Camera& camera, int width, int height, int size,
                     const std::vector<Hit>& reference, Culling culling_of) {
    TraceRun run;
    const float tan_half = tan_half_vfov(camera);
    const auto start = BenchClock::now();
    for (int y0 = 0, ty = 0; y0 < height; y0 += size, ++ty)
        for (int x0 = 0, tx = 0; x0 < width; x0 += size, ++tx) {
            const TileCulling& c = culling_of(tx, ty);
            for (int y = y0; y < std::min(y0 + size, height); ++y)
                for (int x = x0; x < std::min(x0 + size, width); ++x) {
                    Ray ray;
                    ray.origin = camera.position;
                    ray.direction = primary_ray_direction(camera, tan_half, width, height,
                                                          static_cast<float>(x) + 0.5f,
                                                          static_cast<float>(y) + 0.5f);
                    const Hit hit = trace_culled(bvh, c, ray, &run.stats);
                    run.lost += !(hit == reference[static_cast<std::size_t>(y) * width + x]);
                }
        }
    run.seconds = seconds_since(start);
    return run;
}

// cfov's log-polar buffer in tiles of size x size texels: each tile's frustum is the screen
// rectangle of its traced texels' screen points (their bounding box, widened to whole pixels),
// each traced texel's ray through the tile's culled tree
void print_buffer_tiles(const std::string& name, const Scene& scene, const Bvh& bvh,
                        const Camera& camera, int width, int height, int size) {
    const FoveatedParams params = parse_foveated_params(Params(), find_foveation_preset("cfov"));
    const LogPolarMap map = foveated_map(params, scene, camera, width, height, 0);
    const LpInverseTable table = lp_inverse_table(map);
    const float tan_half = tan_half_vfov(camera);
    const TileCulling all = keep_everything(bvh);
    for (const bool exact : {false, true}) {
        TraceStats full, culled;
        std::int64_t lost = 0, nodes = 0, tiles = 0;
        double cull_seconds = 0.0, full_seconds = 0.0, culled_seconds = 0.0;
        for (int j0 = 0; j0 < map.height; j0 += size)
            for (int i0 = 0; i0 < map.width; i0 += size) {
                std::vector<glm::vec2> points;
                for (int j = j0; j < std::min(j0 + size, map.height); ++j)
                    for (int i = i0; i < std::min(i0 + size, map.width); ++i) {
                        glm::vec2 p{0.0f};
                        if (lp_texel_status(map, table, i, j, p) == TexelStatus::traced)
                            points.push_back(p);
                    }
                if (points.empty()) continue;
                glm::vec2 lo = points[0], hi = points[0];
                for (const glm::vec2& p : points) lo = glm::min(lo, p), hi = glm::max(hi, p);
                const int x0 = std::max(0, static_cast<int>(std::floor(lo.x)));
                const int y0 = std::max(0, static_cast<int>(std::floor(lo.y)));
                const int x1 = std::min(width, static_cast<int>(std::floor(hi.x)) + 1);
                const int y1 = std::min(height, static_cast<int>(std::floor(hi.y)) + 1);
                CullOptions options;
                options.exact = exact;
                auto start = BenchClock::now();
                const TileCulling c =
                    cull_bvh(bvh, tile_frustum(camera, width, height, x0, y0, x1, y1), options);
                cull_seconds += seconds_since(start);
                ++tiles;
                nodes += c.nodes_kept;
                for (const glm::vec2& p : points) {
                    Ray ray;
                    ray.origin = camera.position;
                    ray.direction =
                        primary_ray_direction(camera, tan_half, width, height, p.x, p.y);
                    start = BenchClock::now();
                    const Hit a = trace_culled(bvh, all, ray, &full);
                    full_seconds += seconds_since(start);
                    start = BenchClock::now();
                    const Hit b = trace_culled(bvh, c, ray, &culled);
                    culled_seconds += seconds_since(start);
                    lost += !(a == b);
                }
            }
        const double rays = static_cast<double>(full.rays);
        std::printf(
            "  %-14s %5d %6s %6lld %9.1f %11lld %11s %9s %5.1f->%5.1f %10.1f %10.1f %10s %6lld\n",
            name.c_str(), size, exact ? "cfov-e" : "cfov-l", static_cast<long long>(tiles),
            1e3 * cull_seconds, static_cast<long long>(nodes), "-", "-",
            static_cast<double>(full.nodes_visited) / rays,
            static_cast<double>(culled.nodes_visited) / rays, 1e3 * full_seconds,
            1e3 * culled_seconds, "-", static_cast<long long>(lost));
    }
}

// The shadow rays of every primary hit towards the scene's first point light (shade_direct's
// rays, shadow_ray_of), per screen tile of size pixels: each tile's shadow frustum (apex the
// light) culled by Lund's or the exact test, every ray's occlusion through the culled tree
// against the BVH4 trace_any the renderer uses; the unculled BVH2 as the baseline.
void print_shadow_tiles(const std::string& name, const Scene& scene, const Bvh& bvh,
                        const Camera& camera, int width, int height, int size,
                        const std::vector<Hit>& reference) {
    int light = -1;
    for (std::size_t l = 0; l < scene.lights.size() && light < 0; ++l)
        if (scene.lights[l].type == Light::Type::point) light = static_cast<int>(l);
    if (light < 0) return;  // no point light: no row
    const glm::vec3 at = scene.lights[static_cast<std::size_t>(light)].position;
    const TileCulling all = keep_everything(bvh);
    for (const bool exact : {false, true}) {
        TraceStats full, culled, any;
        std::int64_t lost = 0, nodes = 0, tiles = 0;
        double cull_seconds = 0.0, full_seconds = 0.0, culled_seconds = 0.0, any_seconds = 0.0;
        for (int y0 = 0; y0 < height; y0 += size)
            for (int x0 = 0; x0 < width; x0 += size) {
                std::vector<Ray> rays;
                std::vector<glm::vec3> origins;
                for (int y = y0; y < std::min(y0 + size, height); ++y)
                    for (int x = x0; x < std::min(x0 + size, width); ++x) {
                        const Hit& hit = reference[static_cast<std::size_t>(y) * width + x];
                        Ray ray;
                        if (hit.hit() && shadow_ray_of(scene, hit, camera.position, at, ray)) {
                            rays.push_back(ray);
                            origins.push_back(ray.origin);
                        }
                    }
                if (rays.empty()) continue;
                CullOptions options;
                options.exact = exact;
                auto start = BenchClock::now();
                TileFrustum f;
                const TileCulling c = shadow_frustum(at, origins, f) ? cull_bvh(bvh, f, options)
                                                                     : keep_everything(bvh);
                cull_seconds += seconds_since(start);
                ++tiles;
                nodes += c.nodes_kept;
                for (const Ray& ray : rays) {
                    start = BenchClock::now();
                    const bool occluded = trace_any(bvh, ray, any);
                    any_seconds += seconds_since(start);
                    start = BenchClock::now();
                    (void)trace_culled(bvh, all, ray, &full);
                    full_seconds += seconds_since(start);
                    start = BenchClock::now();
                    lost += trace_culled(bvh, c, ray, &culled).hit() != occluded;
                    culled_seconds += seconds_since(start);
                }
            }
        const double rays = static_cast<double>(full.rays);
        std::printf(
            "  %-14s %5d %6s %6lld %9.1f %11lld %11s %9s %5.1f->%5.1f %10.1f %10.1f %10.1f "
            "%6lld\n",
            name.c_str(), size, exact ? "shad-e" : "shad-l", static_cast<long long>(tiles),
            1e3 * cull_seconds, static_cast<long long>(nodes), "-", "-",
            static_cast<double>(full.nodes_visited) / rays,
            static_cast<double>(culled.nodes_visited) / rays, 1e3 * full_seconds,
            1e3 * culled_seconds, 1e3 * any_seconds, static_cast<long long>(lost));
    }
}

// Every pixel-centre primary ray through the BVH4 trace_closest the renderer uses: the hits
// the culled traces must reproduce; returns the seconds it took.
double reference_hits(const Bvh& bvh, const Camera& camera, int width, int height,
                      std::vector<Hit>& reference) {
    const float tan_half = tan_half_vfov(camera);
    reference.assign(static_cast<std::size_t>(width) * height, Hit{});
    TraceStats stats;
    const auto start = BenchClock::now();
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            Ray ray;
            ray.origin = camera.position;
            ray.direction =
                primary_ray_direction(camera, tan_half, width, height, static_cast<float>(x) + 0.5f,
                                      static_cast<float>(y) + 0.5f);
            reference[static_cast<std::size_t>(y) * width + x] = trace_closest(bvh, ray, stats);
        }
    return seconds_since(start);
}

// One table row: the screen in tiles of size pixels, each tile's BVH2 culled with `options`
// (`label` names them), then every tile's rays through its culled tree.
void print_culled_row(const std::string& name, const Bvh& bvh, const Camera& camera, int width,
                      int height, int size, const CullOptions& options, const char* label,
                      const std::vector<Hit>& reference, double rays) {
    const int tiles_x = (width + size - 1) / size, tiles_y = (height + size - 1) / size;
    std::vector<TileCulling> cullings;
    const auto start = BenchClock::now();
    for (int ty = 0; ty < tiles_y; ++ty)
        for (int tx = 0; tx < tiles_x; ++tx)
            cullings.push_back(cull_bvh(
                bvh,
                tile_frustum(camera, width, height, tx * size, ty * size,
                             std::min(tx * size + size, width), std::min(ty * size + size, height)),
                options));
    const double cull_seconds = seconds_since(start);
    std::int64_t nodes = 0, triangles = 0, bytes = 0;
    for (const TileCulling& c : cullings) {
        nodes += c.nodes_kept;
        triangles += c.triangles_kept;
        bytes += c.bytes();
    }
    const TraceRun culled = trace_tiles(
        bvh, camera, width, height, size, reference, [&](int tx, int ty) -> const TileCulling& {
            return cullings[static_cast<std::size_t>(ty * tiles_x + tx)];
        });
    std::printf("  %-14s %5d %6s %6d %9.1f %11lld %11lld %9.2f %11.1f %10s %10.1f %10s %6lld\n",
                name.c_str(), size, label, tiles_x * tiles_y, 1e3 * cull_seconds,
                static_cast<long long>(nodes), static_cast<long long>(triangles),
                static_cast<double>(bytes) / 1048576.0,
                static_cast<double>(culled.stats.nodes_visited) / rays, "-", 1e3 * culled.seconds,
                "-", static_cast<long long>(culled.lost));
    std::fflush(stdout);
}

}  // namespace

int run_bench_frustum(const BenchFrustumOptions& o) {
    std::printf(
        "fovref bench frustum: Lund's tile frustum culling on the CPU, %dx%d, one thread; every "
        "pixel-centre primary ray through its tile's culled BVH2 vs the same BVH2 unculled "
        "(and the BVH4 trace_closest the renderer uses)\n",
        o.width, o.height);
    std::printf("  %-14s %5s %6s %6s %9s %11s %11s %9s %11s %10s %10s %10s %6s\n", "scene", "tile",
                "test", "tiles", "cull ms", "nodes kept", "tris kept", "MB", "visits/ray",
                "BVH2 ms", "culled ms", "BVH4 ms", "lost");
    Progress progress("bench frustum", o.quiet);
    for (std::size_t si = 0; si < o.scenes.size(); ++si) {
        const Scene scene = load_scene(o.scenes[si]);
        const Bvh bvh = build_bvh(scene.positions);
        const Camera camera = camera_at(scene, 0.0f);
        std::vector<Hit> reference;
        const double bvh4_seconds = reference_hits(bvh, camera, o.width, o.height, reference);
        const TileCulling all = keep_everything(bvh);
        const TraceRun unculled = trace_tiles(bvh, camera, o.width, o.height, o.width, reference,
                                              [&](int, int) -> const TileCulling& { return all; });
        const double rays = static_cast<double>(o.width) * o.height;
        std::printf(
            "  %-14s %5s %6s %6d %9s %11lld %11lld %9.2f %11.1f %10.1f %10s %10.1f %6lld\n",
            o.scenes[si].c_str(), "-", "none", 1, "-", static_cast<long long>(all.nodes_kept),
            static_cast<long long>(all.triangles_kept),
            static_cast<double>(all.bytes()) / 1048576.0,
            static_cast<double>(unculled.stats.nodes_visited) / rays, 1e3 * unculled.seconds, "-",
            1e3 * bvh4_seconds, static_cast<long long>(unculled.lost));
        // Lund's test, the exact one, and Lund's with each of his optimisations off
        CullOptions exact, no_trim, no_entry, no_bridge;
        exact.exact = true;
        no_trim.trim = false;
        no_entry.entry = false;
        no_bridge.bridge = false;
        const std::pair<const char*, CullOptions> variants[] = {{"lund", CullOptions{}},
                                                                {"exact", exact},
                                                                {"l-trim", no_trim},
                                                                {"l-entr", no_entry},
                                                                {"l-brdg", no_bridge}};
        for (const int size : o.tile_sizes)
            for (const auto& [label, options] : variants)
                print_culled_row(o.scenes[si], bvh, camera, o.width, o.height, size, options, label,
                                 reference, rays);
        for (const int size : o.tile_sizes)
            print_buffer_tiles(o.scenes[si], scene, bvh, camera, o.width, o.height, size);
        for (const int size : o.tile_sizes)
            print_shadow_tiles(o.scenes[si], scene, bvh, camera, o.width, o.height, size,
                               reference);
        progress.update(static_cast<double>(si + 1) / static_cast<double>(o.scenes.size()));
    }
    progress.finish();
    std::printf(
        "  nodes kept and MB sum the tiles' culled trees (32 bytes a node); visits/ray are BVH2 "
        "nodes whose box the ray's segment meets; 'lost' counts rays whose closest hit differs "
        "from trace_closest's. l-trim / l-entr / l-brdg rows: Lund's test with trimming, the "
        "entry point or bridging off (the others on). cfov-l / cfov-e rows: cfov's log-polar "
        "buffer (the default preset) "
        "in tiles of that many texels, each tile's frustum the screen rectangle of its traced "
        "texels' points, Lund's or the exact test, visits/ray unculled -> culled and the BVH2 "
        "times over the traced texels' rays. shad-l / shad-e rows (scenes with a point light): "
        "the shadow rays of every primary hit towards the first point light, each screen tile's "
        "shadow frustum (apex the light) culled by Lund's or the exact test, visits/ray "
        "unculled -> culled (closest-hit BVH2 traversals), the BVH4 column trace_any's time, "
        "'lost' the rays whose occlusion differs from trace_any's. Lund (Tables 5.5-5.6, DXR): "
        "14.48 ms with the normal "
        "structure, 14.55 ms with his TLAS tracer (Titan V): no gain.\n");
    return 0;
}

}  // namespace fovref
