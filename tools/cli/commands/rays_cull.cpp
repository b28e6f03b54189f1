// `fovref rays cull SCENE OUT_DIR`: each screen tile's frustum-culled BVH2 as a GPU would load it
// (docs/frustum.md, "Exporting the culled trees"): the BVH2's triangles in leaf order, every
// tile's culled tree (culled_tree: BvhNode records, [0] where traversal starts) and a tile table;
// with --shadow the same for each tile's shadow frustum towards a point light.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <vector>

#include "ref/bvh/bvh.h"
#include "ref/core/error.h"
#include "ref/frustum/stages.h"
#include "ref/frustum/tile_frustum.h"
#include "ref/scene/scene_file.h"
#include "tools/cli/commands/rays.h"
#include "tools/cli/common/cli_common.h"
#include "tools/cli/common/output_dir.h"
#include "tools/cli/common/progress.h"

namespace fovref {

namespace {

// Little-endian 32-bit words (the formats' byte order; this tool runs on little-endian hosts).
void put(std::vector<char>& out, const void* value) {
    const char* bytes = static_cast<const char*>(value);
    out.insert(out.end(), bytes, bytes + 4);
}
void put_u32(std::vector<char>& out, std::uint32_t v) { put(out, &v); }
void put_f32(std::vector<char>& out, float v) { put(out, &v); }

void put_node(std::vector<char>& out, const BvhNode& n) {
    for (int k = 0; k < 3; ++k) put_f32(out, n.bounds_min[k]);
    put_u32(out, n.first);
    for (int k = 0; k < 3; ++k) put_f32(out, n.bounds_max[k]);
    put_u32(out, n.count);
}

void write_file(const std::string& path, const std::vector<char>& bytes) {
    std::ofstream f(path, std::ios::binary);
    f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!f) throw Error(path + ": cannot write");
}

// One set of trees (primary or shadow): the records and the tile table.
struct Trees {
    std::vector<char> nodes, tiles;
    std::uint32_t records = 0;
    std::int64_t tiles_written = 0, tiles_unculled = 0;
};

// The records one file may hold: 2^27 (4 GiB of nodes), far below uint32 offsets.
constexpr std::uint64_t max_records = std::uint64_t{1} << 27;

void add_tree(Trees& t, int tx, int ty, int x0, int y0, int x1, int y1,
              const std::vector<BvhNode>& tree) {
    if (t.records + tree.size() > max_records)
        throw Error("rays cull: the culled trees would exceed " + std::to_string(max_records) +
                    " records (4 GiB) at tile (" + std::to_string(tx) + ", " + std::to_string(ty) +
                    "): use larger tiles or a smaller screen");
    for (const std::uint32_t v : {static_cast<std::uint32_t>(tx), static_cast<std::uint32_t>(ty),
                                  static_cast<std::uint32_t>(x0), static_cast<std::uint32_t>(y0),
                                  static_cast<std::uint32_t>(x1), static_cast<std::uint32_t>(y1),
                                  t.records, static_cast<std::uint32_t>(tree.size())})
        put_u32(t.tiles, v);
    for (const BvhNode& n : tree) put_node(t.nodes, n);
    t.records += static_cast<std::uint32_t>(tree.size());
    ++t.tiles_written;
}

// The triangles in the BVH2's leaf order: 3 corners, then the primitive id.
std::vector<char> triangle_records(const Bvh& bvh) {
    std::vector<char> triangles;
    for (std::size_t k = 0; k < bvh.primitives.size(); ++k) {
        for (int c = 0; c < 3; ++c)
            for (int a = 0; a < 3; ++a) put_f32(triangles, bvh.triangle_corners[3 * k + c][a]);
        put_u32(triangles, bvh.primitives[k]);
    }
    return triangles;
}

// The shadow tree of tile [x0, x1) x [y0, y1): its pixel-centre primary hits' shadow rays
// towards `light`, culled by their frustum (none without a shadow ray; the whole tree when the
// rays spread too wide, counted).
std::vector<BvhNode> shadow_tree(const Scene& scene, const Bvh& bvh, const Camera& camera,
                                 int width, int height, int x0, int y0, int x1, int y1,
                                 glm::vec3 light, const CullOptions& options, Trees& shadow) {
    const float tan_half = tan_half_vfov(camera);
    std::vector<glm::vec3> origins;
    for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x) {
            Ray ray;
            ray.origin = camera.position;
            ray.direction =
                primary_ray_direction(camera, tan_half, width, height, static_cast<float>(x) + 0.5f,
                                      static_cast<float>(y) + 0.5f);
            TraceStats stats;
            const Hit hit = trace_closest(bvh, ray, stats);
            Ray s;
            if (hit.hit() && shadow_ray_of(scene, hit, camera.position, light, s))
                origins.push_back(s.origin);
        }
    if (origins.empty()) return {};
    TileFrustum f;
    if (shadow_frustum(light, origins, f))
        return culled_tree(bvh, cull_bvh(bvh, f, options), options);
    ++shadow.tiles_unculled;
    return culled_tree(bvh, keep_everything(bvh), options);
}

