// Input limits: what the loaders accept before they allocate (issue "hardening"). Bad input
// gives a clear error naming the file and the limit, in bounded time and memory, never a crash;
// a legitimate input beyond a limit can raise it with the environment variable named here.
// docs/limits.md is the table users read; `fovref --help` points to it.
#pragma once

#include <cstdint>
#include <string>

namespace fovref {

struct InputLimits {
    /// Bytes of one input file (image, scene, OBJ, MTL, ray file, tolerance file, manifest).
    /// FOVREF_MAX_FILE_BYTES; default 8 GiB (above a 16384^2 RGBA float buffer).
    std::uint64_t max_file_bytes = std::uint64_t{8} << 30;
    /// Decoded pixels of one image (PNG, PFM, EXR, raw, texture). FOVREF_MAX_IMAGE_PIXELS;
    /// default 2^28 = 16384^2, the largest screen fovref renders.
    std::uint64_t max_image_pixels = std::uint64_t{1} << 28;
    /// Texture pixels of one scene, all textures together. FOVREF_MAX_SCENE_PIXELS; default 2^28.
    std::uint64_t max_scene_texture_pixels = std::uint64_t{1} << 28;
    /// Rays in one ray file. FOVREF_MAX_RAYS; default 2^27 (4 GiB of rays).
    std::uint64_t max_rays = std::uint64_t{1} << 27;
    /// Triangles of one scene loaded from files (OBJ, glTF: a small file can instance a mesh
    /// many times). FOVREF_MAX_SCENE_TRIANGLES; default 2^26 (about 6.4 GiB of triangle data).
    std::uint64_t max_scene_triangles = std::uint64_t{1} << 26;
};

/// The limits in force: the defaults above, each replaced by its environment variable when that
/// is set (a positive integer; anything else is an error naming the variable). Read once.
const InputLimits& input_limits();

/// Throws fovref::Error "<what>: <count> <unit> exceed the limit of <limit> (<variable>; see
/// docs/limits.md)" when count > limit.
void check_limit(const std::string& what, std::uint64_t count, std::uint64_t limit,
                 const char* unit, const char* variable);

}  // namespace fovref
