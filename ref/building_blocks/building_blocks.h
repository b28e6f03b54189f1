// Passes that exercise ref/core and ref/scene alone, before any renderer exists. Their goldens
// pin the deterministic math, the RNG, the Halton offsets, the camera model and the procedural
// scene generators bit-exactly across compilers, and a GPU port can check its own versions of
// these building blocks against them.
#pragma once

#include <cstdint>

#include "ref/image/image.h"
#include "ref/scene/scene.h"

namespace fovref {

/// Primary ray directions through every pixel centre (SPEC §1), 3 channels (x, y, z).
Image camera_rays(const Camera& camera, int width, int height);

/// rand_unit(frame, pixel, d) for d = 0, 1, 2 in the three channels; pixel = y * width + x.
Image rng_image(std::uint32_t frame, int width, int height);

/// The 16 Halton(2,3) points (index 1..16) as a 16x1 buffer of (x, y); scaled = Lund eq. 3.11.
Image halton_image(bool scaled);

/// Centroid splat: every triangle's centroid is projected with the camera; the pixel it lands in
/// keeps the nearest one (smallest view depth; equal depth -> lowest primitive id, SPEC §3).
/// A trivial stand-in for a renderer whose buffers pin the scene's geometry, materials and
/// textures (albedo = material albedo x texture at the centroid's uv) and the camera path.
struct SplatBuffers {
    Image depth;                  ///< view depth, 0 where nothing landed
    Image primitive;              ///< triangle index as float, -1 where nothing landed
    Image normal;                 ///< unit geometric normal
    Image albedo;                 ///< linear RGB
    std::int64_t splatted = 0;    ///< centroids that landed on screen in front of the camera
    std::int64_t behind = 0;      ///< centroids at view depth <= near
    std::int64_t off_screen = 0;  ///< centroids in front but outside the screen
};
SplatBuffers centroid_splat(const Scene& scene, const Camera& camera, int width, int height);

/// Headlight shading for a preview: albedo * (0.2 + 0.8 |n . F|); black where nothing landed.
Image headlight_shade(const Image& albedo, const Image& normal, const Image& primitive,
                      const Camera& camera);

/// The scene's triangle data as buffers, one row per triangle: positions and normals are 3
/// corners x 3 channels wide, uvs 3 x 2, the material id 1 x 1.
struct GeometryBuffers {
    Image positions;
    Image normals;
    Image uvs;
    Image material_ids;
};
GeometryBuffers scene_geometry(const Scene& scene);

}  // namespace fovref
