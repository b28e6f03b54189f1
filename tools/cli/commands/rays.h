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
    std::string scene;      ///< procedural scene name or scene file
    std::string rays_path;  ///< input: 8 x binary32 per ray
    std::string hits_path;  ///< output: 16-byte hit records, or 4-byte occlusion flags
    bool any_hit = false;   ///< occlusion queries instead of closest hits
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

/// Registers the options of `rays trace` and `rays make` on their subcommands.
void add_rays_trace_options(CLI::App& command, RaysTraceOptions& options);
void add_rays_make_options(CLI::App& command, RaysMakeOptions& options);

/// Each returns 0; they throw fovref::Error for usage and input errors (the CLI exits 2).
int run_rays_trace(const RaysTraceOptions& options);
int run_rays_make(const RaysMakeOptions& options);

}  // namespace fovref
