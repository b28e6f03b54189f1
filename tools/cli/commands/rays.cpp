#include "tools/cli/commands/rays.h"

#include <algorithm>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/scene/scene_file.h"
#include "ref/trace/rays_file.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/progress.h"

namespace fovref {

int run_rays_trace(const RaysTraceOptions& o) {
    if (o.interleave && o.any_hit)
        throw Error("rays trace: --interleave applies to closest-hit queries, not --any-hit");
    if (o.packets && !o.any_hit)
        throw Error(
            "rays trace: --packets applies to --any-hit queries (closest hits: --interleave)");
    const Scene scene = load_cli_scene(o.scene);
    const std::vector<Ray> rays = read_rays(o.rays_path);
    Progress progress("rays trace", o.quiet);
    const Bvh bvh = build_bvh(scene.positions);
    TraceStats stats;
    const std::size_t step = std::max<std::size_t>(1, rays.size() / 100);
    if (o.any_hit) {
        std::vector<std::uint32_t> occluded(rays.size());
        std::vector<std::uint8_t> flags(rays.size());
        // Chunks for the progress bar; with --packets at least 4096 rays and a multiple of 8, so
        // that no packet is cut short at a chunk's end.
        const std::size_t chunk =
            o.packets ? (std::max<std::size_t>(step, 4096) + 7) / 8 * 8 : step;
        for (std::size_t k = 0; k < rays.size(); k += chunk) {
            const std::size_t n = std::min(chunk, rays.size() - k);
            if (o.packets)
                trace_any_packets(bvh, rays.data() + k, n, flags.data() + k, stats);
            else
                for (std::size_t i = k; i < k + n; ++i) flags[i] = trace_any(bvh, rays[i], stats);
            for (std::size_t i = k; i < k + n; ++i) occluded[i] = flags[i];
            progress.update(static_cast<double>(k) / static_cast<double>(rays.size()));
        }
        progress.finish();
        write_occlusion(o.hits_path, occluded);
    } else {
        std::vector<Hit> hits(rays.size());
        // Chunks for the progress bar; an interleaved chunk of at least 4096 rays keeps its 16
        // lanes busy (a lane drains at the chunk's end).
        const std::size_t chunk = o.interleave ? std::max<std::size_t>(step, 4096) : step;
        for (std::size_t k = 0; k < rays.size(); k += chunk) {
            const std::size_t n = std::min(chunk, rays.size() - k);
            if (o.interleave)
                trace_closest_interleaved(bvh, rays.data() + k, n, hits.data() + k, stats);
            else
                for (std::size_t i = k; i < k + n; ++i)
                    hits[i] = trace_closest(bvh, rays[i], stats);
            progress.update(static_cast<double>(k) / static_cast<double>(rays.size()));
        }
        progress.finish();
        write_hits(o.hits_path, hits);
    }
    say(o.quiet,
        "traced " + std::to_string(rays.size()) + (o.any_hit ? " occlusion" : " closest-hit") +
            " rays: " + std::to_string(stats.hits) + " hit, " +
            std::to_string(stats.nodes_visited) + " nodes visited, " +
            std::to_string(stats.triangles_tested) + " triangles tested -> " + o.hits_path);
    return exit_ok;
}

int run_rays_make(const RaysMakeOptions& o) {
    const Scene scene = load_cli_scene(o.scene);
    std::vector<Ray> rays;
    if (o.camera == (o.random_count > 0))
        throw Error(
            "rays make: give exactly one of --camera (with --width/--height) or --random N");
    if (o.camera) {
        RenderSettings check;
        check.width = o.width;
        check.height = o.height;
        validate_settings(check);
        rays = camera_rays_list(camera_at(scene, o.time), o.width, o.height);
    } else {
        rays = random_rays(scene, o.random_count, o.seed);
    }
    write_rays(o.rays_path, rays);
    say(o.quiet, "wrote " + std::to_string(rays.size()) + " rays to " + o.rays_path);
    return exit_ok;
}

}  // namespace fovref
