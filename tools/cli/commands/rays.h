// `fovref rays trace|make`: the closest hits (or, with --any-hit, the occlusion) of every ray in
// a ray file, for checking a GPU traversal, and ray files of a camera's primary rays or of
// fixed-seed random rays. docs/rays.md describes the file formats.
#pragma once

#include <cstdint>
#include <string>

namespace CLI {
class App;
}

namespace fovref {

struct RaysTraceOptions {
    std::string scene;        ///< procedural scene name or scene file
    std::string rays_path;    ///< input: 8 x binary32 per ray
    std::string hits_path;    ///< output: 16-byte hit records, or 4-byte occlusion flags
    bool any_hit = false;     ///< occlusion queries instead of closest hits
    bool interleave = false;  ///< closest hits by trace_closest_interleaved (docs/bvh.md)
    bool packets = false;     ///< occlusion by trace_any_packets (docs/bvh.md)
    bool quiet = false;
};

struct RaysMakeOptions {
    std::string scene;               ///< procedural scene name or scene file
    std::string rays_path;           ///< output ray file
    bool camera = false;             ///< primary rays through every pixel centre ...
    int width = 320, height = 180;   ///< ... of this screen
    float time = 0.0f;               ///< ... at this camera-path time
    std::uint32_t random_count = 0;  ///< or this many random rays (0: none)
    std::uint32_t seed = 1;          ///< seed of the random rays (the rand() frame)
    bool quiet = false;
};

struct RaysCullOptions {
    std::string scene;    ///< procedural scene name or scene file
    std::string out_dir;  ///< manifest.json, triangles.bin, nodes.bin, tiles.bin (+ shadow_*)
    int width = 1280, height = 720;
    float time = 0.0f;  ///< camera-path time
    int tile_size = 32;
    std::string test = "lund";  ///< lund or exact
    bool no_trim = false, no_entry = false, no_bridge = false;
    bool shadow = false;  ///< also each tile's shadow frustum towards a point light
    int light = -1;       ///< that light (-1: the first point light)
    bool quiet = false;
};

/// Registers the options of `rays trace` and `rays make` on their subcommands.
void add_rays_trace_options(CLI::App& command, RaysTraceOptions& options);
void add_rays_make_options(CLI::App& command, RaysMakeOptions& options);
/// `rays cull`: each screen tile's culled BVH2 (tile frustum culling, docs/frustum.md), written
/// for a GPU to load and traverse or to diff its own culling pass against.
void add_rays_cull_options(CLI::App& command, RaysCullOptions& options);

/// Each returns 0; they throw fovref::Error for usage and input errors (the CLI exits 2).
int run_rays_trace(const RaysTraceOptions& options);
int run_rays_make(const RaysMakeOptions& options);
int run_rays_cull(const RaysCullOptions& options);

}  // namespace fovref