// manifest.json: the camera, the options, the counts and the layouts.
nlohmann::json cull_manifest(const RaysCullOptions& o, const Scene& scene, const Bvh& bvh,
                             const Camera& camera, const CullOptions& options, int tiles_x,
                             int tiles_y, int light, const Trees& primary, const Trees& shadow) {
    nlohmann::json m;
    m["format"] = "fovref culled trees 1 (docs/frustum.md)";
    m["scene"] = o.scene;
    m["width"] = o.width;
    m["height"] = o.height;
    m["time"] = o.time;
    m["camera"] = {{"position", {camera.position.x, camera.position.y, camera.position.z}},
                   {"right", {camera.right.x, camera.right.y, camera.right.z}},
                   {"up", {camera.up.x, camera.up.y, camera.up.z}},
                   {"forward", {camera.forward.x, camera.forward.y, camera.forward.z}},
                   {"vfov_deg", camera.vfov_deg}};
    m["tile_size"] = o.tile_size;
    m["tiles_x"] = tiles_x;
    m["tiles_y"] = tiles_y;
    m["test"] = o.test;
    m["trim"] = options.trim;
    m["entry"] = options.entry;
    m["bridge"] = options.bridge;
    m["triangles"] = bvh.primitives.size();
    m["bvh2_nodes"] = bvh.nodes.size();
    m["nodes"] = primary.records;
    m["layouts"] = {
        {"triangles.bin",
         "per triangle in the BVH2's leaf order: 9 float32 (corners p0, p1, p2), uint32 "
         "primitive id; 40 bytes"},
        {"nodes.bin",
         "BvhNode records, 32 bytes: float32 min x, y, z; uint32 first; float32 max x, y, z; "
         "uint32 count. count > 0: a leaf, triangles first .. first + count - 1 of "
         "triangles.bin; count = 0: an inner node, its children the records first and first + 1 "
         "of the same tile; an empty slot (a culled child) has count 0 and first 0xffffffff: "
         "skip it (its box is min +inf, max -inf)"},
        {"tiles.bin",
         "per tile, row by row: 8 uint32: tx, ty, x0, y0, x1, y1 (pixel edges), the tile's first "
         "record in nodes.bin, its record count (0: nothing kept); a tile's record 0 is where "
         "traversal starts and its children indices count from that record"}};
    m["byte_order"] = "little-endian";
    if (light >= 0) {
        const glm::vec3 at = scene.lights[static_cast<std::size_t>(light)].position;
        m["shadow"] = {{"light", light},
                       {"position", {at.x, at.y, at.z}},
                       {"nodes", shadow.records},
                       {"tiles_unculled", shadow.tiles_unculled},
                       {"files", "shadow_nodes.bin, shadow_tiles.bin: the layouts above"}};
    }
    return m;
}

}  // namespace

int run_rays_cull(const RaysCullOptions& o) {
    RenderSettings check;
    check.width = o.width;
    check.height = o.height;
    validate_settings(check);
    if (o.light >= 0 && !o.shadow) throw Error("rays cull: --light applies with --shadow");
    OutputDirectory out("OUT_DIR", o.out_dir);
    const Scene scene = load_cli_scene(o.scene);
    const int light =
        o.shadow ? shadow_light(scene, o.light, "rays cull: --light", "rays cull: --shadow") : -1;
    Progress progress("rays cull", o.quiet);
    const Bvh bvh = build_bvh(scene.positions);
    const Camera camera = camera_at(scene, o.time);
    CullOptions options;
    options.exact = o.test == "exact";
    options.trim = !o.no_trim;
    options.entry = !o.no_entry;
    options.bridge = !o.no_bridge;
    Trees primary, shadow;
    const int size = o.tile_size;
    const int tiles_x = (o.width + size - 1) / size, tiles_y = (o.height + size - 1) / size;
    for (int ty = 0; ty < tiles_y; ++ty) {
        for (int tx = 0; tx < tiles_x; ++tx) {
            const int x0 = tx * size, y0 = ty * size;
            const int x1 = std::min(x0 + size, o.width), y1 = std::min(y0 + size, o.height);
            const TileCulling c =
                cull_bvh(bvh, tile_frustum(camera, o.width, o.height, x0, y0, x1, y1), options);
            add_tree(primary, tx, ty, x0, y0, x1, y1, culled_tree(bvh, c, options));
            if (light >= 0)
                add_tree(shadow, tx, ty, x0, y0, x1, y1,
                         shadow_tree(scene, bvh, camera, o.width, o.height, x0, y0, x1, y1,
                                     scene.lights[static_cast<std::size_t>(light)].position,
                                     options, shadow));
        }
        progress.update(static_cast<double>(ty + 1) / tiles_y);
    }
    write_file(out.file("triangles.bin"), triangle_records(bvh));
    write_file(out.file("nodes.bin"), primary.nodes);
    write_file(out.file("tiles.bin"), primary.tiles);
    if (light >= 0) {
        write_file(out.file("shadow_nodes.bin"), shadow.nodes);
        write_file(out.file("shadow_tiles.bin"), shadow.tiles);
    }
    {
        std::ofstream f(out.file("manifest.json"));
        f << cull_manifest(o, scene, bvh, camera, options, tiles_x, tiles_y, light, primary, shadow)
                 .dump(1)
          << "\n";
        if (!f) throw Error(o.out_dir + "/manifest.json: cannot write");
    }
    out.commit();
    progress.finish();
    say(o.quiet, "wrote " + std::to_string(tiles_x * tiles_y) + " tiles' culled trees (" +
                     std::to_string(primary.records) + " records) to " + o.out_dir);
    return exit_ok;
}

}  // namespace fovref
