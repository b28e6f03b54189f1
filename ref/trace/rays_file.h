// Ray and hit files, so a GPU implementation's traversal can be checked against the reference
// (docs/rays.md). All files are headerless arrays of little-endian 32-bit records:
//   rays:      per ray 8 x binary32: origin x y z, direction x y z, t_min, t_max   (32 bytes)
//   hits:      per ray t (binary32), primitive (int32), u, v (binary32)          (16 bytes)
//              a miss is t = -1, primitive = -1, u = v = 0
//   occlusion: per ray one uint32: 1 = something in (t_min, t_max], 0 = nothing    (4 bytes)
// A file whose size is not a whole number of records is rejected as truncated; a ray with a
// NaN or infinite field (t_max may be +inf) or a zero direction is rejected with its index.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "ref/bvh/ray.h"
#include "ref/scene/scene.h"

namespace fovref {

std::vector<Ray> read_rays(const std::string& path);
void write_rays(const std::string& path, const std::vector<Ray>& rays);
std::vector<Hit> read_hits(const std::string& path);
void write_hits(const std::string& path, const std::vector<Hit>& hits);
void write_occlusion(const std::string& path, const std::vector<std::uint32_t>& occluded);
std::vector<std::uint32_t> read_occlusion(const std::string& path);

/// Primary rays through every pixel centre, row-major from the top-left (SPEC §1).
std::vector<Ray> camera_rays_list(const Camera& camera, int width, int height);

/// `count` rays with origins uniform in the scene bounds and directions uniform on the sphere,
/// from rand(seed, ray index, 0..4) (SPEC §0); t in (0, inf).
std::vector<Ray> random_rays(const Scene& scene, std::uint32_t count, std::uint32_t seed);

}  // namespace fovref
